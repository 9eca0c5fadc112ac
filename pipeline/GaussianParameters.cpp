#include "pipeline/GaussianParameters.h"

#include <algorithm>
#include <cmath>

namespace gvr {

int groupWidth(ParameterGroup group, int channels) {
    switch (group) {
        case kMeans:
            return 3;
        case kRotations:
            return 4;
        case kLogScales:
            return 3;
        case kOpacityLogits:
            return 1;
        default:
            break;
    }
    return channels;
}

const char* groupName(ParameterGroup group) {
    static const char* names[kGroupCount] = {"means", "rotations", "log_scales", "opacity_logits", "colours"};
    return names[group];
}

GaussianParameters::GaussianParameters(std::size_t count, int channelCount) : channels(channelCount) {
    for (int g = 0; g < kGroupCount; ++g) values[g].assign(count * width(ParameterGroup(g)), 0.0f);
}

void GaussianParameters::setZero() {
    for (auto& group : values) std::fill(group.begin(), group.end(), 0.0f);
}

void GaussianParameters::keepOnly(const std::vector<bool>& keep) {
    for (int g = 0; g < kGroupCount; ++g) {
        const std::size_t w = std::size_t(width(ParameterGroup(g)));
        std::vector<float>& group = values[g];
        std::size_t kept = 0;
        for (std::size_t i = 0; i < keep.size(); ++i) {
            if (!keep[i]) continue;
            std::copy_n(group.begin() + i * w, w, group.begin() + kept * w);
            ++kept;
        }
        group.resize(kept * w);
    }
}

void GaussianParameters::permute(const std::vector<std::uint32_t>& order) {
    for (int g = 0; g < kGroupCount; ++g) {
        const std::size_t w = std::size_t(width(ParameterGroup(g)));
        std::vector<float> moved(values[g].size());
        for (std::size_t k = 0; k < order.size(); ++k) {
            std::copy_n(values[g].begin() + order[k] * w, w, moved.begin() + k * w);
        }
        values[g].swap(moved);
    }
}

void GaussianParameters::append(const GaussianParameters& more) {
    for (int g = 0; g < kGroupCount; ++g)
        values[g].insert(values[g].end(), more.values[g].begin(), more.values[g].end());
}

void GaussianParameters::add(const GaussianParameters& other) {
    for (int g = 0; g < kGroupCount; ++g) {
        std::vector<float>& group = values[g];
        const std::vector<float>& addend = other.values[g];
        for (std::size_t k = 0; k < group.size(); ++k) group[k] += addend[k];
    }
}

bool GaussianParameters::allFinite() const {
    for (const auto& group : values) {
        for (float v : group) {
            if (!std::isfinite(v)) return false;
        }
    }
    return true;
}

}  // namespace gvr
