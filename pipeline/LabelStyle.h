/// @file LabelStyle.h
/// @brief How one structure is drawn when the user overrides its colour or opacity.
#pragma once

#include "pipeline/TransferFunction.h"

#include <array>
#include <optional>

namespace gvr {

struct LabelStyle {
    std::optional<std::array<float, 3>> colour;  ///< each in [0, 1]; unset: the transfer function's
    float opacity = 1.0f;                        ///< scales the transfer function's opacity; >= 0
};

/// @a base with every point's colour replaced by the style's (if any) and its
/// opacity scaled (clamped to 1), so that the structure keeps the base's window.
TransferFunction styledTransferFunction(const TransferFunction& base, const LabelStyle& style);

}  // namespace gvr
