#include "examples/VolPackReference.h"

#include <volpack.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>

namespace gvr {
namespace {

// VolPack's working voxel, filled by vpClassifyScalars from the 8-bit scalars: an encoded
// surface normal (indexes the shading table) and the two classification parameters.
// The normal comes first because shading fields must be a voxel's first fields.
struct Voxel {
    std::uint16_t normal;
    std::uint8_t scalar;
    std::uint8_t gradient;
};
constexpr int kNormalField = 0, kScalarField = 1, kGradientField = 2;
constexpr int kScalarParam = 0, kGradientParam = 1;  // factors of the opacity product

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// A VolPack context and the tables it reads. VolPack keeps pointers to these tables and
// to the image without copying them, so they must live exactly as long as the context.
class Session {
public:
    Session() : mContext(vpCreateContext()) {
        if (!mContext) throw std::runtime_error("VolPack: vpCreateContext failed");
    }
    ~Session() { vpDestroyContext(mContext); }  // also frees the classified volume
    Session(const Session&) = delete;
    Session& operator=(const Session&) = delete;

    vpContext* context() { return mContext; }

    void check(vpResult result, const char* call) {
        if (result != VP_OK) {
            throw std::runtime_error(std::string("VolPack: ") + call +
                                     " failed: " + vpGetErrorString(vpGetError(mContext)));
        }
    }

    std::array<float, VP_SCALAR_MAX + 1> scalarRamp{};
    std::array<float, VP_GRAD_MAX + 1> gradientRamp{};
    std::array<float, VP_NORM_MAX + 1> shadeTable{};  // one grey value per normal, one material
    std::vector<std::uint8_t> image;

private:
    vpContext* mContext;
};

void validate(const VolPackVolume& volume, int width, int height, int frames,
              const std::vector<float>& opacityByValue) {
    if (!opacityByValue.empty() && opacityByValue.size() != VP_SCALAR_MAX + 1) {
        throw std::invalid_argument("VolPack: the opacity table needs one entry per 8-bit value");
    }
    const long long count = 1LL * volume.nx * volume.ny * volume.nz;
    if (volume.nx < 3 || volume.ny < 3 || volume.nz < 3 || volume.nx > VP_MAX_VOLUME_DIM ||
        volume.ny > VP_MAX_VOLUME_DIM || volume.nz > VP_MAX_VOLUME_DIM || count > INT_MAX) {
        throw std::invalid_argument("VolPack: each volume side must be 3.." + std::to_string(VP_MAX_VOLUME_DIM));
    }
    if (volume.voxels.size() != std::size_t(count)) {
        throw std::invalid_argument("VolPack: voxels.size() must be nx*ny*nz");
    }
    for (double s : volume.spacingMm) {
        if (!(s > 0.0) || !std::isfinite(s)) throw std::invalid_argument("VolPack: spacing must be positive");
    }
    if (width < 1 || height < 1 || frames < 1) {
        throw std::invalid_argument("VolPack: width, height and frames must be positive");
    }
}

// Builds VolPack's run-length encoded, classified volume: opacity = scalar table x gradient ramp.
void classify(Session& s, const VolPackVolume& volume, const std::vector<float>& opacityByValue) {
    vpContext* ctx = s.context();
    s.check(vpSetVolumeSize(ctx, volume.nx, volume.ny, volume.nz), "vpSetVolumeSize");
    s.check(vpSetVoxelSize(ctx, sizeof(Voxel), 3, 1, 2), "vpSetVoxelSize");  // 3 fields: 1 shades, 2 classify
    s.check(vpSetVoxelField(ctx, kNormalField, sizeof(Voxel::normal), offsetof(Voxel, normal), VP_NORM_MAX),
            "vpSetVoxelField(normal)");
    s.check(vpSetVoxelField(ctx, kScalarField, sizeof(Voxel::scalar), offsetof(Voxel, scalar), VP_SCALAR_MAX),
            "vpSetVoxelField(scalar)");
    s.check(vpSetVoxelField(ctx, kGradientField, sizeof(Voxel::gradient), offsetof(Voxel, gradient), VP_GRAD_MAX),
            "vpSetVoxelField(gradient)");

    if (opacityByValue.empty()) {
        // Scalar ramp: transparent at 0, opaque from 24 of 255 (the gvr issue's classification).
        int scalarX[] = {0, 24, VP_SCALAR_MAX};
        float scalarY[] = {0.0f, 1.0f, 1.0f};
        s.check(vpRamp(s.scalarRamp.data(), sizeof(float), 3, scalarX, scalarY), "vpRamp(scalar)");
        // Gradient ramp from the VolPack examples: flat regions vanish, so surfaces show.
        int gradientX[] = {0, 5, 20, VP_GRAD_MAX};
        float gradientY[] = {0.0f, 0.0f, 1.0f, 1.0f};
        s.check(vpRamp(s.gradientRamp.data(), sizeof(float), 4, gradientX, gradientY), "vpRamp(gradient)");
    } else {
        // The caller's table alone: the gradient factor is 1 everywhere.
        std::copy(opacityByValue.begin(), opacityByValue.end(), s.scalarRamp.begin());
        s.gradientRamp.fill(1.0f);
    }
    s.check(vpSetClassifierTable(ctx, kScalarParam, kScalarField, s.scalarRamp.data(), sizeof(s.scalarRamp)),
            "vpSetClassifierTable(scalar)");
    s.check(vpSetClassifierTable(ctx, kGradientParam, kGradientField, s.gradientRamp.data(), sizeof(s.gradientRamp)),
            "vpSetClassifierTable(gradient)");
    // Voxels below this opacity are left out of the run-length encoding altogether; with
    // the caller's table, only those gvr's 16-bit stacks would drop too.
    const double minimumOpacity = opacityByValue.empty() ? 0.05 : 1.0 / 65535.0;
    s.check(vpSetd(ctx, VP_MIN_VOXEL_OPACITY, minimumOpacity), "vpSetd(VP_MIN_VOXEL_OPACITY)");

    // Computes gradients and normals and classifies in one pass, without a full Voxel array.
    // VolPack only reads the scalars; its C signature just lacks the const.
    auto* scalars = const_cast<unsigned char*>(volume.voxels.data());
    s.check(vpClassifyScalars(ctx, scalars, int(volume.voxels.size()), kScalarField, kGradientField, kNormalField),
            "vpClassifyScalars");
}

// One grey Phong material and one light, as in VolPack's rendervolume example.
void setUpShadingAndImage(Session& s, int width, int height) {
    vpContext* ctx = s.context();
    s.check(vpSetLookupShader(ctx, 1, 1, kNormalField, s.shadeTable.data(), sizeof(s.shadeTable), 0, nullptr, 0),
            "vpSetLookupShader");
    s.check(vpSetMaterial(ctx, VP_MATERIAL0, VP_AMBIENT, VP_BOTH_SIDES, 0.18, 0.18, 0.18), "vpSetMaterial");
    s.check(vpSetMaterial(ctx, VP_MATERIAL0, VP_DIFFUSE, VP_BOTH_SIDES, 0.35, 0.35, 0.35), "vpSetMaterial");
    s.check(vpSetMaterial(ctx, VP_MATERIAL0, VP_SPECULAR, VP_BOTH_SIDES, 0.39, 0.39, 0.39), "vpSetMaterial");
    s.check(vpSetMaterial(ctx, VP_MATERIAL0, VP_SHINYNESS, VP_BOTH_SIDES, 10.0, 0.0, 0.0), "vpSetMaterial");
    // The direction the light travels, in eye space (x right, y up, z away from the viewer;
    // see setView): from the viewer's upper left. It goes through the model matrix current at
    // this call, still the identity, so the light stays fixed relative to the viewer.
    s.check(vpSetLight(ctx, VP_LIGHT0, VP_DIRECTION, 0.3, -0.3, 1.0), "vpSetLight");
    s.check(vpSetLight(ctx, VP_LIGHT0, VP_COLOR, 1.0, 1.0, 1.0), "vpSetLight");
    s.check(vpEnable(ctx, VP_LIGHT0, 1), "vpEnable(VP_LIGHT0)");
    s.check(vpSetd(ctx, VP_MAX_RAY_OPACITY, 0.95), "vpSetd(VP_MAX_RAY_OPACITY)");  // early ray termination

    s.image.assign(std::size_t(width) * height, 0);
    s.check(vpSetImage(ctx, s.image.data(), width, height, width, VP_LUMINANCE), "vpSetImage");
}

// The camera of gvr's OrthoCamera (render/Camera.cpp), in the volume's index axes: azimuth 0
// looks from +y, azimuth turns the camera towards +x about z, elevation lifts it towards +z,
// and z is up in the image. Unit vectors, in millimetres of the volume.
struct ViewAxes {
    double right[3], up[3], back[3];  // back points from the volume to the eye
};

ViewAxes viewAxes(double azimuthDeg, double elevationDeg) {
    const double az = azimuthDeg * M_PI / 180.0, el = elevationDeg * M_PI / 180.0;
    return {{-std::cos(az), std::sin(az), 0.0},
            {-std::sin(az) * std::sin(el), -std::cos(az) * std::sin(el), std::cos(el)},
            {std::cos(el) * std::sin(az), std::cos(el) * std::cos(az), std::sin(el)}};
}

// Sets VolPack's model matrix (object to eye) and an orthographic window that fits this
// view's projected volume corners with a 2 % margin, as gvr's camera does.
// Pitfall: VolPack's manual puts the viewer at eye +z looking down -z, but its compositing
// treats eye -z as the near side (a test slab in front of a cube hid the cube). So eye z
// points away from the viewer here; image x and y are as documented.
void setView(Session& s, const VolPackVolume& volume, const ViewAxes& view, int width, int height) {
    // VolPack's object space holds the volume centred, its longest side in voxels spanning 1:
    // scaling by that voxel count times the spacing gives millimetres, anisotropy included.
    const double n[3] = {double(volume.nx), double(volume.ny), double(volume.nz)};
    const double maxVoxels = std::max({n[0], n[1], n[2]});
    vpMatrix4 model = {};
    double halfMm[3], radius = 0.0;
    for (int axis = 0; axis < 3; ++axis) {
        const double scale = maxVoxels * volume.spacingMm[axis];
        model[0][axis] = view.right[axis] * scale;  // eye x: right
        model[1][axis] = view.up[axis] * scale;     // eye y: up
        model[2][axis] = -view.back[axis] * scale;  // eye z: away from the viewer (see above)
        halfMm[axis] = 0.5 * n[axis] * volume.spacingMm[axis];
        radius += halfMm[axis] * halfMm[axis];
    }
    model[3][3] = 1.0;
    radius = std::sqrt(radius);

    // A corner's extent along a screen axis is at most the sum of the half sides' projections.
    double halfRight = 0.0, halfUp = 0.0;
    for (int axis = 0; axis < 3; ++axis) {
        halfRight += std::abs(view.right[axis]) * halfMm[axis];
        halfUp += std::abs(view.up[axis]) * halfMm[axis];
    }
    const double pixelMm = 1.02 * std::max(2.0 * halfRight / width, 2.0 * halfUp / height);
    const double halfWidth = 0.5 * width * pixelMm, halfHeight = 0.5 * height * pixelMm;

    vpContext* ctx = s.context();
    s.check(vpCurrentMatrix(ctx, VP_PROJECT), "vpCurrentMatrix(VP_PROJECT)");
    s.check(vpIdentityMatrix(ctx), "vpIdentityMatrix");  // vpWindow multiplies, so start afresh
    s.check(vpWindow(ctx, VP_PARALLEL, -halfWidth, halfWidth, -halfHeight, halfHeight, -radius, radius), "vpWindow");
    s.check(vpCurrentMatrix(ctx, VP_MODEL), "vpCurrentMatrix(VP_MODEL)");
    s.check(vpSetMatrix(ctx, model), "vpSetMatrix");
}

}  // namespace

VolPackResult renderWithVolPack(const VolPackVolume& volume, int width, int height, int frames, double stepDeg,
                                double elevationDeg, const std::vector<float>& opacityByValue) {
    validate(volume, width, height, frames, opacityByValue);
    Session session;
    VolPackResult result;

    const auto classifyStart = Clock::now();
    classify(session, volume, opacityByValue);
    result.classifySeconds = secondsSince(classifyStart);

    setUpShadingAndImage(session, width, height);
    const auto renderStart = Clock::now();
    for (int frame = 0; frame < frames; ++frame) {
        setView(session, volume, viewAxes(frame * stepDeg, elevationDeg), width, height);
        // The normals turn with the view while the light stays put: the table changes each frame.
        session.check(vpShadeTable(session.context()), "vpShadeTable");
        session.check(vpRenderClassifiedVolume(session.context()), "vpRenderClassifiedVolume");
    }
    result.framesPerSecond = frames / secondsSince(renderStart);
    result.frames = frames;

    // VolPack's image row 0 is the bottom (its viewport maps y = -1 to row 0); ours is the top.
    result.lastImage.resize(session.image.size());
    for (int row = 0; row < height; ++row) {
        std::copy_n(session.image.begin() + std::size_t(height - 1 - row) * width, width,
                    result.lastImage.begin() + std::size_t(row) * width);
    }
    return result;
}

}  // namespace gvr
