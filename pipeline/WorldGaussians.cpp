#include "pipeline/WorldGaussians.h"

#include "pipeline/GaussianKernel.h"

#include <algorithm>
#include <cmath>

namespace gvr {

namespace {

using openvdb::math::Mat3d;

/// Column-vector linear map of OpenVDB's row-vector matrix: world = L index.
Mat3d linearPart(const openvdb::math::Mat4d& worldFromIndex) { return worldFromIndex.getMat3().transpose(); }

Mat3d indexCovariance(const ActiveGaussian& g) {
    Mat3d r, s = Mat3d::zero();
    for (int row = 0; row < 3; ++row) {
        for (int column = 0; column < 3; ++column) r(row, column) = g.rotation[3 * row + column];
        s(row, row) = 1.0 / double(g.invVariance[row]);
    }
    return r * s * r.transpose();
}

/// The unit quaternion (w, x, y, z), w >= 0, of rotation @a r (column vectors:
/// v' = r v), by the largest of its four squared components (Shepperd).
std::array<double, 4> quaternionOf(const Mat3d& r) {
    const double trace = r(0, 0) + r(1, 1) + r(2, 2);
    std::array<double, 4> q;
    if (trace > 0.0) {
        const double s = 2.0 * std::sqrt(1.0 + trace);
        q = {0.25 * s, (r(2, 1) - r(1, 2)) / s, (r(0, 2) - r(2, 0)) / s, (r(1, 0) - r(0, 1)) / s};
    } else if (r(0, 0) > r(1, 1) && r(0, 0) > r(2, 2)) {
        const double s = 2.0 * std::sqrt(1.0 + r(0, 0) - r(1, 1) - r(2, 2));
        q = {(r(2, 1) - r(1, 2)) / s, 0.25 * s, (r(0, 1) + r(1, 0)) / s, (r(0, 2) + r(2, 0)) / s};
    } else if (r(1, 1) > r(2, 2)) {
        const double s = 2.0 * std::sqrt(1.0 + r(1, 1) - r(0, 0) - r(2, 2));
        q = {(r(0, 2) - r(2, 0)) / s, (r(0, 1) + r(1, 0)) / s, 0.25 * s, (r(1, 2) + r(2, 1)) / s};
    } else {
        const double s = 2.0 * std::sqrt(1.0 + r(2, 2) - r(0, 0) - r(1, 1));
        q = {(r(1, 0) - r(0, 1)) / s, (r(0, 2) + r(2, 0)) / s, (r(1, 2) + r(2, 1)) / s, 0.25 * s};
    }
    const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    const double sign = q[0] < 0.0 ? -1.0 : 1.0;
    for (double& component : q) component *= sign / norm;
    return q;
}

WorldGaussian inTheWorld(const ActiveGaussian& g, const GaussianAsset& asset, const Mat3d& linear) {
    WorldGaussian out{};
    const openvdb::Vec3d mean = asset.worldFromIndex.transform(openvdb::Vec3d(g.mean[0], g.mean[1], g.mean[2]));
    out.mean = {mean[0], mean[1], mean[2]};
    Mat3d axes;
    openvdb::Vec3d variances;
    openvdb::math::diagonalizeSymmetricMatrix(linear * indexCovariance(g) * linear.transpose(), axes, variances);
    // Ascending scales, axes as right-handed columns.
    int order[3] = {0, 1, 2};
    std::sort(order, order + 3, [&](int a, int b) { return variances[a] < variances[b]; });
    Mat3d sorted;
    for (int a = 0; a < 3; ++a) {
        out.scale[a] = std::sqrt(std::max(variances[order[a]], 0.0));
        for (int row = 0; row < 3; ++row) sorted(row, a) = axes(row, order[a]);
    }
    if (sorted.det() < 0.0) {
        for (int row = 0; row < 3; ++row) sorted(row, 2) = -sorted(row, 2);
    }
    out.rotation = quaternionOf(sorted);
    for (int c = 0; c < 3; ++c)
        out.amplitude[c] = c < asset.params.channels ? asset.mapping.scale * g.amplitude[c] : 0.0;
    return out;
}

}  // namespace

std::vector<WorldGaussian> worldGaussians(const GaussianAsset& asset) {
    const Mat3d linear = linearPart(asset.worldFromIndex);
    std::vector<WorldGaussian> out;
    out.reserve(asset.params.count());
    for (std::size_t i = 0; i < asset.params.count(); ++i)
        out.push_back(inTheWorld(activate(asset.params, i), asset, linear));
    return out;
}

}  // namespace gvr
