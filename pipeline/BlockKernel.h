/// @file BlockKernel.h
/// @brief One Gaussian's kernel exp(-q/2) over one 8^3 block, a row along z at a
/// time: the one kernel that the fit's block loss (forward and backward) and the
/// lattice sampler (export and the renderer's stacks) evaluate.
#pragma once

#include "pipeline/Block.h"
#include "pipeline/FastExp.h"

namespace gvr {

/// One Gaussian's q = (x - mean)^T Sigma^-1 (x - mean) over one block, as a quadratic
/// in r, a position relative to the block's origin: q = h + 2 gLin.r + r^T G r. The
/// lattice sampler and the fit's block loss each fill it for their own r.
struct BlockQuadratic {
    double G[3][3], gLin[3], h;
};

/// q along one row (x, y) of a block, as q(z) = zz (z - zCentre)^2 + qMin: in this
/// form float keeps q accurate near the ellipsoid, where the terms would cancel.
struct RowParabola {
    float zz, zCentre, qMin;
};

/// Calls visit(x, y, row) for each row that the ellipsoid q <= cutoff2 crosses, with
/// x from @a xFirst to @a xLast and y from firstY(x) to @a yLast in steps of
/// @a yStride, both relative to the block's origin as the quadratic's r is.
template <typename FirstY, typename Visit>
__attribute__((always_inline)) inline void forEachRowCrossed(const BlockQuadratic& quad, int xFirst, int xLast,
                                                             const FirstY& firstY, int yLast, int yStride,
                                                             float cutoff2, const Visit& visit) {
    const double(&G)[3][3] = quad.G;
    const double inverseZz = 1.0 / G[2][2];
    const float zz = float(G[2][2]);
    for (int x = xFirst; x <= xLast; ++x) {
        // What the rows of this x share: q's terms in y are linear and quadratic in y.
        const double zLinearX = 2.0 * (G[0][2] * x + quad.gLin[2]), zLinearY = 2.0 * G[1][2];
        const double constantX = quad.h + 2.0 * quad.gLin[0] * x + G[0][0] * x * x;
        const double constantY = 2.0 * (quad.gLin[1] + G[0][1] * x);
        for (int y = firstY(x); y <= yLast; y += yStride) {
            const double zLinear = zLinearX + zLinearY * y;
            const double qMin = constantX + y * (constantY + G[1][1] * y) - 0.25 * zLinear * zLinear * inverseZz;
            if (qMin > cutoff2) continue;  // the row misses the ellipsoid
            visit(x, y, RowParabola{zz, float(-0.5 * zLinear * inverseZz), float(qMin)});
        }
    }
}

/// q at the row's samples z = part to part + lanes - 1, in lanes of Floats: Floats4,
/// or Floats8 in code compiled for AVX2.
template <typename Floats>
__attribute__((always_inline)) inline Floats rowQ(const RowParabola& row, int part) {
    constexpr int kLanes = sizeof(Floats) / sizeof(float);
    Floats z;
    for (int i = 0; i < kLanes; ++i) z[i] = float(i);
    // lane + part is exact, so each sample's dz rounds once, whatever the lanes.
    const Floats dz = (z + float(part)) - row.zCentre;
    return row.zz * dz * dz + row.qMin;
}

/// The kernel exp(-q/2) where @a keep is set, and 0 elsewhere.
template <typename Floats, typename Ints>
__attribute__((always_inline)) inline Floats kernelWhere(const Floats& q, const Ints& keep) {
    return (Floats)((Ints)expNonPositive(-0.5f * q) & keep);
}

}  // namespace gvr
