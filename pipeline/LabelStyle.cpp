#include "pipeline/LabelStyle.h"

#include <algorithm>

namespace gvr {

TransferFunction styledTransferFunction(const TransferFunction& base, const LabelStyle& style) {
    std::vector<TransferPoint> points = base.points();
    for (TransferPoint& p : points) {
        if (style.colour) std::copy(style.colour->begin(), style.colour->end(), p.rgba.begin());
        p.rgba[3] = std::min(1.0f, p.rgba[3] * style.opacity);
    }
    return TransferFunction(std::move(points), "label style");
}

}  // namespace gvr
