#include "pipeline/LabelledFit.h"

#include <algorithm>
#include <map>

namespace gvr {

namespace {

/// @a image with only @a voxels active and holding their values; background elsewhere.
template <typename GridT>
openvdb::GridBase::Ptr maskedCopy(const GridT& image, const std::vector<openvdb::Coord>& voxels) {
    typename GridT::Ptr masked = image.copyWithNewTree();  // same transform, metadata and background
    auto from = image.getConstAccessor();
    auto to = masked->getAccessor();
    for (const openvdb::Coord& ijk : voxels) to.setValueOn(ijk, from.getValue(ijk));
    return masked;
}

openvdb::GridBase::Ptr structureGrid(const openvdb::GridBase& image, const std::vector<openvdb::Coord>& voxels) {
    if (const auto* grey = dynamic_cast<const openvdb::FloatGrid*>(&image)) return maskedCopy(*grey, voxels);
    return maskedCopy(dynamic_cast<const openvdb::Vec3SGrid&>(image), voxels);
}

std::map<int, std::vector<openvdb::Coord>> voxelsByLabel(const openvdb::Int32Grid& labels,
                                                         const std::vector<int>& ids) {
    std::map<int, std::vector<openvdb::Coord>> voxels;
    for (int id : ids) voxels[id];
    for (auto it = labels.cbeginValueOn(); it; ++it) {
        const auto found = voxels.find(*it);
        if (found == voxels.end()) continue;
        if (it.isVoxelValue()) {
            found->second.push_back(it.getCoord());
        } else {
            openvdb::CoordBBox tile;
            it.getBoundingBox(tile);
            for (auto ijk = tile.begin(); ijk; ++ijk) found->second.push_back(*ijk);
        }
    }
    return voxels;
}

openvdb::CoordBBox boundsWithMargin(const std::vector<openvdb::Coord>& voxels) {
    openvdb::CoordBBox box;
    for (const openvdb::Coord& ijk : voxels) box.expand(ijk);
    box.expand(kStructureMargin);
    return box;
}

}  // namespace

std::vector<std::uint64_t> countLabelVoxels(const openvdb::Int32Grid& labels, const std::vector<int>& ids) {
    std::map<int, std::uint64_t> counts;
    for (auto it = labels.cbeginValueOn(); it; ++it) counts[*it] += it.getVoxelCount();
    std::vector<std::uint64_t> result;
    for (int id : ids) result.push_back(counts[id]);
    return result;
}

LabelledFitResult fitStructures(const openvdb::GridBase& image, const openvdb::Int32Grid& labels,
                                std::vector<StructureFit> structures, const FitSettings& settings,
                                const FitObserver& observer) {
    std::vector<int> ids;
    std::size_t allBudgets = 0;
    for (const StructureFit& s : structures) {
        ids.push_back(s.id);
        allBudgets += s.budget;
    }
    const auto voxels = voxelsByLabel(labels, ids);
    LabelledFitResult result;
    result.params = GaussianParameters(0, image.isType<openvdb::Vec3SGrid>() ? 3 : 1);
    FitProgress done;  // what the structures before this one spent
    double budgetDone = 0.0;
    for (StructureFit& s : structures) {
        const std::vector<openvdb::Coord>& own = voxels.at(s.id);
        s.voxels = own.size();
        if (own.empty() || s.budget == 0) continue;
        const double share = double(s.budget) / double(std::max<std::size_t>(allBudgets, 1));
        FitSettings one = settings;
        one.gaussians = s.budget;
        one.seed = settings.seed + 1000003ull * std::uint64_t(std::int64_t(s.id) & 0x7fffffff);
        if (settings.seconds > 0.0) one.seconds = settings.seconds * share;
        const VolumeTarget target(structureGrid(image, own), "label " + std::to_string(s.id), boundsWithMargin(own));
        const auto relay = [&](const FitProgress& p) {
            if (!observer) return;
            FitProgress whole = p;
            whole.iteration += done.iteration;
            whole.seconds += done.seconds;
            whole.fraction = budgetDone + share * p.fraction;
            whole.gaussians += result.params.count();
            observer(whole);
        };
        const GaussianParameters fitted = fitGaussians(target, one, relay, &s.report);
        result.params.append(fitted);
        result.labels.insert(result.labels.end(), fitted.count(), s.id);
        done.iteration += s.report.iterations;
        done.seconds += s.report.seconds;
        budgetDone += share;
    }
    result.structures = std::move(structures);
    return result;
}

}  // namespace gvr
