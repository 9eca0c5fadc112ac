#include "render/ShearWarp.h"

#include "render/RowCompositor.h"
#include "render/Warp.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iterator>

namespace gvr {

using openvdb::Vec3d;

std::string ShearWarpSettings::validate() const {
    // Below a twentieth of a voxel the stack would hold thousands of slices per voxel row.
    if (!(sliceSpacingVoxels >= 0.05) || sliceSpacingVoxels > 64.0)
        return "`slice_spacing` must be in [0.05, 64] voxels";
    if (!(reuseAngleDeg >= 0.0 && reuseAngleDeg <= 60.0)) return "`reuse_angle` must be between 0 and 60 degrees";
    if (!(terminationOpacity > 0.0f && terminationOpacity <= 1.0f)) return "`termination` must be in (0, 1]";
    if (!(supersampling >= 1.0 && supersampling <= 4.0)) return "`supersample` must be in [1, 4]";
    return {};
}

Vec3d ShearWarpSettings::stackNormalFor(const Vec3d& direction) const {
    if (stacks == StackOrientation::View) return direction.unit();
    // Ties go to the first axis, so that a view at exactly 45 degrees has one stack.
    int axis = 0;
    for (int a = 1; a < 3; ++a) {
        if (std::abs(direction[a]) > std::abs(direction[axis])) axis = a;
    }
    return Vec3d(axis == 0, axis == 1, axis == 2);
}

SegmentViews ShearWarpSettings::segmentViews() const {
    const double axisToDiagonalDeg = std::acos(1.0 / std::sqrt(3.0)) * 180.0 / M_PI;
    return {classification, stacks == StackOrientation::View ? reuseAngleDeg : axisToDiagonalDeg};
}

bool ShearWarpSettings::serves(const Vec3d& normal, const Vec3d& direction) const {
    if (stacks == StackOrientation::Axes) return normal == stackNormalFor(direction);
    return angleToStackDeg(direction, normal) <= reuseAngleDeg;
}

double angleToStackDeg(const Vec3d& direction, const Vec3d& normal) {
    return angleBetweenDeg(direction, direction.dot(normal) < 0.0 ? -normal : normal);
}

namespace {

// The compositor's parts, which only this file puts together (out of the unity
// build, so that their names stay here).
using namespace compositing;

/// @a memory: storage for the intermediate image, of any size and content.
IntermediateImage compositeSlices(const SliceStack& stack, const Vec3d& direction, const ShearWarpSettings& settings,
                                  std::vector<float> memory) {
    const float terminationOpacity = settings.terminationOpacity;
    const CompositeLanes lanes = settings.compositeLanes;
    const StackGeometry& g = stack.geometry();
    const double dn = direction.dot(g.normal);
    // Moving one slice back shifts the ray this far across the slices, in samples.
    const double shiftX = direction.dot(g.e1) / dn * g.sliceMm / g.sampleMm[0];
    const double shiftY = direction.dot(g.e2) / dn * g.sliceMm / g.sampleMm[1];
    const double lastX = shiftX * (g.slices - 1), lastY = shiftY * (g.slices - 1);
    IntermediateImage out;
    // The margins keep every pixel a sample reaches inside the image, whatever the shear.
    out.originX = int(std::floor(std::min(0.0, -lastX))) - 1;
    out.originY = int(std::floor(std::min(0.0, -lastY))) - 1;
    out.width = int(std::ceil(std::max(0.0, -lastX))) + g.width + 1 - out.originX;
    out.height = int(std::ceil(std::max(0.0, -lastY))) + g.height + 1 - out.originY;
    // Each band clears its own rows, while they are in its core's cache.
    out.rgba = std::move(memory);
    out.rgba.resize(std::size_t(out.width) * out.height * 4);
    out.reached.resize(out.height);
    std::vector<SliceShear> shears(g.slices);
    for (int k = 0; k < g.slices; ++k) shears[k] = shearOf(g, k, shiftX, shiftY, out.originX, out.originY);
    // A view from behind the stack meets its slices last to first.
    const bool backwards = dn < 0.0;
    // The path through one slice is 1 / cos(angle) slice spacings long.
    const double obliquity = 1.0 / std::abs(dn);
    const ValueLevels* levels = stack.valueLevels();
    if (stack.content() == StackContent::Colours) {
        const ColourLightTable light(*levels, obliquity);
        compositeBands(stack, shears, backwards, Compositing<ColourLightTable>{light, terminationOpacity, lanes}, out);
    } else if (levels && stack.classification() == Classification::Segments) {
        const SegmentLightTable light(*levels, obliquity);
        compositeBands(stack, shears, backwards, Compositing<SegmentLightTable>{light, terminationOpacity, lanes}, out);
    } else if (levels) {
        const ValueLightTable light(*levels, obliquity);
        compositeBands(stack, shears, backwards, Compositing<ValueLightTable>{light, terminationOpacity, lanes}, out);
    } else {
        const ObliquityTable oblique(obliquity);
        const ClassifiedLightTable light{oblique};
        compositeBands(stack, shears, backwards, Compositing<ClassifiedLightTable>{light, terminationOpacity, lanes},
                       out);
    }
    return out;
}

/// Where the camera's pixels meet the front slice of the stack, on @a intermediate.
IntermediateMap intermediateMap(const StackGeometry& g, const OrthoCamera& camera,
                                const IntermediateImage& intermediate) {
    const double dn = camera.direction.dot(g.normal);
    const auto onFront = [&](double x, double y) {
        // Follow the pixel's ray to the front slice; its position there, in samples.
        const Vec3d p = camera.pixelPoint(x, y);
        const Vec3d q = p + camera.direction * (g.normal.dot(g.origin - p) / dn) - g.origin;
        return openvdb::Vec2d(q.dot(g.e1) / g.sampleMm[0] - intermediate.originX,
                              q.dot(g.e2) / g.sampleMm[1] - intermediate.originY);
    };
    const openvdb::Vec2d origin = onFront(0, 0), alongX = onFront(1, 0) - origin, alongY = onFront(0, 1) - origin;
    return {origin[0], alongX[0], alongY[0], origin[1], alongX[1], alongY[1]};
}

}  // namespace

ShearWarpRenderer::ShearWarpRenderer(const RenderVolume& volume, const Classifier& classifier,
                                     const ShearWarpSettings& settings)
    : ShearWarpRenderer(std::vector<StackLayer>{{&volume, classifier}}, settings) {}

ShearWarpRenderer::ShearWarpRenderer(std::vector<StackLayer> layers, const ShearWarpSettings& settings)
    : mLayers(std::move(layers)), mSettings(settings) {}

Framebuffer ShearWarpRenderer::render(const OrthoCamera& camera, FrameStats* stats) {
    const auto start = std::chrono::steady_clock::now();
    FrameStats frame;
    frame.index = mFrames++;
    auto serving = std::find_if(mStacks.begin(), mStacks.end(), [&](const std::unique_ptr<SliceStack>& stack) {
        return mSettings.serves(stack->geometry().normal, camera.direction);
    });
    frame.reused = serving != mStacks.end();
    if (!frame.reused) {
        // A view stack serves only its cone: the next one replaces it.
        if (mSettings.stacks == StackOrientation::View) mStacks.clear();
        mStacks.push_back(std::make_unique<SliceStack>(
            mLayers, mSettings.stackNormalFor(camera.direction), mSettings.sliceSpacingVoxels,
            mSettings.sampleMmFor(camera, *mLayers.front().volume), ProgressFn{}, nullptr, StackSampling::Voxels,
            mSettings.segmentViews()));
        serving = std::prev(mStacks.end());
        frame.buildMs = millisecondsSince(start);
        frame.gaussiansTouched = (*serving)->gaussiansTouched();
    }
    Framebuffer image = mFramer.frame(**serving, camera, mSettings, frame);
    frame.totalMs = millisecondsSince(start);
    if (stats) *stats = frame;
    return image;
}

Framebuffer ShearWarpFramer::frame(const SliceStack& stack, const OrthoCamera& camera,
                                   const ShearWarpSettings& settings, FrameStats& stats) {
    const auto composited = std::chrono::steady_clock::now();
    IntermediateImage intermediate = compositeSlices(stack, camera.direction, settings, std::move(mIntermediate));
    stats.compositeMs = millisecondsSince(composited);

    const auto warped = std::chrono::steady_clock::now();
    Framebuffer image =
        warpToImage(intermediate, intermediateMap(stack.geometry(), camera, intermediate), camera.width, camera.height);
    stats.warpMs = millisecondsSince(warped);
    mIntermediate = std::move(intermediate.rgba);
    return image;
}

}  // namespace gvr
