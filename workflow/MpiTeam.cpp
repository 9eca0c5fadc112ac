#include "workflow/MpiTeam.h"

#include <mpi.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <climits>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>

namespace gvr {

namespace {

bool launchedByMpirun() { return std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMIX_RANK"); }

int localSizeFromEnvironment() {
    const char* local = std::getenv("OMPI_COMM_WORLD_LOCAL_SIZE");
    return local ? std::max(1, std::atoi(local)) : 1;
}

/// Each brick is two messages, its header then its bytes. A rank sends its bricks in
/// ascending order and rank 0 receives them in that order, and MPI never lets one
/// message overtake another between the same two ranks with the same tag, so two
/// tags serve any number of bricks.
constexpr int kHeaderTag = 0, kBytesTag = 1;

void send(const BrickOutcome& outcome) {
    if (outcome.bytes.size() > std::size_t(INT_MAX)) {
        throw std::runtime_error("brick " + std::to_string(outcome.brick) + ": its part of " +
                                 std::to_string(outcome.bytes.size()) + " bytes is too large for one MPI message");
    }
    const std::uint64_t header[2] = {outcome.ok ? 1u : 0u, outcome.bytes.size()};
    MPI_Send(header, 2, MPI_UINT64_T, 0, kHeaderTag, MPI_COMM_WORLD);
    MPI_Send(outcome.bytes.data(), int(outcome.bytes.size()), MPI_CHAR, 0, kBytesTag, MPI_COMM_WORLD);
}

BrickOutcome receive(std::size_t brick, int from) {
    std::uint64_t header[2] = {0, 0};
    MPI_Recv(header, 2, MPI_UINT64_T, from, kHeaderTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    BrickOutcome outcome{brick, from, header[0] == 1, std::string(header[1], '\0')};
    MPI_Recv(outcome.bytes.data(), int(header[1]), MPI_CHAR, from, kBytesTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    return outcome;
}

}  // namespace

MpiTeam::MpiTeam(TeamErrorReporter report) : mReport(std::move(report)) {
    MPI_Init(nullptr, nullptr);
    MPI_Comm_rank(MPI_COMM_WORLD, &mRank);
    MPI_Comm_size(MPI_COMM_WORLD, &mSize);
    mLocalSize = localSizeFromEnvironment();
}

MpiTeam::~MpiTeam() { MPI_Finalize(); }

std::vector<BrickOutcome> MpiTeam::gather(std::vector<BrickOutcome> mine, const std::vector<int>& owners) const {
    std::sort(mine.begin(), mine.end(), [](const BrickOutcome& a, const BrickOutcome& b) { return a.brick < b.brick; });
    if (!isRoot()) {
        for (const BrickOutcome& outcome : mine) send(outcome);
        return {};
    }
    std::vector<BrickOutcome> all(owners.size());
    for (BrickOutcome& outcome : mine) all[outcome.brick] = std::move(outcome);
    for (std::size_t b = 0; b < owners.size(); ++b) {
        if (owners[b] != 0) all[b] = receive(b, owners[b]);
    }
    return all;
}

void MpiTeam::broadcast(std::string& bytes) const {
    std::uint64_t size = bytes.size();
    MPI_Bcast(&size, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD);
    if (size > std::uint64_t(INT_MAX))
        throw std::runtime_error("an asset of " + std::to_string(size) + " bytes is too large for one MPI message");
    bytes.resize(size);
    MPI_Bcast(bytes.data(), int(size), MPI_CHAR, 0, MPI_COMM_WORLD);
}

void MpiTeam::abortUnlessAlone(const std::exception& error) const {
    if (mSize == 1) return;
    if (mReport) mReport(mRank, mSize, error);
    MPI_Abort(MPI_COMM_WORLD, 2);
    std::exit(2);  // MPI_Abort does not return; this tells the compiler so
}

std::size_t MpiTeam::threadsPerRank() const {
    const int cores = tbb::this_task_arena::max_concurrency();
    return std::size_t(std::max(1, cores / mLocalSize));
}

std::unique_ptr<BrickTeam> teamOfThisLaunch(TeamErrorReporter report) {
    if (!launchedByMpirun()) return std::make_unique<SoloTeam>();
    return std::make_unique<MpiTeam>(std::move(report));
}

}  // namespace gvr
