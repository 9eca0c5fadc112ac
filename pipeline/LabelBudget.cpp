#include "pipeline/LabelBudget.h"

#include "pipeline/Error.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace gvr {

std::vector<std::size_t> splitBudget(std::size_t total, const std::vector<std::uint64_t>& voxels, std::size_t floor) {
    std::vector<std::size_t> budget(voxels.size());
    std::size_t floors = 0;
    for (std::size_t s = 0; s < voxels.size(); ++s)
        floors += budget[s] = std::size_t(std::min<std::uint64_t>(floor, voxels[s]));
    if (floors > total) {
        throw InputError("`gaussians`", std::to_string(total) + " Gaussians cannot give " +
                                            std::to_string(voxels.size()) + " structures their floor of " +
                                            std::to_string(floor) + " each");
    }
    const double allVoxels = double(std::accumulate(voxels.begin(), voxels.end(), std::uint64_t(0)));
    const std::size_t rest = total - floors;
    std::vector<double> remainder(voxels.size(), 0.0);
    std::size_t given = 0;
    for (std::size_t s = 0; s < voxels.size() && allVoxels > 0; ++s) {
        const double share = double(rest) * double(voxels[s]) / allVoxels;
        budget[s] += std::size_t(share);
        given += std::size_t(share);
        remainder[s] = share - std::floor(share);
    }
    std::vector<std::size_t> order(voxels.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return remainder[a] > remainder[b]; });
    for (std::size_t k = 0; given < rest && !order.empty(); ++k, ++given) ++budget[order[k % order.size()]];
    return budget;
}

std::vector<std::size_t> proportionalBudgets(double gaussiansPerVoxel, const std::vector<std::uint64_t>& voxels,
                                             std::size_t floor) {
    std::vector<std::size_t> budget;
    for (std::uint64_t v : voxels) {
        const auto proportional = std::size_t(std::llround(gaussiansPerVoxel * double(v)));
        budget.push_back(std::max(proportional, std::size_t(std::min<std::uint64_t>(floor, v))));
    }
    return budget;
}

}  // namespace gvr
