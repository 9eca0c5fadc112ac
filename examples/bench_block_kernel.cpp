// The fit's block kernel on its own: one call of blockSquaredError (forward and
// backward, over one draw of the fit's default batch), eight lanes against four.
//
//   bench_block_kernel SOURCE.vdb [COUNT | ASSET.gvr] ...
//
// COUNT seeds that many Gaussians as a fit starts them; an asset gives a fitted set
// (smaller, anisotropic Gaussians, as at the end of a fit). Each figure is the
// fastest of several calls, so that other work on a shared machine shows less; the
// two kernels alternate, so drift hits both alike. Defaults: 10000 40000 100000 400000.

#include "io/asset/AssetFile.h"
#include "io/formats/GridFile.h"
#include "pipeline/BlockLoss.h"
#include "pipeline/FitSettings.h"
#include "pipeline/Initialisation.h"

#include <tbb/tick_count.h>

#include <algorithm>
#include <cstdio>
#include <string>

namespace {

using namespace gvr;

constexpr int kRepeats = 9;

struct Timing {
    double seconds = 1e300;
    std::uint64_t voxels = 0;
};

/// One call of the kernel with gradients, as a fit step makes it.
double timeOneCall(const GaussianField& field, const BlockBins& bins, const VolumeTarget& target,
                   const std::vector<SampledBlock>& blocks, BlockKernel kernel, GradientChunks& chunks,
                   std::uint64_t& voxels) {
    BlockLossSettings settings;
    settings.rowStride = FitSettings{}.rowStride;
    settings.kernel = kernel;
    std::vector<BlockOutcome> outcomes;
    const tbb::tick_count start = tbb::tick_count::now();
    chunks.reset(field.gaussians().size());
    blockSquaredError(field, bins, target, blocks, settings, &chunks, &outcomes);
    const double seconds = (tbb::tick_count::now() - start).seconds();
    voxels = 0;
    for (const BlockOutcome& outcome : outcomes) voxels += outcome.voxels;
    return seconds;
}

void measure(const char* label, const GaussianParameters& params, const VolumeTarget& target) {
    const BlockGrid grid(target.box());
    GaussianField field;
    field.rebuild(params, kDefaultCutoffSigmas, /*fastBuild=*/true, kBinSlackVoxels, kBinSlackFraction);
    BlockBins bins(grid, kBinSlackVoxels, kBinSlackFraction);
    bins.build(field);
    const FitSettings defaults;
    const BlockSampler sampler(grid, ImportanceSettings{}, defaults.rowStride);
    const std::vector<SampledBlock> blocks = sampler.draw(double(defaults.batchFor(params.count())), 1);
    GradientChunks chunks;
    Timing eight, four;
    for (int r = 0; r < kRepeats; ++r) {
        for (auto [kernel, timing] : {std::pair{BlockKernel::Best, &eight}, std::pair{BlockKernel::FourLanes, &four}}) {
            std::uint64_t voxels = 0;
            timing->seconds =
                std::min(timing->seconds, timeOneCall(field, bins, target, blocks, kernel, chunks, voxels));
            timing->voxels = voxels;
        }
    }
    const auto perSecond = [](const Timing& t) { return double(t.voxels) / t.seconds / 1e6; };
    std::printf("| %s | %zu | %zu | %.1f | %.2f | %.1f | %.2f | %.2fx |\n", label, params.count(), blocks.size(),
                1e3 * eight.seconds, perSecond(eight), 1e3 * four.seconds, perSecond(four),
                four.seconds / eight.seconds);
    std::fflush(stdout);
}

bool isCount(const std::string& text) {
    return !text.empty() && std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; });
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: bench_block_kernel SOURCE.vdb [COUNT | ASSET.gvr] ...\n");
        return 2;
    }
    try {
        openvdb::initialize();
        const openvdb::GridPtrVecPtr grids = readGridFile(argv[1]);
        const VolumeTarget target(chooseVolumeGrid(*grids, argv[1]), argv[1]);
        std::vector<std::string> sets(argv + 2, argv + argc);
        if (sets.empty()) sets = {"10000", "40000", "100000", "400000"};
        std::printf(
            "%s, the fit's defaults (batch %.0f voxels a Gaussian, at least %zu; every %d-th row); fastest of %d "
            "calls\n\n",
            argv[1], kBatchPerGaussian, kLeastVoxelBatch, FitSettings{}.rowStride, kRepeats);
        std::printf(
            "| Gaussians from | count | blocks | 8 lanes: ms | M voxels/s | 4 lanes: ms | M voxels/s | 8 against 4 |\n"
            "|---|---|---|---|---|---|---|---|\n");
        for (const std::string& set : sets) {
            if (isCount(set)) {
                SeedSettings seeds;
                seeds.count = std::stoull(set);
                measure("seeds", initialiseGaussians(target, seeds), target);
            } else {
                measure(set.c_str(), readAsset(set).params, target);
            }
        }
        return 0;
    } catch (const std::exception& error) {
        std::fprintf(stderr, "bench_block_kernel: %s\n", error.what());
        return 1;
    }
}
