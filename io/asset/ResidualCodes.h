/// @file ResidualCodes.h
/// @brief The residual layer's codes as range-coded streams, one per slab, each
/// code's bits coded in the context of its decoded neighbours' magnitudes.
///
/// Residual magnitudes cluster (tissue edges, noise, flat air), so a code beside
/// large codes is likely large and a code beside zeros likely zero: the same model
/// that costs an order-0 coder a bit per voxel in air costs a thousandth of one here.
/// A code is binarised as a zero flag, the bit length of its magnitude in unary
/// (one value past the longest says "stored exactly"), the bits under its top bit,
/// and its sign. Slabs code apart, as the layer's prediction does, so both encode
/// and decode run slab by slab in parallel.
#pragma once

#include "pipeline/ResidualLayer.h"

#include <string>
#include <string_view>
#include <vector>

namespace gvr {

/// One stream per slab (residualSlabCount) of @a layer's codes.
std::vector<std::string> encodeResidualCodes(const ResidualLayer& layer);

/// Fills @a layer.codes (sized to its dims and channels beforehand) from @a streams,
/// one per slab. @throw std::runtime_error when a stream runs out before its codes do.
void decodeResidualCodes(const std::vector<std::string_view>& streams, ResidualLayer& layer);

}  // namespace gvr
