#include "pipeline/FieldToGrid.h"

#include "pipeline/LeafAssembly.h"
#include "pipeline/ThresholdCut.h"

#include <algorithm>

namespace gvr {

namespace {

/// Makes the leaf of each block the field reaches, in physical units.
template <typename GridT>
class LeafSampler {
public:
    using LeafT = typename GridT::TreeType::LeafNodeType;
    using ValueT = typename GridT::ValueType;
    static_assert(LeafT::DIM == kBlockDim, "blocks are OpenVDB leaves");

    LeafSampler(const LatticeSampler& sampler, const FieldToGridSettings& settings)
        : mSampler(sampler),
          mSettings(settings),
          mChannels(sampler.channels()),
          mCut(settings.mapping, mChannels, settings.threshold, settings.thresholdAbove) {}

    std::unique_ptr<LeafT> operator()(const openvdb::Coord& origin) const {
        float sums[kBlockVoxels * 3] = {};
        const openvdb::CoordBBox voxels = mSampler.sampleBlock(origin, sums, -1.0f, mSettings.evaluation);
        if (voxels.empty()) return nullptr;
        auto leaf = std::make_unique<LeafT>(origin, background(), false);
        for (auto ijk = voxels.begin(); ijk; ++ijk) {
            const int offset = blockOffset(*ijk);
            const float* sum = sums + offset * mChannels;
            if (std::all_of(sum, sum + mChannels, [](float v) { return v == 0.0f; })) continue;  // unreached
            if (mCut.cuts(sum)) continue;
            float physical[3];
            for (int c = 0; c < mChannels; ++c) physical[c] = mSettings.mapping.toPhysicalFloat(sum[c], c);
            leaf->setValueOn(offset, valueOf(physical));
        }
        return leaf->isEmpty() ? nullptr : std::move(leaf);
    }

    /// What inactive voxels hold: the physical value of normalised 0.
    ValueT background() const {
        float physical[3];
        for (int c = 0; c < mChannels; ++c) physical[c] = mSettings.mapping.toPhysicalFloat(0.0, c);
        return valueOf(physical);
    }

private:
    static ValueT valueOf(const float* physical) {
        if constexpr (std::is_same_v<ValueT, openvdb::Vec3s>)
            return ValueT(physical[0], physical[1], physical[2]);
        else
            return physical[0];
    }

    const LatticeSampler& mSampler;
    const FieldToGridSettings& mSettings;
    const int mChannels;
    const ThresholdCut mCut;
};

template <typename GridT>
typename GridT::Ptr sampleInto(const LatticeSampler& sampler, const FieldToGridSettings& settings,
                               const ProgressFn& progress) {
    const LeafSampler<GridT> leaves(sampler, settings);
    typename GridT::Ptr grid = assembleGrid<GridT>(sampler.occupiedBlocks(), leaves.background(), leaves, progress);
    grid->setTransform(openvdb::math::Transform::createLinearTransform(sampler.lattice().worldFromIndex));
    return grid;
}

}  // namespace

openvdb::GridBase::Ptr fieldToGrid(const GaussianField& field, const openvdb::math::Mat4d& fieldWorldFromIndex,
                                   const Lattice& lattice, const FieldToGridSettings& settings,
                                   const ProgressFn& progress) {
    const LatticeSampler sampler(field, fieldWorldFromIndex, lattice, settings.fieldBox);
    openvdb::GridBase::Ptr grid;
    if (field.channels() == 1) {
        grid = sampleInto<openvdb::FloatGrid>(sampler, settings, progress);
        grid->setName("density");
    } else {
        grid = sampleInto<openvdb::Vec3SGrid>(sampler, settings, progress);
        grid->setName("color");
    }
    return grid;
}

}  // namespace gvr
