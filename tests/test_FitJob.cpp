// One fit as gvr fit and gvr.fit run it: the request refused before anything is
// read, an empty volume said out loud, and a bound that holds for the source as read
// rather than for the grid its threshold made.

#include "io/asset/AssetFile.h"
#include "io/formats/NiftiWriter.h"
#include "pipeline/Error.h"
#include "pipeline/QualityMetrics.h"
#include "tests/TestHelpers.h"
#include "workflow/ComparisonInput.h"
#include "workflow/FitJob.h"

#include <cmath>
#include <limits>

namespace gvr {
namespace {

FitRequest shortRequest(std::size_t gaussians) {
    FitRequest request;
    request.options.gaussians = gaussians;
    request.options.settings.seconds = 0.0;
    request.options.settings.iterations = 3;
    return request;
}

FitInput fileInput(const std::string& path) {
    FitInput input;
    input.path = path;
    return input;
}

TEST(FitJob, ABadRequestIsRefusedBeforeTheInputIsRead) {
    FitRequest nan = shortRequest(10);
    nan.bound = BoundRequest::exactly(std::numeric_limits<double>::quiet_NaN());
    const std::string missing = "/no/such/volume.nii.gz";
    EXPECT_NE(test::errorMessageOf<InputError>([&] { FitJob(fileInput(missing), nan); }).find("`max_error`"),
              std::string::npos);

    FitRequest bricked = shortRequest(10);
    bricked.bound = BoundRequest::exactly(1.0);
    bricked.bricks.count = 2;
    const std::string both = test::errorMessageOf<InputError>([&] { FitJob(fileInput(missing), bricked); });
    EXPECT_NE(both.find("`bricks`"), std::string::npos) << both;
    EXPECT_EQ(both.find(missing), std::string::npos) << both;

    FitRequest searched = shortRequest(0);
    searched.bound = BoundRequest{kSearchedBound, 0.0};
    EXPECT_NE(test::errorMessageOf<InputError>([&] { checkedFitRequest(searched); }).find("`ratio`"),
              std::string::npos);
}

TEST(FitJob, ABoundGivesTheGaussiansThePreviewRatioUnlessACountIsAsked) {
    FitRequest request;
    request.options.settings.iterations = 1;
    request.options.settings.seconds = 0.0;
    request.bound = BoundRequest::exactly(2.0);
    const FitRequest preview = checkedFitRequest(request);
    EXPECT_EQ(preview.options.ratio, kBoundedPreviewRatio);
    EXPECT_EQ(preview.options.minimumGaussians, kBoundedPreviewGaussians);

    request.options.gaussians = 50;
    const FitRequest counted = checkedFitRequest(request);
    EXPECT_EQ(counted.options.ratio, BudgetedFitOptions().ratio);
    EXPECT_EQ(counted.options.minimumGaussians, 0u);
}

TEST(FitJob, AnEmptyVolumeIsSaidToGiveAnAssetWithoutGaussians) {
    test::TempDir dir;
    const std::string empty = test::smallGrid(dir, /*empty=*/true);
    const FitJob job(fileInput(empty), shortRequest(10));
    ASSERT_EQ(job.warnings().size(), 1u);
    EXPECT_NE(job.warnings()[0].find(empty + " has no active voxels"), std::string::npos) << job.warnings()[0];
    EXPECT_EQ(job.run().result.asset.params.count(), 0u);

    const std::string full = test::smallGrid(dir);
    EXPECT_TRUE(FitJob(fileInput(full), shortRequest(10)).warnings().empty());
}

TEST(FitJob, AGridInMemoryFitsAsItsFileDoes) {
    test::TempDir dir;
    const std::string path = test::smallGrid(dir);
    const FitJob fromFile(fileInput(path), shortRequest(20));
    FitInput inMemory;
    inMemory.inMemory = fromFile.loaded();
    const FitJob fromMemory(inMemory, shortRequest(20));
    EXPECT_EQ(fromMemory.name(), "volume");
    const GaussianParameters a = fromFile.run().result.asset.params, b = fromMemory.run().result.asset.params;
    ASSERT_EQ(a.count(), 20u);
    ASSERT_EQ(b.count(), a.count());
    EXPECT_EQ(a.values, b.values);
}

TEST(FitJob, ABoundHoldsForTheSourceAsReadNotForItsThresholdedGrid) {
    // A blob over a noise floor of 1 to 5, which a threshold of 10 leaves out of the grid.
    test::TempDir dir;
    FloatVolume source(openvdb::Coord(20, 18, 12), 1);
    for (int k = 0; k < 12; ++k) {
        for (int j = 0; j < 18; ++j) {
            for (int i = 0; i < 20; ++i) {
                const double d2 = (i - 10) * (i - 10) + (j - 9) * (j - 9) + (k - 6) * (k - 6);
                *source.at(i, j, k) = float(std::lround(1 + (i * 7 + j * 3 + k) % 5 + 150.0 * std::exp(-d2 / 12.0)));
            }
        }
    }
    const std::string path = dir.path("floor.nii");
    NiftiStorage storage;
    storage.type = SampleType::Int16;
    writeNifti(path, source, storage);
    FitInput input = fileInput(path);
    input.ingest.build.threshold = 10.0;
    FitRequest request = shortRequest(12);
    request.bound = BoundRequest::exactly(0.5);
    const FitJob job(input, request);
    const FitOutcome outcome = job.run();
    ASSERT_TRUE(outcome.layer.has_value());
    EXPECT_LE(outcome.layer->maxError, 0.5);

    const std::string asset = dir.path("bounded.gvr");
    writeAssetBytes(asset, outcome.result.file);
    const FloatVolume exported = loadComparisonInput(asset, {}).volume;
    EXPECT_LE(maxAbsoluteError(loadComparisonInput(path, {}).volume, exported), 0.5);
    // The grid holds its background where the floor was: at least 0.5 from the export there.
    EXPECT_GE(maxAbsoluteError(comparisonInputOf(job.loaded().grid, "grid").volume, exported), 0.5);
}

}  // namespace
}  // namespace gvr
