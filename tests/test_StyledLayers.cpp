// A labelled asset as render layers: each styled structure on its own layer with
// its style, the rest with the base classification, and styles that cannot apply refused.

#include "pipeline/Error.h"
#include "render/StyledLayers.h"

#include <gtest/gtest.h>

#include <string>

namespace gvr {
namespace {

/// Three grey Gaussians with labels 1, 2 and 3, named a, b and c.
GaussianAsset labelledAsset() {
    GaussianAsset asset;
    asset.params = GaussianParameters(3, 1);
    for (std::size_t i = 0; i < 3; ++i) {
        for (int a = 0; a < 3; ++a) asset.params.at(kMeans, i)[a] = 2.0f + 2.0f * float(i);
        asset.params.at(kRotations, i)[0] = 1.0f;
        asset.params.at(kColours, i)[0] = 1.0f;
    }
    asset.labels = {1, 2, 3};
    asset.labelTable.names = {{1, "a"}, {2, "b"}, {3, "c"}};
    asset.source.dims = openvdb::Vec3i(8, 8, 8);
    asset.source.valueMax = 1.0;
    return asset;
}

Classifier baseClassifier(int channels) {
    return Classifier(TransferFunction({{0.1, {0.2f, 0.2f, 0.2f, 0.0f}}, {1.0, {1.0f, 1.0f, 1.0f, 0.8f}}}, "test"),
                      channels);
}

TEST(StyledLayers, PutsEachStyledStructureOnItsOwnLayerAndTheRestOnTheBase) {
    LabelStyle red;
    red.colour = std::array<float, 3>{1.0f, 0.0f, 0.0f};
    red.opacity = 0.5f;
    const Classifier base = baseClassifier(1);
    const StyledLayers styled = styledLayers(labelledAsset(), {{"b", red}}, base, 0.5f, "styles.json");

    ASSERT_EQ(styled.layers.size(), 2u);
    ASSERT_EQ(styled.volumes.size(), 2u);
    EXPECT_EQ(styled.layers[0].volume, styled.volumes[0].get());
    EXPECT_EQ(styled.layers[1].volume, styled.volumes[1].get());
    // The styled layer: red everywhere, half the base's opacity.
    for (const TransferPoint& point : styled.layers[0].classifier.transferFunction().points()) {
        EXPECT_EQ(point.rgba[0], 1.0f);
        EXPECT_EQ(point.rgba[1], 0.0f);
        EXPECT_EQ(point.rgba[2], 0.0f);
    }
    EXPECT_FLOAT_EQ(styled.layers[0].classifier.transferFunction().points().back().rgba[3], 0.4f);
    // The other structures keep the base classification untouched.
    const auto& rest = styled.layers[1].classifier.transferFunction().points();
    ASSERT_EQ(rest.size(), base.transferFunction().points().size());
    for (std::size_t p = 0; p < rest.size(); ++p) EXPECT_EQ(rest[p].rgba, base.transferFunction().points()[p].rgba);
}

TEST(StyledLayers, StylingEveryStructureLeavesNoBaseLayer) {
    LabelStyle faint;
    faint.opacity = 0.25f;
    const StyledLayers styled = styledLayers(labelledAsset(), {{"all", faint}}, baseClassifier(1), 0.5f, "styles.json");
    EXPECT_EQ(styled.layers.size(), 3u);  // one for each structure, none for the base
}

TEST(StyledLayers, RefusesUnknownStructuresAndColoursOnRgbNamingTheStyles) {
    LabelStyle style;
    try {
        styledLayers(labelledAsset(), {{"nowhere", style}}, baseClassifier(1), 0.5f, "styles.json");
        FAIL() << "an unknown structure was accepted";
    } catch (const InputError& error) {
        EXPECT_EQ(std::string(error.what()).rfind("styles.json", 0), 0u) << error.what();
    }
    style.colour = std::array<float, 3>{0.0f, 1.0f, 0.0f};
    try {
        styledLayers(labelledAsset(), {{"a", style}}, baseClassifier(3), 0.5f, "styles.json");
        FAIL() << "a colour was accepted for an RGB asset";
    } catch (const InputError& error) {
        EXPECT_EQ(std::string(error.what()).rfind("styles.json", 0), 0u) << error.what();
    }
}

}  // namespace
}  // namespace gvr
