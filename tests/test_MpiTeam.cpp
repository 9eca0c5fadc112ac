#include "tests/ScopedEnvironment.h"
#include "workflow/MpiTeam.h"

#include <gtest/gtest.h>

namespace gvr {
namespace {

/// MPI itself is left to mpi_bricks, which starts real ranks under mpirun: MPI can
/// start only once in a process, and never again after it ends.
TEST(MpiTeam, OutsideMpirunTheTeamIsThisProcessAloneAndMpiIsLeftAlone) {
    const test::ScopedEnvironment noOpenMpi("OMPI_COMM_WORLD_SIZE", std::nullopt), noPmix("PMIX_RANK", std::nullopt);
    bool reported = false;
    const std::unique_ptr<BrickTeam> team = teamOfThisLaunch([&](int, int, const std::exception&) { reported = true; });
    ASSERT_NE(team, nullptr);
    EXPECT_NE(dynamic_cast<const SoloTeam*>(team.get()), nullptr);
    EXPECT_EQ(team->size(), 1);
    EXPECT_TRUE(team->isRoot());
    team->abortUnlessAlone(std::runtime_error("alone, the caller rethrows"));
    EXPECT_FALSE(reported);
}

}  // namespace
}  // namespace gvr
