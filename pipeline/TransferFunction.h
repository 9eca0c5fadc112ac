/// @file TransferFunction.h
/// @brief A piecewise-linear map from a scalar in physical units (HU, intensity,
/// luminance) to colour and opacity, shared by export and every renderer.
#pragma once

#include <array>
#include <string>
#include <vector>

namespace gvr {

struct TransferPoint {
    double value = 0.0;                     ///< physical units
    std::array<float, 4> rgba{0, 0, 0, 0};  ///< each in [0, 1]
};

class TransferFunction {
public:
    /// @param points at least one, values strictly increasing and finite, rgba in [0, 1]
    /// @throw InputError naming @a culprit (a file or preset) when they are not.
    TransferFunction(std::vector<TransferPoint> points, const std::string& culprit);

    /// Linear between neighbouring points; the end points' values beyond them.
    std::array<float, 4> operator()(double value) const;

    const std::vector<TransferPoint>& points() const { return mPoints; }

    /// The largest value up to which the opacity is 0 everywhere (-infinity when it
    /// is not 0 even far below the first point): renderers skip what stays below it.
    double transparentUpTo() const;

private:
    std::vector<TransferPoint> mPoints;
};

}  // namespace gvr
