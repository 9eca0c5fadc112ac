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

#include <openvdb/math/Vec2.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace gvr {

struct StackGeometry {
    openvdb::Vec3d normal, e1, e2;      ///< unit, world; slices are perpendicular to normal
    openvdb::Vec3d origin;              ///< world position of sample (0, 0) of slice 0, the front
    openvdb::Vec2d sampleMm{1.0, 1.0};  ///< between samples along e1 and along e2
    double sliceMm = 1.0;               ///< between slices
    /// sliceMm in voxels (RenderVolume::voxelMm): the spacing asked, or when that is
    /// coarser, the finest that can show more (kMostSamplesPerVoxelCrossed slices for
    /// each voxel a ray can cross).
    double sliceVoxels = 1.0;
    int width = 0, height = 0, slices = 0;
    /// The volume's extent along e2, in rows of samples (fractional): its faces,
    /// when e2 runs along one of its axes. Nothing lies beyond them, though the
    /// lattice reaches a row further (of background, for resampling up to them).
    double firstRowInside = 0.0, lastRowInside = 0.0;
    /// The same along e1, in columns.
    double firstColumnInside = 0.0, lastColumnInside = 0.0;
    /// Whether the samples of a slice fall on the volume's voxel centres (and evenly
    /// between them) along e1 and e2.
    bool samplesOnVoxels = false;

    /// The sample lattice: index (i, j, k) is sample (i, j) of slice k.
    Lattice lattice() const;
};

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

/// How a slice of values keeps them: as 16-bit codes spread evenly from its least
/// value to its greatest (ValueLevels::codingFor), in half a float's bytes. A code,
/// or a code interpolated between codes, stands for a level of the transfer
/// function, which compositing reads.
struct ValueCoding {
    static constexpr int kLastCode = 65535;
    double lowest = 0.0, codesPerValue = 0.0;       ///< the value of code 0, and codes per unit of value
    float firstLevel = 0.0f, levelsPerCode = 0.0f;  ///< the (fractional) level of code 0, and levels per code

    /// The nearest code to @a value; values beyond the codes take the end ones.
    std::uint16_t code(float value) const {
        const double c = (double(value) - lowest) * codesPerValue + 0.5;
        if (!(c > 0.0)) return 0;
        return c >= kLastCode ? std::uint16_t(kLastCode) : std::uint16_t(c);
    }
    /// The value @a code stands for.
    double value(float code) const { return codesPerValue > 0.0 ? lowest + code / codesPerValue : lowest; }
    /// The level, fractional, that @a code stands for: ValueLevels::nearest rounds it.
    float level(float code) const { return firstLevel + code * levelsPerCode; }
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

/// The classification of a stack of values, in levels: the transfer function at
/// kCount values spread evenly over its points (it is constant beyond them), with
/// opacity over one slice spacing. A resampled value takes its nearest level.
class ValueLevels {
public:
    static constexpr int kCount = 4096;

    ValueLevels(const TransferFunction& tf, double sliceSpacingVoxels);
    int levelOf(float value) const { return mScale.levelOf(value); }
    /// The level nearest to fractional level @a level (ValueCoding::level).
    static int nearest(float level) {
        const float rounded = level + 0.5f;
        if (!(rounded > 0.0f)) return 0;
        return rounded >= float(kCount - 1) ? kCount - 1 : int(rounded);
    }
    /// Straight colour and the opacity of one slice spacing.
    const std::array<float, 4>& rgba(int level) const { return mRgba[level]; }
    /// The fractional level below which every nearest level is transparent: minus
    /// infinity when level 0 can be seen, and beyond the last level when none can.
    float darkBelow() const { return mDarkBelow; }
    /// The coding of values from @a lo to @a hi, and no further than kCodeReach spans
    /// of the transfer function beyond its points: a value that far off classifies
    /// as its end level all the same, and resamples with its neighbours little
    /// differently, while the codes keep a 500th of the span or finer.
    ValueCoding codingFor(float lo, float hi) const;
    /// Whether some value in [lo, hi] has a level that is not transparent.
    bool anyVisible(float lo, float hi) const { return anyVisibleLevel(levelOf(lo), levelOf(hi)); }
    /// Whether some level in [lo, hi] is not transparent (none when lo > hi).
    bool anyVisibleLevel(int lo, int hi) const { return hi >= lo && mVisibleFrom[lo] <= hi; }
    /// anyVisibleLevel(lo[n], hi[n]) into seen[n] for each n below @a count.
    void markVisible(const std::uint16_t* lo, const std::uint16_t* hi, std::size_t count, std::uint8_t* seen) const;

private:
    /// Values to levels. In double precision, so that any span of float values, from
    /// the gap between two denormals to the whole float range, has finite levels per unit.
    struct Scale {
        double first, perValue;  ///< the value of level 0, and levels per unit of value
        int levelOf(float value) const {
            const double level = (double(value) - first) * perValue + 0.5;
            if (!(level > 0.0)) return 0;  // NaN too
            return level >= double(kCount - 1) ? kCount - 1 : int(level);
        }
    };

    static constexpr double kCodeReach = 64.0;
    Scale mScale;
    float mDarkBelow;
    std::vector<std::array<float, 4>> mRgba;
    /// The first visible level at or above each level (kCount for none): a range's
    /// test in one read of a table small enough to stay in cache.
    std::vector<std::uint16_t> mVisibleFrom;
};

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
