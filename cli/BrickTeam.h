/// @file BrickTeam.h
/// @brief The processes that share a bricked fit: the ranks of an mpirun, or this
/// process alone. Each rank fits its share of the bricks; rank 0 gathers every
/// brick's part (or its error) and merges. Then every rank measures the merged
/// asset's error on its bricks, and rank 0 gathers that too.
#pragma once

#include "Bricks.h"

#include <exception>
#include <string>
#include <vector>

namespace gvr {

/// How one brick went: its result's bytes (a part asset, say), or what went wrong.
struct BrickOutcome {
    std::size_t brick = 0;
    int rank = 0;
    bool ok = false;
    std::string bytes;  ///< the result when ok, else the error message
};

class BrickTeam {
public:
    /// Joins MPI when mpirun started this process (OpenMPI and PMIx set the rank in
    /// the environment); otherwise a team of one that never touches MPI.
    BrickTeam();
    ~BrickTeam();
    BrickTeam(const BrickTeam&) = delete;
    BrickTeam& operator=(const BrickTeam&) = delete;

    int rank() const { return mRank; }
    int size() const { return mSize; }
    bool isRoot() const { return mRank == 0; }
    /// This machine's cores shared among the team's processes on it.
    std::size_t threadsPerRank() const;

    /// The rank that fits each brick: largest budget first, each to the rank with
    /// the fewest Gaussians so far. The same in every rank.
    std::vector<int> owners(const std::vector<Brick>& bricks) const;

    /// On rank 0: every brick's outcome, in brick order (its own from @a mine, the
    /// others received). On the other ranks: sends @a mine and returns nothing.
    std::vector<BrickOutcome> gather(std::vector<BrickOutcome> mine, const std::vector<int>& owners) const;

    /// Rank 0's @a bytes, in every rank.
    void broadcast(std::string& bytes) const;

    /// In a team of more than one: reports @a error with this rank and ends every
    /// rank with exit code 2, for a failure that would leave the others waiting for
    /// this one forever. Alone: returns, so that the caller rethrows.
    void abortUnlessAlone(const std::exception& error) const;

private:
    bool mMpi = false;
    int mRank = 0, mSize = 1, mLocalSize = 1;
};

}  // namespace gvr
