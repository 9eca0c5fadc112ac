/// @file LeafAssembly.h
/// @brief Builds a sparse grid from leaf nodes filled in parallel.
///
/// Filling leaves is independent work; linking them into the tree is not, so the
/// leaves are made concurrently and linked afterwards by one thread, in order.
#pragma once

#include "pipeline/Progress.h"

#include <openvdb/openvdb.h>
#include <tbb/parallel_for.h>

#include <memory>
#include <vector>

namespace gvr {

/// Makes the leaves at @a origins and links them into @a grid, replacing any leaf
/// already at the same origin.
/// @param origins   leaf origins (multiples of the leaf size), each visited once
/// @param makeLeaf  called concurrently as makeLeaf(origin); returns a
///                  std::unique_ptr<LeafNodeType>, null to leave the leaf out
/// @param counter   advanced once per origin
template <typename GridT, typename MakeLeaf>
void addLeaves(GridT& grid, const std::vector<openvdb::Coord>& origins, const MakeLeaf& makeLeaf,
               ProgressCounter& counter) {
    using LeafT = typename GridT::TreeType::LeafNodeType;
    std::vector<std::unique_ptr<LeafT>> leaves(origins.size());
    tbb::parallel_for(std::size_t(0), origins.size(), [&](std::size_t n) {
        leaves[n] = makeLeaf(origins[n]);
        counter.advance();
    });
    for (auto& leaf : leaves) {
        if (leaf) grid.tree().addLeaf(leaf.release());
    }
}

/// A new grid of the leaves at @a origins (see addLeaves()).
template <typename GridT, typename MakeLeaf>
typename GridT::Ptr assembleGrid(const std::vector<openvdb::Coord>& origins,
                                 const typename GridT::ValueType& background, const MakeLeaf& makeLeaf,
                                 const ProgressFn& progress = {}) {
    typename GridT::Ptr grid = GridT::create(background);
    ProgressCounter counter(progress, origins.size());
    addLeaves(*grid, origins, makeLeaf, counter);
    return grid;
}

}  // namespace gvr
