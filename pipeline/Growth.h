/// @file Growth.h
/// @brief Coarse to fine: the fit starts with fewer, wider Gaussians and grows the
/// count in steps by splitting the widest ones.
///
/// A split keeps the field nearly as it was, so the loss does not jump: the two
/// halves sit at +-sigma/2 along the parent's widest axis with sigma * sqrt(3)/2
/// along it, which keeps the parent's mean, covariance and mass.
#pragma once

#include "Adam.h"
#include "GaussianParameters.h"

#include <cstddef>

namespace gvr {

/// The count at growth stage @a stage of @a doublings (stage == doublings is the
/// final count): ceil(finalCount / 2^(doublings - stage)), at least 1.
std::size_t countAtStage(std::size_t finalCount, int doublings, int stage);

/// The stage due at fraction @a fraction of the budget: stage k starts at
/// k * share / doublings, so the last doubling happens at @a share.
int stageAt(double fraction, int doublings, double share);

/// Splits the @a extra Gaussians with the longest axis (ties: the lower index) in
/// two, appending the second halves with zeroed Adam moments.
/// @return the number split: min(extra, params.count()).
std::size_t splitWidest(GaussianParameters& params, Adam& adam, std::size_t extra);

}  // namespace gvr
