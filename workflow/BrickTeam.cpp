#include "workflow/BrickTeam.h"

#include <tbb/task_arena.h>

#include <algorithm>
#include <numeric>

namespace gvr {

std::vector<int> BrickTeam::owners(const std::vector<Brick>& bricks) const {
    std::vector<std::size_t> order(bricks.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return bricks[a].budget > bricks[b].budget; });
    std::vector<std::size_t> load(std::size_t(size()), 0);
    std::vector<int> owner(bricks.size(), 0);
    for (std::size_t b : order) {
        const auto least = std::min_element(load.begin(), load.end());
        owner[b] = int(least - load.begin());
        *least += bricks[b].budget;
    }
    return owner;
}

std::size_t SoloTeam::threadsPerRank() const { return std::size_t(tbb::this_task_arena::max_concurrency()); }

std::vector<BrickOutcome> SoloTeam::gather(std::vector<BrickOutcome> mine, const std::vector<int>& owners) const {
    std::vector<BrickOutcome> all(owners.size());
    for (BrickOutcome& outcome : mine) all[outcome.brick] = std::move(outcome);
    return all;
}

}  // namespace gvr
