// Asset codec benchmark: what each attribute's bit depth costs in bytes and in PSNR.
//
//   bench_asset_codec ASSET SOURCE.vdb [--no-sweep]
//
// ASSET should be written with fine quantisation (e.g. gvr fit ... --mean-step 0.001
// --rotation-bits 15 --scale-bits 16 --amplitude-bits 16), so that its Gaussians stand
// in for the unquantised fit. Each attribute is swept on its own, the others kept
// fine; then the defaults are measured together, against version 1's fixed widths.
// PSNR is of the whole volume against SOURCE, every voxel counted.

#include "io/asset/AssetBodyV1.h"
#include "io/asset/AssetFile.h"
#include "io/formats/GridFile.h"
#include "pipeline/FieldAccuracy.h"

#include <cstdio>
#include <functional>
#include <string>

namespace {

using namespace gvr;

struct Measured {
    AttributeBytes bytes;
    double psnr = 0.0;
};

Measured measure(const GaussianAsset& asset, const VolumeTarget& target, const AssetEncoding& encoding) {
    const QuantisationV2 quantisation(asset.params, encoding);
    Measured m;
    const std::string body = encodeAssetBodyV2(asset.params, quantisation, &m.bytes);
    const GaussianField field(decodeAssetBodyV2(body, asset.params.count(), quantisation), asset.cutoffSigmas);
    m.psnr = measureFieldAccuracy(field, target).psnr;
    return m;
}

AssetEncoding fine() {
    AssetEncoding e;
    e.meanStep = 1.0f / 1024.0f;
    e.rotationBits = 15;
    e.logScaleBits = 16;
    e.amplitudeBits = 16;
    return e;
}

void sweep(const char* attribute, const std::vector<double>& settings,
           const std::function<void(AssetEncoding&, double)>& set,
           const std::function<std::size_t(const AttributeBytes&)>& bytesOf, const GaussianAsset& asset,
           const VolumeTarget& target, double reference) {
    const double n = double(asset.params.count());
    for (double value : settings) {
        AssetEncoding encoding = fine();
        set(encoding, value);
        const Measured m = measure(asset, target, encoding);
        std::printf("| %s | %g | %.2f | %.2f | %+.3f |\n", attribute, value, bytesOf(m.bytes) / n, m.psnr,
                    m.psnr - reference);
        std::fflush(stdout);
    }
}

/// Each attribute's bit depth on its own, the others kept fine.
void sweepEveryAttribute(const GaussianAsset& asset, const VolumeTarget& target, double reference) {
    std::printf("| attribute | setting | bytes per Gaussian | PSNR dB | vs as read |\n|---|---|---|---|---|\n");
    sweep(
        "mean step (voxels)", {1.0 / 4, 1.0 / 8, 1.0 / 16, 1.0 / 32},
        [](AssetEncoding& e, double v) { e.meanStep = float(v); }, [](const AttributeBytes& b) { return b.position; },
        asset, target, reference);
    sweep(
        "rotation bits", {6, 7, 8, 9, 10}, [](AssetEncoding& e, double v) { e.rotationBits = int(v); },
        [](const AttributeBytes& b) { return b.rotation; }, asset, target, reference);
    sweep(
        "log-scale bits", {5, 6, 7, 8, 10}, [](AssetEncoding& e, double v) { e.logScaleBits = int(v); },
        [](const AttributeBytes& b) { return b.logScales; }, asset, target, reference);
    sweep(
        "amplitude bits", {8, 9, 10, 11, 12, 14}, [](AssetEncoding& e, double v) { e.amplitudeBits = int(v); },
        [](const AttributeBytes& b) { return b.amplitudes; }, asset, target, reference);
}

}  // namespace

int main(int argc, char** argv) {
    const bool sweeps = !(argc == 4 && std::string(argv[3]) == "--no-sweep");
    if (argc != 3 && sweeps) {
        std::fprintf(stderr, "usage: bench_asset_codec ASSET SOURCE.vdb [--no-sweep]\n");
        return 2;
    }
    try {
        openvdb::initialize();
        const GaussianAsset asset = readAsset(argv[1]);
        const openvdb::GridPtrVecPtr grids = readGridFile(argv[2]);
        const VolumeTarget target(chooseVolumeGrid(*grids, argv[2]), argv[2]);
        const double n = double(asset.params.count());
        const int channels = asset.params.channels;

        const GaussianField asRead(asset.params, asset.cutoffSigmas);
        const double reference = measureFieldAccuracy(asRead, target).psnr;
        std::printf("%s: %zu Gaussians, %d channel(s); PSNR as read %.2f dB\n\n", argv[1], asset.params.count(),
                    channels, reference);
        if (sweeps) sweepEveryAttribute(asset, target, reference);

        const Measured chosen = measure(asset, target, AssetEncoding{});
        const AttributeBytes& b = chosen.bytes;
        const double v1Colour = 1.0 + 2.0 * channels;
        std::printf("\n| attribute | v1 bytes per Gaussian | v2 (defaults) bytes per Gaussian |\n|---|---|---|\n");
        std::printf("| position | 6 | %.2f |\n| rotation | 4 | %.2f |\n| log-scales | 6 | %.2f |\n", b.position / n,
                    b.rotation / n, b.logScales / n);
        std::printf("| opacity + colour (v1), amplitude (v2) | %.0f | %.2f |\n", v1Colour, b.amplitudes / n);
        std::printf("| body | %zu | %.2f |\n", assetV1BytesPerGaussian(channels),
                    (b.position + b.rotation + b.logScales + b.amplitudes) / n);
        std::printf("\nPSNR with the defaults: %.2f dB (%+.3f dB against the asset as read)\n", chosen.psnr,
                    chosen.psnr - reference);
        return 0;
    } catch (const std::exception& error) {
        std::fprintf(stderr, "bench_asset_codec: %s\n", error.what());
        return 1;
    }
}
