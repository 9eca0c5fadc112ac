/// @file ResidualLayer.h
/// @brief An error-bounded layer over the Gaussians: every voxel of the source
/// within a bound E of what the layer reconstructs, the Gaussian field being its
/// prediction (and the Gaussians alone its preview).
///
/// Each voxel is predicted, its residual quantised in steps of 2E + 1 stored
/// samples (integer data, so that a file in the source's own type holds the
/// result exactly) or 2E (float data), and the quantised residual added back.
/// As in the SZ family of codecs, the prediction of a voxel uses only voxels
/// decoded before it, so that the decoder predicts exactly as the encoder did; voxels
/// code level by level (SZ3's interpolation order), and each 8^3 block picks its
/// predictor (the Gaussians, an interpolation of decoded neighbours, or the Gaussians
/// corrected by an interpolation of their neighbours' decoded residuals), since on
/// CT the Gaussians' tails over air predict worse than the neighbours do. The encoder
/// runs the decoder's arithmetic and stores any voxel whose reconstruction would miss
/// the bound after rounding exactly, so the bound holds on every voxel.
#pragma once

#include "pipeline/FloatVolume.h"

#include <cstdint>
#include <limits>
#include <vector>

namespace gvr {

/// The numbers a layer's reconstructed values are: the source's own stored samples
/// (intercept + slope * k for integer k) where every source voxel is one, else floats.
struct ResidualDomain {
    bool integers = false;
    double slope = 1.0, intercept = 0.0;
};

/// How a block's voxels are predicted.
enum class ResidualPredictor : std::uint8_t {
    Gaussians = 0,   ///< the Gaussian field at the voxel
    Neighbours = 1,  ///< cubic interpolation between decoded voxels
    Both = 2,        ///< the Gaussian field plus linear interpolation of the decoded residuals from it
};
constexpr int kResidualPredictors = 3;
/// Slices coded apart from the others, so that slabs code in parallel (a slab
/// interpolates between its own slices only).
constexpr int kResidualSlabSlices = 32;
/// The slabs of a volume of @a dims: the slices [s * kResidualSlabSlices, ...) for each s.
inline int residualSlabCount(const openvdb::Coord& dims) {
    return (dims.z() + kResidualSlabSlices - 1) / kResidualSlabSlices;
}
/// A code that says: this voxel's exact value is the next of ResidualLayer::exact.
constexpr std::int32_t kResidualExact = std::numeric_limits<std::int32_t>::min();
/// Quantised residuals stay within this; beyond, the voxel is stored exactly.
constexpr std::int32_t kMaxResidualCode = (1 << 30) - 1;

struct ResidualLayer {
    double bound = 0.0;  ///< E, in the source's units: no voxel is further from it
    /// The source's range in the domain (stored samples or values): reconstructions are
    /// clamped into it, so they stay in the source's type and never step away from it.
    double low = 0.0, high = 0.0;
    ResidualDomain domain;
    openvdb::Coord dims{0, 0, 0};
    int channels = 1;
    /// One per 8^3 block (i fastest, then j, then k) and channel, channels innermost.
    std::vector<ResidualPredictor> predictors;
    /// One per voxel and channel, in FloatVolume's order: the quantised residual, or kResidualExact.
    std::vector<std::int32_t> codes;
    /// The exact values (stored samples k for integer domains, else the value), slab
    /// by slab, then channel by channel, in the coding order within.
    std::vector<double> exact;
    /// CRC-32 of the reconstruction's floats as the encoder decoded them: a reader
    /// whose arithmetic differed (its prediction not bit for bit the encoder's) finds out.
    std::uint32_t reconstructionChecksum = 0;

    /// The quantisation step in the domain: 2E + 1 samples (E rounded down to whole
    /// samples), or 2E.
    double step() const;
    std::size_t exactVoxels() const { return exact.size(); }
};

/// The domain of @a source: its stored samples when every value is intercept +
/// slope * k for an integer k with |k| < 2^31, exactly as a float holds it.
ResidualDomain residualDomainOf(const FloatVolume& source, double slope, double intercept);

/// The layer that takes @a prediction (the Gaussians on the source's lattice) to
/// within @a bound of @a source on every voxel.
/// @throw InputError naming `max_error` for a bound that is NaN, negative, infinite,
///        or zero over float data (which has no lossless path); std::invalid_argument
///        when the volumes differ in shape.
ResidualLayer encodeResidualLayer(const FloatVolume& source, const FloatVolume& prediction, double bound,
                                  const ResidualDomain& domain);

/// The reconstruction: @a prediction (bit for bit the one the layer was encoded
/// over) with the layer added. @throw std::runtime_error when the layer does not
/// match the prediction's shape, or its exact values run out.
FloatVolume decodeResidualLayer(const ResidualLayer& layer, const FloatVolume& prediction);

}  // namespace gvr
