/// @file LabelledFit.h
/// @brief Fitting by structure: each chosen label is fitted on its own, with its own
/// budget, samples and seed, and the Gaussians keep their label.
///
/// A structure's target is its own voxels, with background everywhere else in its
/// bounding box (plus a margin), so its Gaussians are pulled back from its
/// neighbours and the structures add up to the selected part of the volume. Voxels
/// outside every chosen structure are never sampled and seed no Gaussian.
#pragma once

#include "pipeline/Fitter.h"

#include <openvdb/openvdb.h>

#include <vector>

namespace gvr {

/// Voxels beyond a structure's bounding box that its fit still sees (as background).
constexpr int kStructureMargin = 2;

struct StructureFit {
    int id = 0;
    std::uint64_t voxels = 0;
    std::size_t budget = 0;  ///< Gaussians asked for
    FitReport report;
};

struct LabelledFitResult {
    GaussianParameters params;
    std::vector<int> labels;  ///< one per Gaussian, grouped in structure order
    std::vector<StructureFit> structures;
};

/// Voxel count of each of @a ids in @a labels.
std::vector<std::uint64_t> countLabelVoxels(const openvdb::Int32Grid& labels, const std::vector<int>& ids);

/// Fits @a structures (id and budget set; the rest is filled in) one after another.
/// A time budget is shared in proportion to the budgets; an iteration budget applies
/// to each structure. A structure's seed depends on its id only, so with an
/// iteration budget it comes out the same whichever others are fitted with it.
/// @a observer sees the whole fit's progress (iterations and seconds summed).
LabelledFitResult fitStructures(const openvdb::GridBase& image, const openvdb::Int32Grid& labels,
                                std::vector<StructureFit> structures, const FitSettings& settings,
                                const FitObserver& observer = {});

}  // namespace gvr
