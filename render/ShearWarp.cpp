#include "ShearWarp.h"

#include <tbb/parallel_for.h>

#include <chrono>
#include <cmath>

namespace gvr {

using openvdb::Vec3d;

namespace {

double millisecondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

/// Opacity and colour factor for a path 1/cos(angle) slices long, per 16-bit
/// opacity level: the view may cross the slices obliquely when the stack is reused.
struct ObliquityTable {
    std::vector<float> opacity, colourFactor;
    explicit ObliquityTable(double lengthRatio) : opacity(65536), colourFactor(65536, 1.0f) {
        // ln(1 - alpha) per level never changes, so each frame needs one exp a level:
        // 1 - (1 - alpha)^r = 1 - exp(r ln(1 - alpha)).
        static const std::vector<double> logTransmittance = [] {
            std::vector<double> table(65536);
            for (int level = 0; level < 65536; ++level) table[level] = std::log1p(-level / 65535.0);
            return table;
        }();
        for (int level = 0; level < 65536; ++level) {
            opacity[level] = float(1.0 - std::exp(lengthRatio * logTransmittance[level]));
            if (level > 0) colourFactor[level] = opacity[level] * 65535.0f / level;
        }
    }
};

/// One slice row as seen through a run: zero outside it.
struct RowView {
    const StackSample* samples = nullptr;
    int begin = 0, end = 0;
    const StackSample* at(int x) const { return x >= begin && x < end ? samples + (x - begin) : nullptr; }
};

RowView rowView(const Slice& slice, int row, int height) {
    if (row < 0 || row >= height) return {};
    const RowRun& run = slice.rows[row];
    return {slice.samples.data() + run.offset, int(run.begin), int(run.end)};
}

void addWeighted(const StackSample* s, float w, float* sum) {
    if (!s || w == 0.0f) return;
    sum[0] += w * s->r;
    sum[1] += w * s->g;
    sum[2] += w * s->b;
    sum[3] += w * s->a;
}

/// The intermediate image: the slices sheared for a direction and composited front
/// to back, in the stack's plane.
struct Intermediate {
    int width = 0, height = 0;
    int originX = 0, originY = 0;  ///< stack sample coordinates of pixel (0, 0)
    std::vector<float> rgba;       ///< premultiplied
};

}  // namespace

std::string ShearWarpSettings::validate() const {
    // Below a twentieth of a voxel the stack would hold thousands of slices per voxel row.
    if (!(sliceSpacingVoxels >= 0.05) || sliceSpacingVoxels > 64.0) return "--slice-spacing must be in [0.05, 64] voxels";
    if (!(reuseAngleDeg >= 0.0 && reuseAngleDeg <= 60.0)) return "--reuse-angle must be between 0 and 60 degrees";
    if (!(terminationOpacity > 0.0f && terminationOpacity <= 1.0f)) return "--termination must be in (0, 1]";
    return {};
}

namespace {

Intermediate compositeSlices(const SliceStack& stack, const Vec3d& direction, float terminationOpacity) {
    const StackGeometry& g = stack.geometry();
    const double dn = direction.dot(g.normal);
    // Moving one slice back shifts the ray this far across the slices, in samples.
    const double shiftX = direction.dot(g.e1) / dn * g.sliceMm / g.pixelMm;
    const double shiftY = direction.dot(g.e2) / dn * g.sliceMm / g.pixelMm;
    const double lastX = shiftX * (g.slices - 1), lastY = shiftY * (g.slices - 1);
    Intermediate out;
    out.originX = int(std::floor(std::min(0.0, -lastX))) - 1;
    out.originY = int(std::floor(std::min(0.0, -lastY))) - 1;
    out.width = int(std::ceil(std::max(0.0, -lastX))) + g.width + 1 - out.originX;
    out.height = int(std::ceil(std::max(0.0, -lastY))) + g.height + 1 - out.originY;
    out.rgba.assign(std::size_t(out.width) * out.height * 4, 0.0f);
    const ObliquityTable table(1.0 / dn);
    const float scale = 1.0f / 65535.0f;

    tbb::parallel_for(0, out.height, [&](int row) {
        float* pixels = out.rgba.data() + std::size_t(row) * out.width * 4;
        const int y = row + out.originY;
        for (int k = 0; k < g.slices; ++k) {
            const Slice& slice = stack.slices()[k];
            const double sy = y + k * shiftY, sx = k * shiftX;
            const int jy = int(std::floor(sy)), ix = int(std::floor(sx));
            const float fy = float(sy - jy), fx = float(sx - ix);
            const RowView upper = rowView(slice, jy, g.height), lower = rowView(slice, jy + 1, g.height);
            int first = INT32_MAX, last = INT32_MIN;  // pixels that see either row's run
            for (const RowView* r : {&upper, &lower}) {
                if (r->begin >= r->end) continue;
                first = std::min(first, r->begin - 1 - ix - out.originX);
                last = std::max(last, r->end - 1 - ix - out.originX);
            }
            first = std::max(first, 0);
            last = std::min(last, out.width - 1);
            for (int p = first; p <= last; ++p) {
                float* pixel = pixels + std::size_t(p) * 4;
                if (pixel[3] >= terminationOpacity) continue;
                const int x = p + out.originX + ix;
                float sum[4] = {0, 0, 0, 0};
                addWeighted(upper.at(x), (1 - fx) * (1 - fy), sum);
                addWeighted(upper.at(x + 1), fx * (1 - fy), sum);
                addWeighted(lower.at(x), (1 - fx) * fy, sum);
                addWeighted(lower.at(x + 1), fx * fy, sum);
                if (sum[3] <= 0.0f) continue;
                const int level = std::min(65535, int(sum[3] + 0.5f));
                const float alpha = table.opacity[level], factor = table.colourFactor[level] * scale;
                const float transmit = 1.0f - pixel[3];
                for (int c = 0; c < 3; ++c) pixel[c] += transmit * sum[c] * factor;
                pixel[3] += transmit * alpha;
            }
        }
    });
    return out;
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
    frame.reused = mStack && angleBetweenDeg(camera.direction, mStack->geometry().normal) <= mSettings.reuseAngleDeg;
    if (!frame.reused) {
        // Samples finer than the image's pixels would only be averaged away by the warp.
        mStack = std::make_unique<SliceStack>(mLayers, camera.direction, mSettings.sliceSpacingVoxels, camera.pixelMm);
        frame.buildMs = millisecondsSince(start);
        frame.gaussiansTouched = mStack->gaussiansTouched();
    }
    Framebuffer image = shearWarpFrame(*mStack, camera, mSettings.terminationOpacity, frame);
    frame.totalMs = millisecondsSince(start);
    if (stats) *stats = frame;
    return image;
}

Framebuffer shearWarpFrame(const SliceStack& stack, const OrthoCamera& camera, float terminationOpacity,
                           FrameStats& stats) {
    const auto composited = std::chrono::steady_clock::now();
    const Intermediate intermediate = compositeSlices(stack, camera.direction, terminationOpacity);
    stats.compositeMs = millisecondsSince(composited);

    const auto warped = std::chrono::steady_clock::now();
    const StackGeometry& g = stack.geometry();
    const double dn = camera.direction.dot(g.normal);
    Framebuffer image(camera.width, camera.height);
    tbb::parallel_for(0, camera.height, [&](int y) {
        for (int x = 0; x < camera.width; ++x) {
            // Follow the pixel's ray to the front slice; its position there, in samples.
            const Vec3d p = camera.pixelPoint(x, y);
            const Vec3d onFront = p + camera.direction * (g.normal.dot(g.origin - p) / dn) - g.origin;
            const double u = onFront.dot(g.e1) / g.pixelMm - intermediate.originX;
            const double v = onFront.dot(g.e2) / g.pixelMm - intermediate.originY;
            const int i = int(std::floor(u)), j = int(std::floor(v));
            if (i < 0 || j < 0 || i + 1 >= intermediate.width || j + 1 >= intermediate.height) continue;
            const float fu = float(u - i), fv = float(v - j);
            const float* a = intermediate.rgba.data() + (std::size_t(j) * intermediate.width + i) * 4;
            const float* b = a + std::size_t(intermediate.width) * 4;
            float* out = image.pixel(x, y);
            for (int c = 0; c < 4; ++c) {
                out[c] = (1 - fv) * ((1 - fu) * a[c] + fu * a[c + 4]) + fv * ((1 - fu) * b[c] + fu * b[c + 4]);
            }
        }
    });
    stats.warpMs = millisecondsSince(warped);
    return image;
}

}  // namespace gvr
