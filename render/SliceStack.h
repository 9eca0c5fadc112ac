/// @file SliceStack.h
/// @brief One stack of classified slices through a volume, perpendicular to a
/// stack direction: what shear-warp builds once and composites for many views.
///
/// Slices are sampled on a lattice in world space (sampleMm across, sliceMm apart),
/// so any stack direction works, not only the volume's axes. Along a volume's axis
/// the samples fall on its voxel centres, where resampling a slice bilinearly gives
/// the trilinear field exactly, as the ray marcher samples it; slices across one lie
/// a quarter of a voxel off its voxel planes. A stack of one volume whose
/// background cannot be seen keeps each sample's value (StackContent), 16 bits a
/// channel, and compositing classifies the value it resamples from them
/// (post-classification, as the ray marcher does: an opaque surface then lies where
/// the values cross it, not where resampled opacities do, and a colour section's
/// colours blend before they are classified). Other stacks (several layers, or a
/// visible background) keep each sample classified: premultiplied colour and the
/// opacity of one slice spacing, 16 bits each. Each
/// slice row keeps only its runs of samples that can be seen (Lacroute's
/// run-length encoding), which is how compositing skips empty space, inside the
/// body too.
#pragma once

#include "pipeline/Progress.h"
#include "render/Classifier.h"
#include "render/RenderVolume.h"
#include "render/StackGeometry.h"
#include "render/ValueLevels.h"

#include <openvdb/math/Vec2.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace gvr {

/// What a stack's slices hold.
enum class StackContent {
    /// Classified samples (StackSample): premultiplied colour and opacity.
    Classified,
    /// A grey volume's values, as codes (Slice::codes).
    Values,
    /// A colour volume's values (StackSample): the colour the classifier gives it, and
    /// the code of its luminance, which the transfer function classifies.
    Colours,
};

struct StackSample {
    /// Premultiplied colour and opacity, x 65535; in a stack of colours, the colour
    /// x 65535 and the code of its luminance.
    std::uint16_t r = 0, g = 0, b = 0, a = 0;
};

/// Transparent gaps shorter than this many samples stay inside a run: a run costs
/// more to step over than a few empty samples cost to composite.
constexpr int kRunGap = 4;

/// Samples of background a slice stores before its first run and after its last,
/// so that compositing may read eight samples at once from anywhere within seven
/// of a run, and take nothing from those beyond it.
constexpr int kStoredMargin = 8;

/// A run is stored with its row's neighbouring sample on either side (the
/// background beyond the row's ends), so that resampling may read a run's
/// neighbours without a test: classified samples there are transparent.
struct RowRun {
    std::uint32_t begin = 0, end = 0;  ///< samples [begin, end) of the row are stored
    std::uint32_t offset = 0;          ///< where sample `begin` sits in Slice::samples
};

struct Slice {
    /// Row j's runs are runs[rowRuns[j]] up to runs[rowRuns[j + 1]], left to right;
    /// every sample outside them is transparent.
    std::vector<std::uint32_t> rowRuns;
    std::vector<RowRun> runs;
    std::vector<StackSample> samples;  ///< classified stacks, and stacks of colours
    std::vector<std::uint16_t> codes;  ///< stacks of grey values (ValueLevels), laid out as samples are
    ValueCoding coding;                ///< what the codes stand for (of the luminance, for colours)

    /// samples or codes, by the type of what is stored: for code written once for both.
    template <typename Sample>
    std::vector<Sample>& stored();
    template <typename Sample>
    const std::vector<Sample>& stored() const {
        return const_cast<Slice*>(this)->stored<Sample>();
    }
};

template <>
inline std::vector<StackSample>& Slice::stored() {
    return samples;
}
template <>
inline std::vector<std::uint16_t>& Slice::stored() {
    return codes;
}

/// One volume and how to classify it. A stack may hold several layers that share
/// the first one's place in the world: the structures of one asset, each with its
/// own style.
struct StackLayer {
    const RenderVolume* volume = nullptr;
    Classifier classifier;
};

/// How a stack of values is composited (ValueLevels).
enum class Classification {
    /// Each sample classified alone: a band of values thinner than a slice spacing
    /// may fall between two slices and be missed.
    Points,
    /// Pre-integrated (Engel, Kraus and Ertl): each stretch of a ray from one slice to
    /// the next takes the transfer function averaged over the values between its
    /// two ends, which sees such bands. The build keeps every sample whose stretch
    /// to a neighbouring slice could be seen, for any view within
    /// SegmentViews::maxAngleDeg of the stack's normal. Outside the volume the
    /// values are the background's, as for points: a ray entering through a face
    /// crosses every value between the background's and the face's.
    Segments,
};

/// "points" or "segments": how the command line and reports name a classification.
inline const char* classificationName(Classification classification) {
    return classification == Classification::Segments ? "segments" : "points";
}

/// The classification called @a name, or none when no classification is.
inline std::optional<Classification> classificationNamed(const std::string& name) {
    for (const Classification c : {Classification::Points, Classification::Segments}) {
        if (name == classificationName(c)) return c;
    }
    return std::nullopt;
}

/// The views a stack of segments serves exactly: a view further off the normal
/// crosses more samples from one slice to the next than the build looked at, and
/// where one end of a stretch was left out it is classified as a point.
struct SegmentViews {
    Classification classification = Classification::Points;
    double maxAngleDeg = 0.0;  ///< degrees; taken as 0 to 80
};

/// What a stack samples: each volume's voxels (RenderVolume::blocksOn), or a quick
/// look that need not wait for them (previewBlocksOn), for a coarse first image.
enum class StackSampling { Voxels, Preview };

class SliceStack {
public:
    /// Samples @a volume on the stack's lattice (in parallel over 8^3 blocks, only
    /// where the volume has content). Opacities are corrected from one voxel to one
    /// slice spacing: 1 - (1 - alpha)^(sliceMm / voxelMm). The samples keep their
    /// values when the volume's background is transparent, and are classified otherwise.
    /// @param sampleMm  the spacing asked across the slices: a stack of the voxels
    ///                  (not a preview) samples no coarser than they lie along each
    ///                  axis, nor more than twice as finely as asked (StackGeometry::sampleMm)
    /// @param cancel  when set (from any thread), the build stops within one slab of
    ///                eight slices and throws Cancelled
    SliceStack(const RenderVolume& volume, const Classifier& classifier, const openvdb::Vec3d& direction,
               double sliceSpacingVoxels, double sampleMm, const ProgressFn& progress = {},
               const std::atomic<bool>* cancel = nullptr, StackSampling sampling = StackSampling::Voxels,
               SegmentViews segments = {});

    /// The same for several layers: where layers meet, their opacities combine as
    /// 1 - prod(1 - alpha) and their colours in proportion to their opacities.
    SliceStack(const std::vector<StackLayer>& layers, const openvdb::Vec3d& direction, double sliceSpacingVoxels,
               double sampleMm, const ProgressFn& progress = {}, const std::atomic<bool>* cancel = nullptr,
               StackSampling sampling = StackSampling::Voxels, SegmentViews segments = {});

    const StackGeometry& geometry() const { return mGeometry; }
    const std::vector<Slice>& slices() const { return mSlices; }
    /// Gaussians the build evaluated (0 for grids).
    std::size_t gaussiansTouched() const { return mGaussiansTouched; }
    StackContent content() const { return mContent; }
    /// How to classify the slices' values (the luminance of colours); null when the
    /// slices hold classified samples.
    const ValueLevels* valueLevels() const { return mLevels.get(); }
    /// How the slices' values are composited: segments only for a stack of grey
    /// values built for them.
    Classification classification() const { return mClassification; }

private:
    StackGeometry mGeometry;
    StackContent mContent = StackContent::Classified;
    std::unique_ptr<ValueLevels> mLevels;
    Classification mClassification = Classification::Points;
    std::vector<Slice> mSlices;
    std::size_t mGaussiansTouched = 0;
};

}  // namespace gvr
