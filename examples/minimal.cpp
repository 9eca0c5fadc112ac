// The smallest complete use of the gvr library: a medical volume in, Gaussians
// fitted, the reconstruction out as OpenVDB, and a shear-warp image of it.
//
//     build/examples/minimal [VOLUME] [OUT_FOLDER]
//
// VOLUME defaults to Debian's Colin27 T1 MRI (mricron-data); OUT_FOLDER to ".".
// Every step is one call; the `gvr` command does the same with progress bars,
// flags and error messages around them. Read top to bottom.

#include "io/Ingest.h"
#include "io/asset/AssetExport.h"
#include "io/asset/AssetFile.h"
#include "io/formats/GridFile.h"
#include "io/formats/ImageFile.h"
#include "render/ShearWarp.h"
#include "workflow/FitToBudget.h"
#include "workflow/RenderInput.h"

#include <iostream>

int main(int argc, char** argv) {
    const std::string input = argc > 1 ? argv[1] : "/usr/share/mricron/templates/ch2.nii.gz";
    const std::string out = argc > 2 ? argv[2] : ".";
    try {
        // 1. Ingest. Any format gvr reads becomes a sparse OpenVDB grid in physical
        //    units (HU stays HU), placed in world millimetres, with metadata that
        //    records where it came from. Voxels at the volume's minimum are inactive.
        const gvr::IngestResult ingested = gvr::ingest(input, gvr::IngestOptions{});
        const openvdb::GridBase::Ptr grid = ingested.grid;
        std::cout << "ingested " << input << ": " << grid->activeVoxelCount() << " active voxels\n";

        // 2. Fit. The Gaussians are fitted in normalised units (0 = background, 1 =
        //    top of the data range) and kept with what places them in the world and
        //    maps them back. 4000 Gaussians and 300 iterations take a few seconds;
        //    `gvr fit` asks for a compression ratio and a time budget instead.
        gvr::BudgetedFitOptions options;
        options.gaussians = 4000;
        options.settings.iterations = 300;
        gvr::GaussianAsset asset = gvr::fitToBudget(grid, input, options).asset;
        gvr::writeAsset(out + "/minimal.gvr", asset);
        std::cout << "fitted " << asset.params.count() << " Gaussians -> " << out << "/minimal.gvr\n";

        // 3. Export. The Gaussian field, evaluated at the source's voxel centres and
        //    mapped back to physical units, as a fog volume Blender and Houdini open.
        const gvr::ExportResult exported = gvr::exportAsset(asset, gvr::ExportSettings{});
        gvr::writeGridFile(out + "/minimal.vdb", openvdb::GridCPtrVec(exported.grids.begin(), exported.grids.end()));
        std::cout << "exported the reconstruction -> " << out << "/minimal.vdb\n";

        // 4. Render. The renderer sees the Gaussians straight from the asset; a
        //    transfer function preset classifies the values; one orthographic view
        //    around the volume's centre is shear-warped into a framebuffer.
        const gvr::GaussianRenderVolume volume(asset);
        const gvr::Classifier classifier = gvr::classifierFor("mri", volume);
        const gvr::OrthoCamera camera =
            gvr::makeCamera({30.0, 15.0}, gvr::worldCorners(volume.worldFromIndex(), volume.box()), 256, 256);
        gvr::ShearWarpRenderer renderer(volume, classifier, gvr::ShearWarpSettings{});
        const gvr::Framebuffer image = renderer.render(camera);

        // 5. Write the image. The renderer returns premultiplied floats; io writes them.
        gvr::writeImage(out + "/minimal.png", image.width, image.height, image.rgba.data());
        std::cout << "rendered a view -> " << out << "/minimal.png\n";
        return 0;
    } catch (const std::exception& error) {
        // Library calls throw gvr::InputError for bad input, naming the culprit.
        std::cerr << "minimal: " << error.what() << "\n";
        return 1;
    }
}
