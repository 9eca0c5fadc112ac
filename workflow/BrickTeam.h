/// @file BrickTeam.h
/// @brief The processes that share a bricked fit. Each rank fits its share of the
/// bricks; rank 0 gathers every brick's part (or its error) and merges. Then every
/// rank measures the merged asset's error on its bricks, and rank 0 gathers that too.
///
/// A SoloTeam is this process alone (a plain `gvr fit --bricks`, or Python); an
/// MpiTeam (MpiTeam.h) is the ranks of an mpirun. The bricked fit (TeamFit.h) sees
/// only this interface.
#pragma once

#include "pipeline/Bricks.h"

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
    virtual ~BrickTeam() = default;

    virtual int rank() const = 0;
    virtual int size() const = 0;
    bool isRoot() const { return rank() == 0; }
    /// This machine's cores shared among the team's processes on it.
    virtual std::size_t threadsPerRank() const = 0;

    /// The rank that fits each brick: largest budget first, each to the rank with
    /// the fewest Gaussians so far. The same in every rank.
    std::vector<int> owners(const std::vector<Brick>& bricks) const;

    /// On rank 0: every brick's outcome, in brick order (its own from @a mine, the
    /// others received). On the other ranks: sends @a mine and returns nothing.
    virtual std::vector<BrickOutcome> gather(std::vector<BrickOutcome> mine, const std::vector<int>& owners) const = 0;

    /// Rank 0's @a bytes, in every rank.
    virtual void broadcast(std::string& bytes) const = 0;

    /// In a team of more than one: reports @a error with this rank and ends every
    /// rank, for a failure that would leave the others waiting for this one
    /// forever. Alone: returns, so that the caller rethrows.
    virtual void abortUnlessAlone(const std::exception& error) const = 0;
};

/// This process alone: it fits every brick, and nothing travels.
class SoloTeam final : public BrickTeam {
public:
    int rank() const override { return 0; }
    int size() const override { return 1; }
    std::size_t threadsPerRank() const override;
    std::vector<BrickOutcome> gather(std::vector<BrickOutcome> mine, const std::vector<int>& owners) const override;
    void broadcast(std::string&) const override {}
    void abortUnlessAlone(const std::exception&) const override {}
};

}  // namespace gvr
