/// @file MpiTeam.h
/// @brief The ranks of an mpirun as a BrickTeam. Kept in a library of its own
/// (gvr_mpi_team) so that only what runs under mpirun links MPI.
#pragma once

#include "workflow/BrickTeam.h"

#include <functional>
#include <memory>

namespace gvr {

/// Says, in the caller's terms, why rank @a rank of @a size is about to end the team.
using TeamErrorReporter = std::function<void(int rank, int size, const std::exception& error)>;

class MpiTeam final : public BrickTeam {
public:
    /// Joins MPI; call it only in a process that mpirun started.
    explicit MpiTeam(TeamErrorReporter report);
    ~MpiTeam() override;
    MpiTeam(const MpiTeam&) = delete;
    MpiTeam& operator=(const MpiTeam&) = delete;

    int rank() const override { return mRank; }
    int size() const override { return mSize; }
    std::size_t threadsPerRank() const override;
    std::vector<BrickOutcome> gather(std::vector<BrickOutcome> mine, const std::vector<int>& owners) const override;
    void broadcast(std::string& bytes) const override;
    /// Reports @a error, then ends every rank with exit code 2.
    void abortUnlessAlone(const std::exception& error) const override;

private:
    TeamErrorReporter mReport;
    int mRank = 0, mSize = 1, mLocalSize = 1;
};

/// An MpiTeam when mpirun started this process (OpenMPI and PMIx set the rank in
/// the environment), else a SoloTeam that never touches MPI.
std::unique_ptr<BrickTeam> teamOfThisLaunch(TeamErrorReporter report);

}  // namespace gvr
