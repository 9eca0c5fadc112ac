#include "render/StackGeometry.h"

#include "render/Camera.h"

#include <algorithm>
#include <cmath>
#include <optional>

namespace gvr {

using openvdb::Coord;
using openvdb::Vec3d;

namespace {

/// Any unit vector not parallel to @a normal, for the slices' in-plane axes.
Vec3d helperAxis(const Vec3d& normal) { return std::abs(normal.z()) < 0.9 ? Vec3d(0, 0, 1) : Vec3d(0, 1, 0); }

/// Samples along one axis of a lattice: count of them, @a step apart from @a first.
struct AxisSamples {
    int count = 1;
    double first = 0.0, step = 1.0;
    bool onVoxelCentres = false;  ///< and evenly between them
};

/// Enough samples @a step apart to cover [lo, hi], centred on it.
AxisSamples centredSamples(double lo, double hi, double step) {
    const int count = std::max(1, int(std::ceil((hi - lo) / step - 1e-9)));
    return {count, lo + 0.5 * ((hi - lo) - (count - 1) * step), step};
}

/// The same with one more sample beyond each end: resampling a slice between its
/// outermost samples and the background then meets the background's value.
AxisSamples paddedSamples(AxisSamples samples) {
    return {samples.count + 2, samples.first - samples.step, samples.step};
}

/// A volume's voxel centres seen along a world direction: their spacing, and where one lies.
struct VoxelRow {
    double edgeMm = 0.0, centreMm = 0.0;
};

/// The volume's voxel centres along @a along, when it runs along one of the
/// volume's index axes and across the other two (so that the centres' places on it
/// are one evenly spaced row); none otherwise.
std::optional<VoxelRow> voxelRowAlong(const RenderVolume& volume, const Vec3d& along) {
    const openvdb::math::Mat4d& worldFromIndex = volume.worldFromIndex();
    const Vec3d zero = worldFromIndex.transform(Vec3d(0.0));
    std::optional<VoxelRow> row;
    for (int axis = 0; axis < 3; ++axis) {
        Vec3d unit(0.0);
        unit[axis] = 1.0;
        const Vec3d edge = worldFromIndex.transform(unit) - zero;
        const double cosine = std::abs(edge.dot(along)) / edge.length();
        if (cosine > 1.0 - 1e-9) {
            row = VoxelRow{edge.length(), worldFromIndex.transform(volume.box().min().asVec3d()).dot(along)};
        } else if (!(cosine < 1e-9)) {
            return std::nullopt;
        }
    }
    return row;
}

/// How far a lattice on the voxel centres may stray from the spacing asked: at
/// ct-head's default view (pixels of 1.39 voxels, 0.93 asked) a lattice of one
/// voxel scores higher against the reference with the `mri` preset than the
/// lattice asked (lower with a surface), from fewer samples
/// (docs/benchmarks.md, "Samples on the voxel centres, slices off the voxel planes").
constexpr double kVoxelStepReach = 1.3;

/// The step of a lattice on the voxel centres of @a row nearest @a wantedMm: a
/// voxel over a whole number of samples (rounded down), or a whole number of voxels
/// (rounded to the nearest); none when that strays more than kVoxelStepReach from it.
std::optional<double> stepOnVoxels(double wantedMm, const VoxelRow& row) {
    const double step = wantedMm <= row.edgeMm ? row.edgeMm / std::floor(row.edgeMm / wantedMm)
                                               : row.edgeMm * std::round(wantedMm / row.edgeMm);
    if (!std::isfinite(step) || !(step <= wantedMm * kVoxelStepReach && step * kVoxelStepReach >= wantedMm)) {
        return std::nullopt;  // NaN and infinity too
    }
    return step;
}

/// Samples on the voxel centres of @a row, @a step apart, from the last one before
/// @a lo to the first one beyond @a hi.
AxisSamples samplesOnVoxels(double lo, double hi, double step, const VoxelRow& row) {
    const double before = std::ceil((lo - row.centreMm) / step - 1e-9) - 1.0;
    const double after = std::floor((hi - row.centreMm) / step + 1e-9) + 1.0;
    return {int(after - before) + 1, row.centreMm + before * step, step, true};
}

/// How much finer than asked a stack may sample, to keep to the voxels (sampleSpacing).
constexpr double kFinerThanAsked = 2.0;

/// The spacing to sample along @a along when @a wantedMm is asked: no coarser than
/// the voxels along it (its voxel edge, or the smallest where it runs along no
/// axis), nor more than kFinerThanAsked times finer than asked. Where the view
/// shrinks the volume, samples further apart than the voxels skip some, and a thin
/// structure between them shows as stripes: at 256 x 256, chest `ct` frames fell
/// short of the one-ray ray marcher (docs/benchmarks.md, "Samples no
/// coarser than the voxels"). Asked coarser than the voxels, a stack so holds at
/// most a sample a voxel.
double sampleSpacing(const RenderVolume& volume, const std::optional<VoxelRow>& row, double wantedMm) {
    const double voxelMm = row ? row->edgeMm : volume.voxelMm();
    return std::max(std::min(wantedMm, voxelMm), wantedMm / kFinerThanAsked);
}

/// Samples along @a along covering [lo, hi] and one beyond each end, about
/// @a wantedMm apart (at sampleSpacing when @a fine): on the voxel centres when
/// @a onVoxels, it runs along an axis of the volume and they lie near, else centred.
AxisSamples samplesAlong(const RenderVolume& volume, const Vec3d& along, double lo, double hi, double wantedMm,
                         bool onVoxels, bool fine) {
    const std::optional<VoxelRow> row = voxelRowAlong(volume, along);
    if (fine) wantedMm = sampleSpacing(volume, row, wantedMm);
    if (row && onVoxels) {
        if (const std::optional<double> step = stepOnVoxels(wantedMm, *row))
            return samplesOnVoxels(lo, hi, *step, *row);
    }
    return paddedSamples(centredSamples(lo, hi, wantedMm));
}

/// Slices across a volume's axis lie this far off its voxel planes, in voxels. On the
/// planes, with samples on the voxel centres, a ray met only the voxels' own values
/// and a scan's steps of value showed as rings: at 512 x 512 at `gvr render`'s
/// default view, axis stacks' images of ct-head and the chest scored closer to the
/// reference a quarter of a voxel off them (with a sharper warp than today's; at
/// 256 x 256, some further and some closer: docs/benchmarks.md,
/// "Samples on the voxel centres, slices off the voxel planes").
constexpr double kSlicesOffPlanes = 0.25;

/// Slices @a step apart within [lo, hi], kSlicesOffPlanes of a voxel off the voxel
/// planes of @a row.
AxisSamples slicesOffPlanes(double lo, double hi, double step, const VoxelRow& row) {
    const double phase = row.centreMm + kSlicesOffPlanes * row.edgeMm;
    const double first = std::ceil((lo - phase) / step), last = std::floor((hi - phase) / step);
    return {std::max(1, int(last - first) + 1), phase + first * step, step};
}

/// The finest slice spacing, in voxels, of a stack through a volume @a depthMm deep
/// along its normal: no ray crosses more voxels than the volume's dimensions add up
/// to, so a stack holds at most kMostSamplesPerVoxelCrossed slices for each. Only
/// very unequal voxels reach it: 12^3 voxels of 1e-6 x 1 x 1 mm stacked along a 1 mm
/// edge took 12 million slices of 1e-6 mm (7 GB) to show 12 voxels.
double finestSliceVoxels(const RenderVolume& volume, double depthMm) {
    const Coord dims = volume.box().dim();
    const double crossed = double(dims.x()) + double(dims.y()) + double(dims.z());
    return depthMm / (kMostSamplesPerVoxelCrossed * crossed * volume.voxelMm());
}

}  // namespace

StackGeometry stackGeometryFor(const RenderVolume& volume, const Vec3d& direction, double sliceSpacingVoxels,
                               double sampleMm, bool keepsValues, bool fine) {
    StackGeometry g;
    g.normal = direction.unit();
    g.e1 = helperAxis(g.normal).cross(g.normal).unit();
    g.e2 = g.normal.cross(g.e1).unit();
    Vec3d lo(1e300), hi(-1e300);
    for (const Vec3d& corner : worldCorners(volume.worldFromIndex(), volume.box())) {
        const Vec3d p(corner.dot(g.e1), corner.dot(g.e2), corner.dot(g.normal));
        lo = openvdb::math::minComponent(lo, p);
        hi = openvdb::math::maxComponent(hi, p);
    }
    g.sliceVoxels = std::max(sliceSpacingVoxels, finestSliceVoxels(volume, hi[2] - lo[2]));
    g.sliceMm = volume.voxelMm() * g.sliceVoxels;
    const AxisSamples across = samplesAlong(volume, g.e1, lo[0], hi[0], sampleMm, keepsValues, fine);
    const AxisSamples down = samplesAlong(volume, g.e2, lo[1], hi[1], sampleMm, keepsValues, fine);
    const std::optional<VoxelRow> planes = voxelRowAlong(volume, g.normal);
    const AxisSamples slices =
        planes ? slicesOffPlanes(lo[2], hi[2], g.sliceMm, *planes) : centredSamples(lo[2], hi[2], g.sliceMm);
    g.sampleMm = {across.step, down.step};
    g.samplesOnVoxels = across.onVoxelCentres && down.onVoxelCentres;
    g.width = across.count;
    g.height = down.count;
    g.slices = slices.count;
    g.firstRowInside = (lo[1] - down.first) / down.step;
    g.lastRowInside = (hi[1] - down.first) / down.step;
    g.firstColumnInside = (lo[0] - across.first) / across.step;
    g.lastColumnInside = (hi[0] - across.first) / across.step;
    g.origin = g.e1 * across.first + g.e2 * down.first + g.normal * slices.first;
    return g;
}

Lattice StackGeometry::lattice() const {
    openvdb::math::Mat4d m = openvdb::math::Mat4d::identity();
    const Vec3d rows[4] = {e1 * sampleMm[0], e2 * sampleMm[1], normal * sliceMm, origin};
    for (int r = 0; r < 4; ++r) {
        for (int c = 0; c < 3; ++c) m(r, c) = rows[r][c];
    }
    return {m, openvdb::CoordBBox(Coord(0), Coord(width - 1, height - 1, slices - 1))};
}

int segmentReach(const StackGeometry& g, double maxAngleDeg) {
    // Across the finer of the two sample spacings, the shear reaches furthest.
    const double finerMm = std::min(g.sampleMm[0], g.sampleMm[1]);
    const double shift = std::tan(std::clamp(maxAngleDeg, 0.0, 80.0) * M_PI / 180.0) * g.sliceMm / finerMm;
    return int(std::ceil(shift - 1e-9));
}

}  // namespace gvr
