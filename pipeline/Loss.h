/// @file Loss.h
/// @brief Weighted squared residuals of the field at sample points, and their gradient.
///
/// Work is split into a fixed number of chunks, each with its own gradient buffer,
/// summed in chunk order: results do not depend on the thread count or scheduling.
#pragma once

#include "pipeline/BlockBins.h"
#include "pipeline/GaussianField.h"

#include <array>
#include <memory>
#include <vector>

namespace gvr {

/// Points where the field is compared with the volume.
struct SampleSet {
    std::vector<std::array<float, 3>> points;  ///< index space
    std::vector<float> targets;                ///< channels per point, normalised units
    std::vector<float> weights;                ///< one per point
    std::size_t size() const { return points.size(); }
};

/// One gradient buffer per chunk, reused across iterations. A chunk keeps the
/// GradientSums of each Gaussian it touched, so that the rotation and quaternion
/// adjoints run once per Gaussian in sumInto(). The sums are stored densely in
/// the order of first touch, behind a slot per Gaussian: a chunk touches only part
/// of the Gaussians, and clearing costs what a pass touched. They sit in fixed pages,
/// not a growing vector, whose doubling left up to half of the fit's largest
/// buffer unused.
class GradientChunks {
public:
    static constexpr std::size_t kChunks = 8;

    /// Zeroes every buffer, sized for @a count Gaussians.
    void reset(std::size_t count);
    /// Gaussian @a index's sums in chunk @a c, to add a point to.
    GradientSums& sumsOf(std::size_t c, std::uint32_t index);
    /// dL/dparams of Gaussians [begin, end) of @a field, activated from @a params,
    /// into @a gradient (resized to end - begin and overwritten, Gaussian begin + i at
    /// index i), summing the chunks in chunk order. Calls for disjoint ranges may run
    /// at the same time. @return how many of them got a gradient.
    std::size_t sumInto(const GaussianField& field, const GaussianParameters& params, std::size_t begin,
                        std::size_t end, GaussianParameters& gradient) const;
    /// The same for every Gaussian of @a field.
    std::size_t sumInto(const GaussianField& field, const GaussianParameters& params,
                        GaussianParameters& gradient) const {
        return sumInto(field, params, 0, field.gaussians().size(), gradient);
    }

private:
    static constexpr std::uint32_t kUntouched = ~std::uint32_t(0);
    static constexpr std::uint32_t kPageSums = 2048;

    GradientSums& sumsAt(std::size_t c, std::uint32_t slot) const {
        return mPages[c][slot / kPageSums][slot % kPageSums];
    }

    std::array<std::vector<std::unique_ptr<GradientSums[]>>, kChunks> mPages;  ///< by slot, kPageSums a page
    std::array<std::vector<std::uint32_t>, kChunks> mTouched;                  ///< slot -> Gaussian
    std::array<std::vector<std::uint32_t>, kChunks> mSlots;                    ///< Gaussian -> slot, or kUntouched
};

/// L = scale * sum_s w_s |f(x_s) - t_s|^2 over @a samples, point by point.
/// @param gradients  when not null, dL/dparams is added into its chunks
/// @param bins  when not null, where to find the Gaussians near each point (a
///              fit's bins, whose field's BVH is not kept current); else the BVH
double weightedSquaredError(const GaussianField& field, const SampleSet& samples, double scale,
                            GradientChunks* gradients = nullptr, const BlockBins* bins = nullptr);

/// Target minus field at each sample, channels per point; from the bins if given.
std::vector<float> residualsAt(const GaussianField& field, const SampleSet& samples, const BlockBins* bins = nullptr);

}  // namespace gvr
