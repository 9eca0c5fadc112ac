/// @file BrickTeam.h
/// @brief The processes that share a bricked fit: the ranks of an mpirun, or this
/// process alone. Each rank fits its share of the bricks; rank 0 gathers every
/// brick's part (or its error) and merges. Then every rank measures a share of the
/// merged asset's error, and rank 0 adds it up.
#pragma once

#include "Bricks.h"
#include "VolumeError.h"

#include <exception>
#include <string>
#include <utility>
#include <vector>

namespace gvr {

/// How one brick went: its part asset's bytes, or what went wrong.
struct BrickOutcome {
    std::size_t brick = 0;
    int rank = 0;
    bool ok = false;
    std::string bytes;  ///< the part (encodeAsset) when ok, else the error message
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

    /// This rank's share of @a slices items: [first, first + count), contiguous and
    /// in rank order.
    std::pair<int, int> share(int slices) const;

    /// On rank 0: every rank's slice errors joined in rank order, so that in slice
    /// order when each rank measured its share(). On the other ranks: sends @a mine
    /// and returns nothing.
    std::vector<SliceError> gatherSlices(std::vector<SliceError> mine, int slices) const;

    /// In a team of more than one: reports @a error with this rank and ends every
    /// rank with exit code 2, for a failure that would leave the others waiting for
    /// this one forever. Alone: returns, so that the caller rethrows.
    void abortUnlessAlone(const std::exception& error) const;

private:
    bool mMpi = false;
    int mRank = 0, mSize = 1, mLocalSize = 1;
};

}  // namespace gvr
