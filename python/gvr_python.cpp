// The gvr Python module: volumes to and from numpy, fits, assets, renders and
// evaluation, as thin calls into the library the command line uses. Errors in the
// user's input raise gvr.Error (a ValueError) with the command line's one-line message.

#include "io/DenseCopy.h"
#include "io/GridBuilder.h"
#include "io/Ingest.h"
#include "io/LabelGrid.h"
#include "io/asset/AssetExport.h"
#include "io/asset/AssetFile.h"
#include "io/formats/JsonText.h"
#include "io/formats/LabelStyleFile.h"
#include "io/formats/VolumeOutputs.h"
#include "pipeline/AssetProbe.h"
#include "pipeline/Error.h"
#include "pipeline/FloatVolume.h"
#include "pipeline/SettingNames.h"
#include "pipeline/WorldGaussians.h"
#include "python/CallsInFlight.h"
#include "render/Camera.h"
#include "render/ShearWarp.h"
#include "render/VolumeClassifier.h"
#include "workflow/ComparisonInput.h"
#include "workflow/Evaluate.h"
#include "workflow/FitJob.h"
#include "workflow/ProbeAsset.h"
#include "workflow/RenderInput.h"
#include "workflow/RenderJob.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <filesystem>
#include <iomanip>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <variant>

namespace py = pybind11;

namespace gvr {
namespace {

/// A volume: an OpenVDB grid in physical units, as ingest makes it.
struct Volume {
    openvdb::GridBase::Ptr grid;
    openvdb::Int32Grid::Ptr labels;  ///< structure labels on the same voxels, or null
};

/// The library names settings by the command line's keys (SettingNames.h); the
/// arguments of these functions share them but for a few.
std::string inPythonTerms(const std::string& message) {
    static const std::map<std::string, std::string> renamed = {{"time", "seconds"}, {"show", "structures"}};
    static const std::set<std::string> switches = {"resample", "resample_labels"};
    return respellSettings(message, [](const std::string& key, const std::string& value) {
        const auto found = renamed.find(key);
        const std::string name = found == renamed.end() ? key : found->second;
        if (switches.count(key)) return name + "=True";
        return value.empty() ? name : name + "=" + value;
    });
}

/// Raised inside a fit's progress callback to stop the fit, once Python's error
/// indicator holds why (Ctrl-C, or an exception in the user's callback).
struct PythonErrorPending {};

// ---- numpy in ----

template <typename T>
void copySamples(const py::array& array, DenseVolume& volume) {
    const auto typed = py::array_t<T>::ensure(array);
    T* out = volume.data<T>();
    const int channels = volume.channels;
    const auto [nx, ny, nz] = volume.dims;
    if (channels == 1) {
        const auto in = typed.template unchecked<3>();
        for (std::int64_t k = 0; k < nz; ++k)
            for (std::int64_t j = 0; j < ny; ++j)
                for (std::int64_t i = 0; i < nx; ++i) *out++ = in(i, j, k);
    } else {
        const auto in = typed.template unchecked<4>();
        for (std::int64_t k = 0; k < nz; ++k)
            for (std::int64_t j = 0; j < ny; ++j)
                for (std::int64_t i = 0; i < nx; ++i)
                    for (int c = 0; c < channels; ++c) *out++ = in(i, j, k, c);
    }
}

/// numpy types gvr does not store, converted to one it does: bool to uint8,
/// float16 to float32, 64-bit integers to int32 when every value fits, else to
/// float64 (exact up to 2^53); anything else unchanged.
py::array storableArray(const py::array& array) {
    const py::dtype dtype = array.dtype();
    const char kind = dtype.kind();
    const auto size = dtype.itemsize();
    const auto as = [&](const char* name) { return py::array(array.attr("astype")(name)); };
    if (kind == 'b') return as("uint8");
    if (kind == 'f' && size == 2) return as("float32");
    if ((kind == 'i' || kind == 'u') && size == 8) {
        const py::module_ numpy = py::module_::import("numpy");
        const bool fitsInt32 = array.size() == 0 || (numpy.attr("min")(array).cast<double>() >= -2147483648.0 &&
                                                     numpy.attr("max")(array).cast<double>() <= 2147483647.0);
        if (fitsInt32) return as("int32");
        const double largest = numpy.attr("max")(numpy.attr("abs")(array.attr("astype")("float64"))).cast<double>();
        if (largest > 9007199254740992.0) {
            throw InputError("array", "holds 64-bit integers beyond 2^53, which no type gvr stores keeps exactly");
        }
        return as("float64");
    }
    return array;
}

SampleType sampleTypeOf(const py::dtype& dtype) {
    const char kind = dtype.kind();
    const auto size = dtype.itemsize();
    if (kind == 'u' && size == 1) return SampleType::UInt8;
    if (kind == 'i' && size == 1) return SampleType::Int8;
    if (kind == 'u' && size == 2) return SampleType::UInt16;
    if (kind == 'i' && size == 2) return SampleType::Int16;
    if (kind == 'u' && size == 4) return SampleType::UInt32;
    if (kind == 'i' && size == 4) return SampleType::Int32;
    if (kind == 'f' && size == 4) return SampleType::Float32;
    if (kind == 'f' && size == 8) return SampleType::Float64;
    throw InputError("array", "dtype " + dtype.attr("name").cast<std::string>() +
                                  " is not supported (uint8, int8, uint16, int16, uint32, int32, float32, float64; "
                                  "bool, float16 and int64 are converted)");
}

/// The array's samples in gvr's layout (i fastest, channels interleaved), in its own type.
DenseVolume denseFromArray(const py::array& given) {
    const py::array array = storableArray(given);
    const bool rgb = array.ndim() == 4 && array.shape(3) == 3;
    if (array.ndim() != 3 && !rgb) {
        std::string shape;
        for (py::ssize_t d = 0; d < array.ndim(); ++d) shape += (d ? ", " : "") + std::to_string(array.shape(d));
        throw InputError("array", "shape (" + shape + ") is neither (x, y, z) nor (x, y, z, 3)");
    }
    DenseVolume volume;
    volume.type = sampleTypeOf(array.dtype());
    volume.channels = rgb ? 3 : 1;
    for (int a = 0; a < 3; ++a) volume.dims[a] = array.shape(a);
    if (volume.voxelCount() == 0) throw InputError("array", "is empty");
    allocateSamples(volume, "array");
    switch (volume.type) {
        case SampleType::UInt8:
            copySamples<std::uint8_t>(array, volume);
            break;
        case SampleType::Int8:
            copySamples<std::int8_t>(array, volume);
            break;
        case SampleType::UInt16:
            copySamples<std::uint16_t>(array, volume);
            break;
        case SampleType::Int16:
            copySamples<std::int16_t>(array, volume);
            break;
        case SampleType::UInt32:
            copySamples<std::uint32_t>(array, volume);
            break;
        case SampleType::Int32:
            copySamples<std::int32_t>(array, volume);
            break;
        case SampleType::Float32:
            copySamples<float>(array, volume);
            break;
        case SampleType::Float64:
            copySamples<double>(array, volume);
            break;
    }
    return volume;
}

/// @a given as a numpy array: lists and tuples (of lists) too, as numpy.asarray makes them.
py::array asArray(const py::object& given, const std::string& name) {
    try {
        return py::module_::import("numpy").attr("asarray")(given);
    } catch (py::error_already_set&) {
        throw InputError(name, "is neither an array nor a sequence numpy can make one of");
    }
}

/// nibabel's 4x4 affine (world = A (i, j, k, 1)^T) as OpenVDB's row-vector matrix.
openvdb::math::Mat4d matrixFromAffine(const py::object& affine) {
    const auto a = py::array_t<double, py::array::forcecast>::ensure(asArray(affine, "affine"));
    if (!a || a.ndim() != 2 || a.shape(0) != 4 || a.shape(1) != 4) throw InputError("affine", "must be a 4x4 array");
    const auto m = a.unchecked<2>();
    double rows[3][4];
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) rows[r][c] = m(r, c);
    return worldFromIndexRows(rows);
}

/// A float64 array says nothing of the type its file stored, and a fit's ratio then
/// counts 8 bytes a voxel: 2.84:1 against an int16 file, asked for 10:1.
void warnOfAGuessedSourceType(const py::array& array) {
    if (array.dtype().kind() != 'f' || array.dtype().itemsize() != 8) return;
    const char* note =
        "the array is float64, so a fit's ratio counts 8 bytes a voxel; pass source_type= the file's "
        "type (for nibabel, str(img.get_data_dtype())), or use Volume.from_nibabel(img)";
    if (PyErr_WarnEx(PyExc_UserWarning, note, 2) != 0) throw py::error_already_set();
}

Volume volumeFromNumpy(const py::object& samples, std::optional<std::array<double, 3>> spacing,
                       const std::optional<py::object>& affine, std::optional<double> threshold,
                       const std::string& modality, std::optional<float> nanTo, const std::string& sourceType) {
    if (spacing && affine) throw InputError("spacing", "give spacing or affine, not both");
    const py::array array = asArray(samples, "array");
    if (sourceType.empty()) warnOfAGuessedSourceType(array);
    GridBuildSettings settings;
    settings.sourceFile = "array";
    settings.threshold = threshold;
    settings.nanTo = nanTo;
    settings.validate();  // before the array is copied
    DenseVolume dense = denseFromArray(array);
    if (spacing) dense.worldFromIndex = worldFromSpacing({(*spacing)[0], (*spacing)[1], (*spacing)[2]});
    if (affine) dense.worldFromIndex = matrixFromAffine(*affine);
    if (!modality.empty()) dense.modality = modality;
    const std::optional<SampleType> declared =
        sourceType.empty() ? std::nullopt : std::optional<SampleType>(sampleTypeFromName(sourceType, "source_type"));
    const WithoutGil released;
    openvdb::GridBase::Ptr grid = buildGrid(dense, settings);
    if (declared) {  // the ratio's raw size is the source file's, not the array's
        VolumeMetadata metadata = *readVolumeMetadata(*grid);
        metadata.sourceType = sampleTypeName(*declared);
        writeVolumeMetadata(metadata, *grid);
    }
    return {grid, nullptr};
}

/// A nibabel image, with what its header says: the stored type (for the ratio), the
/// affine, and the scaling, which np.asarray(img.dataobj) applies. RGB images come
/// as a last axis of 3.
Volume volumeFromNibabel(const py::object& image, std::optional<double> threshold, const std::string& modality,
                         std::optional<float> nanTo) {
    for (const char* needed : {"dataobj", "affine", "get_data_dtype"}) {
        if (!py::hasattr(image, needed)) {
            throw InputError("image", "is not a nibabel image (it has no " + std::string(needed) + ")");
        }
    }
    const py::module_ numpy = py::module_::import("numpy");
    py::object samples = numpy.attr("asarray")(image.attr("dataobj"));
    py::dtype stored = py::dtype::from_args(image.attr("get_data_dtype")());
    if (py::hasattr(stored, "fields") && !stored.attr("fields").is_none()) {  // RGB24: fields R, G and B
        samples = py::module_::import("numpy.lib.recfunctions").attr("structured_to_unstructured")(samples);
        stored = py::dtype::from_args(py::list(stored.attr("fields").attr("values")())[0].cast<py::tuple>()[0]);
    }
    const std::string sourceType = py::str(stored.attr("name"));
    return volumeFromNumpy(samples, std::nullopt, py::object(image.attr("affine")), threshold, modality, nanTo,
                           sourceType);
}

// ---- numpy out ----

/// The index of the grid's first sample, where to_numpy() starts.
openvdb::CoordBBox boxOf(const Volume& volume) { return volumeBox(*volume.grid); }

py::array volumeToNumpy(const Volume& volume) {
    auto samples = std::make_unique<FloatVolume>();
    {
        const WithoutGil released;
        *samples = denseCopy(*volume.grid, boxOf(volume), "volume", "copy to NumPy");
    }
    const FloatVolume& v = *samples;
    const py::ssize_t c = v.channels, item = sizeof(float);
    std::vector<py::ssize_t> shape{v.dims.x(), v.dims.y(), v.dims.z()};
    std::vector<py::ssize_t> strides{c * item, c * item * v.dims.x(), c * item * v.dims.x() * v.dims.y()};
    if (c > 1) {
        shape.push_back(c);
        strides.push_back(item);
    }
    const float* data = v.values.data();
    // The array owns the samples: no copy on the way out.
    py::capsule owner(samples.release(), [](void* p) { delete static_cast<FloatVolume*>(p); });
    return py::array(py::dtype::of<float>(), shape, strides, data, owner);
}

py::array affineOf(const Volume& volume) {
    openvdb::math::Mat4d shift = openvdb::math::Mat4d::identity();
    shift.setTranslation(boxOf(volume).min().asVec3d());
    const openvdb::math::Mat4d m = shift * volume.grid->transform().baseMap()->getAffineMap()->getMat4();
    py::array_t<double> affine(std::vector<py::ssize_t>{4, 4});
    auto a = affine.mutable_unchecked<2>();
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) a(r, c) = m(c, r);  // row-vector to column-vector convention
    return affine;
}

py::dict metadataOf(const Volume& volume) {
    py::dict out;
    out["grid"] = volume.grid->getName();
    const auto m = readVolumeMetadata(*volume.grid);
    if (!m) return out;
    out["source_file"] = m->sourceFile;
    out["modality"] = m->modality;
    out["source_type"] = m->sourceType;
    out["channels"] = m->channels;
    out["dims"] = py::make_tuple(m->dims.x(), m->dims.y(), m->dims.z());
    out["spacing_mm"] = py::make_tuple(m->spacingMm.x(), m->spacingMm.y(), m->spacingMm.z());
    out["value_min"] = m->valueMin;
    out["value_max"] = m->valueMax;
    out["background"] = m->background;
    out["threshold"] = m->threshold ? py::object(py::float_(*m->threshold)) : py::object(py::none());
    out["raw_bytes"] = m->rawSourceBytes();
    return out;
}

Volume ingestPath(const std::string& path, std::optional<double> threshold,
                  std::optional<std::array<double, 3>> spacing, std::optional<float> nanTo, int volumeIndex,
                  const std::string& labels, const std::string& labelNames, bool resampleLabels) {
    IngestOptions options;
    options.labels = labels;
    options.labelNames = labelNames;
    options.resampleLabels = resampleLabels;
    options.build.threshold = threshold;
    options.build.nanTo = nanTo;
    options.build.validate();  // before the file is read
    options.read.volumeIndex = volumeIndex;
    if (spacing) options.read.spacingMm = openvdb::Vec3d((*spacing)[0], (*spacing)[1], (*spacing)[2]);
    const WithoutGil released;
    const IngestResult result = loadOrIngest(path, options);
    return {result.grid, result.labels};
}

std::map<int, std::string> labelNamesOf(const LabelTable& table) { return {table.names.begin(), table.names.end()}; }

// ---- fit ----

/// The fit's progress as a dict for @a progress, Ctrl-C, and interpreter exit, from the fitting thread.
FitObserver pythonObserver(const std::optional<py::function>& progress, std::optional<std::size_t> brick) {
    return [&progress, brick](const FitProgress& p) {
        if (CallsInFlight::instance().stopping()) throw InterpreterExiting();
        py::gil_scoped_acquire gil;
        if (PyErr_CheckSignals() != 0) throw PythonErrorPending{};  // Ctrl-C
        if (!progress) return;
        try {
            py::dict state;
            state["iteration"] = p.iteration;
            state["seconds"] = p.seconds;
            state["fraction"] = p.fraction;
            state["gaussians"] = p.gaussians;
            state["held_out_psnr_db"] =
                p.heldOutEvaluated ? py::object(py::float_(p.heldOutPsnr)) : py::object(py::none());
            state["setting_up"] = p.setUp ? py::object(py::float_(*p.setUp)) : py::object(py::none());
            state["brick"] = brick ? py::object(py::int_(*brick)) : py::object(py::none());
            (*progress)(state);
        } catch (py::error_already_set& error) {
            error.restore();
            throw PythonErrorPending{};
        }
    };
}

/// max_error: a number in the source's units, or text such as "0.5%" of its data range, or "auto".
using MaxError = std::variant<double, std::string>;

BoundRequest boundRequestOf(const MaxError& maxError, std::optional<double> ratio) {
    if (const auto* number = std::get_if<double>(&maxError)) return BoundRequest::exactly(*number, ratio.value_or(0.0));
    return {std::get<std::string>(maxError), ratio.value_or(0.0)};
}

/// A file, read as `gvr fit` reads it, or a Volume in memory.
FitInput fitInputOf(const std::variant<Volume, std::string>& input) {
    FitInput fitInput;
    if (const auto* path = std::get_if<std::string>(&input)) {
        fitInput.path = *path;
    } else {
        const Volume& volume = std::get<Volume>(input);
        fitInput.inMemory = {volume.grid, volume.labels, {}};
    }
    return fitInput;
}

/// Each line as a UserWarning, from a thread that does not hold the GIL.
void warnEach(const std::vector<std::string>& lines) {
    if (lines.empty()) return;
    py::gil_scoped_acquire acquire;
    for (const std::string& line : lines) {
        if (PyErr_WarnEx(PyExc_UserWarning, inPythonTerms(line).c_str(), 1) != 0) throw py::error_already_set();
    }
}

GaussianAsset fit(const std::variant<Volume, std::string>& input, std::optional<double> ratio,
                  std::optional<double> seconds, std::size_t gaussians, std::size_t iterations, std::uint64_t seed,
                  const std::string& ablation, const std::string& labels, std::size_t bricks, int halo,
                  const std::optional<py::function>& progress, double minSamples,
                  const std::optional<MaxError>& maxError) {
    // Each pair names one thing twice: say so, rather than let one of them win.
    if (ratio && gaussians > 0) throw InputError("`gaussians`", "cannot be combined with `ratio`: both set the count");
    if (seconds && iterations > 0)
        throw InputError("`iterations`", "cannot be combined with `seconds`: both end the fit");
    FitRequest request;
    BudgetedFitOptions& options = request.options;
    options.settings.minSamplesPerGaussian = minSamples;
    options.labels = labels;
    options.ratio = ratio.value_or(options.ratio);
    options.gaussians = gaussians;
    options.ablation = ablation;
    options.settings.seed = seed;
    options.settings.iterations = iterations;
    options.settings.seconds = iterations > 0 ? 0.0 : seconds.value_or(kDefaultFitSeconds);
    if (maxError) request.bound = boundRequestOf(*maxError, ratio);
    request.bricks = {bricks, halo};
    try {
        const WithoutGil released;
        const FitJob job(fitInputOf(input), std::move(request));
        FitJobObservers observers;
        observers.fit = pythonObserver(progress, {});
        observers.bricks = [&progress](std::size_t brick) { return pythonObserver(progress, brick); };
        FitOutcome outcome = job.run(observers);
        std::vector<std::string> warnings = job.warnings();
        const std::string undertrained =
            undertrainedNote(outcome.result, job.request().options.settings, "min_samples=");
        if (!undertrained.empty()) warnings.push_back(undertrained);
        warnEach(warnings);
        if (outcome.layer) return decodeAsset(outcome.result.file, job.name());
        return std::move(outcome.result.asset);
    } catch (const PythonErrorPending&) {
        throw py::error_already_set();
    }
}

// ---- assets ----

std::map<int, std::string> structuresOf(const GaussianAsset& asset) { return labelNamesOf(asset.labelTable); }

Volume exportVolume(const GaussianAsset& asset, const std::optional<std::variant<Volume, std::string>>& like,
                    std::optional<double> voxelSize, const std::string& layers) {
    if (like && voxelSize) throw InputError("voxel_size", "give like or voxel_size, not both");
    ExportSettings settings;
    settings.layers = parseAssetLayers(layers, "layers");
    if (like) {
        const auto* volume = std::get_if<Volume>(&*like);
        if (!volume && !std::filesystem::exists(std::get<std::string>(*like))) {
            // asset.export('x.nii.gz') once said only "no such file": the first argument is like=.
            throw InputError("like", "'" + std::get<std::string>(*like) +
                                         "' does not exist: like= names the volume whose "
                                         "voxels to export onto; to write the export, call asset.export().save(path)");
        }
        settings.lattice = volume ? latticeOf(*volume->grid, "like") : latticeLike(std::get<std::string>(*like));
    }
    if (voxelSize) settings.lattice = resizedLattice(asset.worldFromIndex, asset.source.dims, *voxelSize);
    const WithoutGil released;
    return {exportAsset(asset, settings).grids.front(), nullptr};
}

py::array probe(const GaussianAsset& asset, const py::object& points, const std::string& layers) {
    const auto p = py::array_t<double, py::array::forcecast>::ensure(asArray(points, "points"));
    if (!p || p.ndim() != 2 || p.shape(1) != 3) throw InputError("points", "must be an (n, 3) array of voxel indices");
    const AssetLayers chosen = parseAssetLayers(layers, "layers");
    const auto in = p.unchecked<2>();
    std::vector<std::array<double, 3>> indices(p.shape(0));
    for (py::ssize_t n = 0; n < p.shape(0); ++n) indices[n] = {in(n, 0), in(n, 1), in(n, 2)};
    std::vector<AssetProbe::Sample> samples;
    {
        const WithoutGil released;
        samples = probeAsset(asset, indices, chosen, "asset");
    }
    const int channels = asset.params.channels;
    py::array_t<double> values(std::vector<py::ssize_t>{p.shape(0), channels});
    auto out = values.mutable_unchecked<2>();
    for (py::ssize_t n = 0; n < p.shape(0); ++n) {
        for (int c = 0; c < channels; ++c) out(n, c) = samples[n].value[c];
    }
    return values;
}

/// One read-only (count, width) float64 array of a field of every world Gaussian.
template <std::size_t N>
py::array gaussianArray(const GaussianAsset& asset, std::array<double, N> WorldGaussian::*field, int width) {
    const std::vector<WorldGaussian> gaussians = worldGaussians(asset);
    py::array_t<double> out(std::vector<py::ssize_t>{py::ssize_t(gaussians.size()), width});
    auto view = out.mutable_unchecked<2>();
    for (std::size_t i = 0; i < gaussians.size(); ++i) {
        for (int c = 0; c < width; ++c) view(i, c) = (gaussians[i].*field)[c];
    }
    out.attr("flags").attr("writeable") = false;
    return out;
}

std::string sourceName(const VolumeMetadata& m) {
    return m.sourceFile.empty() ? "" : ", from " + std::filesystem::path(m.sourceFile).filename().string();
}

std::string reprOf(const Volume& volume) {
    const openvdb::Coord d = boxOf(volume).dim();
    std::ostringstream out;
    out << "<gvr.Volume " << d.x() << "x" << d.y() << "x" << d.z();
    if (const auto m = readVolumeMetadata(*volume.grid)) {
        out << " " << (m->channels == 3 ? "RGB " : "") << m->sourceType << ", " << m->spacingMm.x() << "x"
            << m->spacingMm.y() << "x" << m->spacingMm.z() << " mm" << sourceName(*m);
    }
    return out.str() + ">";
}

double ratioOf(const GaussianAsset& asset) {
    return double(asset.source.rawSourceBytes()) / double(assetFileBytes(asset));
}

std::string reprOf(const GaussianAsset& asset) {
    std::ostringstream out;
    out << "<gvr.Asset " << asset.params.count() << " Gaussians, " << assetFileBytes(asset) << " bytes (" << std::fixed
        << std::setprecision(1) << ratioOf(asset) << ":1 against the raw source), "
        << (asset.params.channels == 3 ? "RGB" : "grey") << ", source " << asset.source.dims.x() << "x"
        << asset.source.dims.y() << "x" << asset.source.dims.z() << sourceName(asset.source);
    if (!asset.labelTable.names.empty()) out << ", " << asset.labelTable.names.size() << " structures";
    return out.str() + ">";
}

// ---- render and evaluate ----

/// An Asset, a Volume, or a file of either (an asset, a .vdb, anything ingest reads).
using Renderable = std::variant<GaussianAsset, Volume, std::string>;
/// A preset name or a JSON file as `gvr render --tf` takes them, or the file's
/// points themselves: [[value, r, g, b, a], ...].
using TransferSpec = std::variant<std::string, std::vector<std::array<double, 5>>>;

Classifier classifierOf(const RenderVolume& volume, const TransferSpec& tf) {
    if (const auto* points = std::get_if<std::vector<std::array<double, 5>>>(&tf)) {
        std::vector<TransferPoint> converted;
        for (const auto& [value, r, g, b, a] : *points)
            converted.push_back({value, {float(r), float(g), float(b), float(a)}});
        return volumeClassifier(volume, TransferFunction(std::move(converted), "tf"));
    }
    return classifierFor(std::get<std::string>(tf), volume);
}

RenderInput renderInputOf(const Renderable& what, AssetLayers layers, float minScale) {
    if (const auto* asset = std::get_if<GaussianAsset>(&what)) {
        RenderInput input;
        input.asset = *asset;
        input.volume = assetRenderVolume(*asset, layers, minScale, "asset");
        return input;
    }
    if (const auto* volume = std::get_if<Volume>(&what)) {
        RenderInput input;
        input.volume = std::make_unique<GridRenderVolume>(volume->grid);
        return input;
    }
    return loadRenderInput(std::get<std::string>(what), "", "", layers, minScale, IngestOptions{});
}

/// label_style: a JSON file as `gvr render --label-style` reads, or a dict of the same.
using LabelStyleSpec = std::variant<std::string, py::dict>;

void addLabelStyles(const std::optional<LabelStyleSpec>& spec, RenderRequest& request) {
    if (!spec) return;
    if (const auto* path = std::get_if<std::string>(&*spec)) {
        request.labelStyles = readLabelStyles(*path);
        request.labelStylesName = *path;
        return;
    }
    const std::string text = py::str(py::module_::import("json").attr("dumps")(std::get<py::dict>(*spec)));
    request.labelStylesName = "label_style";
    request.labelStyles = parseLabelStyles(nlohmann::json::parse(text, nullptr, false), request.labelStylesName);
}

py::array render(const Renderable& what, double azimuth, double elevation, std::pair<int, int> size,
                 const TransferSpec& tf, double supersample, const std::string& classify, const std::string& layers,
                 const std::string& renderer, double step, int samples,
                 const std::optional<LabelStyleSpec>& labelStyle) {
    const auto [width, height] = size;
    if (width < 1 || height < 1 || width > kMaxImageSide || height > kMaxImageSide) {
        throw InputError("size", "must be (width, height) in 1 to " + std::to_string(kMaxImageSide) + " pixels");
    }
    RenderRequest request;
    const std::optional<RendererKind> kind = rendererNamed(renderer);
    if (!kind) throw InputError("renderer", "'" + renderer + "' is neither shear-warp nor raymarch");
    request.renderer = *kind;
    request.shearWarp.stacks = automaticStacks(1);  // as gvr render draws a still
    request.shearWarp.supersampling = supersample;
    const std::optional<Classification> classification = classificationNamed(classify);
    if (!classification) throw InputError("classify", "'" + classify + "' is neither points nor segments");
    request.shearWarp.classification = *classification;
    request.rayMarch.stepVoxels = step;
    request.rayMarch.raysPerSide = samples;
    if (const std::string problem = request.validate(); !problem.empty()) throw InputError("render", problem);
    addLabelStyles(labelStyle, request);
    const AssetLayers chosen = parseAssetLayers(layers, "layers");
    Framebuffer image;
    {
        const WithoutGil released;
        const RenderInput input = renderInputOf(what, chosen, request.minScale());
        const OrthoCamera camera = makeCamera(
            {azimuth, elevation}, worldCorners(input.volume->worldFromIndex(), input.volume->box()), width, height);
        RenderJob job(input, classifierOf(*input.volume, tf), request);
        FrameStats stats;
        image = job.render(camera, stats);
    }
    py::array_t<float> rgba(std::vector<py::ssize_t>{height, width, 4});
    std::copy(image.rgba.begin(), image.rgba.end(), rgba.mutable_data());
    return rgba;
}

using Comparable = std::variant<GaussianAsset, Volume, std::string>;

ComparisonInput comparisonInput(const Comparable& input) {
    if (const auto* asset = std::get_if<GaussianAsset>(&input)) {
        return comparisonInputOf(exportAsset(*asset, ExportSettings{}).grids.front(), "asset");
    }
    if (const auto* volume = std::get_if<Volume>(&input)) return comparisonInputOf(volume->grid, "volume");
    return loadComparisonInput(std::get<std::string>(input), IngestOptions{});
}

py::object evaluatePair(const Comparable& reference, const Comparable& test, EvalOptions options) {
    std::string json;
    {
        const WithoutGil released;
        json = jsonText(
            evalResultJson(evaluate(comparisonInput(reference), comparisonInput(test), options, "reference", "test")));
    }
    return py::module_::import("json").attr("loads")(json);
}

}  // namespace
}  // namespace gvr

PYBIND11_MODULE(gvr, m) {
    using namespace gvr;
    using namespace pybind11::literals;
    openvdb::initialize();
    m.doc() = "gvr: medical volumes as compact sets of 3D Gaussians, rendered with shear-warp";
    m.attr("__version__") = GVR_VERSION;
    static py::exception<InputError> error(m, "Error", PyExc_ValueError);
    py::module_::import("atexit").attr("register")(py::cpp_function([] { CallsInFlight::instance().stopAndWait(); }));
    py::register_exception_translator([](std::exception_ptr thrown) {
        try {
            if (thrown) std::rethrow_exception(thrown);
        } catch (const InputError& e) {
            error(inPythonTerms(e.what()).c_str());
        } catch (const InterpreterExiting& e) {
            PyErr_SetString(PyExc_SystemExit, e.what());  // which a thread ends on without a traceback
        }
    });

    py::class_<Volume>(m, "Volume",
                       "A volume as gvr holds it: a sparse OpenVDB grid in physical units (HU stays HU), "
                       "placed in world millimetres. Arrays are indexed [i, j, k] (x, y, z), as nibabel's "
                       "get_fdata() gives them, with RGB as a last axis of 3.")
        .def_static("from_numpy", &volumeFromNumpy, "array"_a, "spacing"_a = py::none(), "affine"_a = py::none(),
                    "threshold"_a = py::none(), "modality"_a = "", "nan_to"_a = py::none(), "source_type"_a = "",
                    "A volume from a 3-D array (x, y, z) or (x, y, z, 3) of uint8 to float64 (bool becomes "
                    "uint8, float16 float32, int64 int32 when its values fit, else float64). Give the voxel "
                    "spacing in mm or nibabel's 4x4 affine (default: 1 mm voxels at the origin). Voxels at or "
                    "below threshold (default: the minimum; -950 for modality='CT') are inactive. The samples are "
                    "copied once, in their own type; NaN or Inf raises gvr.Error unless nan_to replaces them. "
                    "source_type ('uint8', 'int16', ...) names the type the source file stored: a fit's ratio "
                    "is against metadata['raw_bytes'], voxels x channels x its size (default: the array's "
                    "type, so np.asarray(img.dataobj) of a scaled uint8 NIfTI, float64, would count 8 bytes, and a "
                    "float64 array without source_type gives a UserWarning). Lists and tuples are taken as numpy "
                    "takes them.")
        .def_static("from_nibabel", &volumeFromNibabel, "image"_a, "threshold"_a = py::none(), "modality"_a = "",
                    "nan_to"_a = py::none(),
                    "A volume from a nibabel image, as from_numpy(np.asarray(image.dataobj), affine=image.affine, "
                    "source_type=str(image.get_data_dtype())) would make it: its scaling applied, and a fit's ratio "
                    "counted against the type the file stores. RGB images get a last axis of 3.")
        .def("to_numpy", &volumeToNumpy,
             "The samples as float32 in physical units, shape (x, y, z) or (x, y, z, 3), inactive voxels "
             "at the background value; the array owns them (no further copy).")
        .def_property_readonly("affine", &affineOf, "nibabel's convention: world mm = affine @ (i, j, k, 1)")
        .def_property_readonly("metadata", &metadataOf,
                               "Where the volume came from, its value range and type, and raw_bytes: the size "
                               "that fit's ratio divides")
        .def("__repr__", [](const Volume& v) { return reprOf(v); })
        .def_property_readonly("shape",
                               [](const Volume& v) {
                                   const openvdb::Coord d = boxOf(v).dim();
                                   return py::make_tuple(d.x(), d.y(), d.z());
                               })
        .def_property_readonly(
            "structures",
            [](const Volume& v) {
                return v.labels ? labelNamesOf(labelTableOf(*v.labels)) : std::map<int, std::string>{};
            },
            "Structure names by label id (empty without labels)")
        .def(
            "save",
            [](const Volume& v, const std::string& path) {
                checkVolumeOutputs("path", {path}, {});
                openvdb::GridCPtrVec grids{v.grid};
                if (v.labels) grids.push_back(v.labels);
                const NiftiStorage storage = ingestedNiftiStorage(*v.grid, false);
                const WithoutGil released;
                writeVolumeOutputs({path}, grids, volumeBox(*v.grid), storage);
            },
            "path"_a,
            "Write the volume (atomically) in the format its extension names, as `gvr ingest -o` does: .vdb "
            "with its labels, or .nii/.nii.gz in the source's sample type; any other extension raises gvr.Error");

    m.def("ingest", &ingestPath, "path"_a, "threshold"_a = py::none(), "spacing"_a = py::none(),
          "nan_to"_a = py::none(), "volume"_a = 0, "labels"_a = "", "label_names"_a = "", "resample_labels"_a = false,
          "Read any volume gvr ingest reads (NIfTI, DICOM series, MetaImage, MGH, image stacks, raw, .vdb) "
          "into a Volume, as `gvr ingest` does; labels: a label volume (an atlas) on the same voxels, named "
          "from label_names (\"ID NAME\" lines), for fit(labels=...). A .vdb keeps the labels ingest stored.");

    py::class_<GaussianAsset>(m, "Asset", "Fitted Gaussians with what places them and maps their values")
        .def_static("load", &readAsset, "path"_a, "Read a .gvr asset (format 1 or 2)")
        .def(
            "save", [](GaussianAsset& a, const std::string& path) { writeAsset(path, a); }, "path"_a,
            "Write the asset (atomically), in storage order")
        .def("__repr__", [](const GaussianAsset& a) { return reprOf(a); })
        .def_property_readonly("count", [](const GaussianAsset& a) { return a.params.count(); })
        .def_property_readonly("bytes", &assetFileBytes, "The size of its .gvr file in bytes, as save() writes it")
        .def_property_readonly("ratio", &ratioOf,
                               "The source's raw bytes (metadata['raw_bytes'] of the volume it was fitted to) over "
                               "bytes; for its PSNR, gvr.evaluate(volume, asset)['psnr']")
        .def_property_readonly(
            "means", [](const GaussianAsset& a) { return gaussianArray(a, &WorldGaussian::mean, 3); },
            "(count, 3) centres in world mm (the source's scanner space, RAS); read-only")
        .def_property_readonly(
            "scales", [](const GaussianAsset& a) { return gaussianArray(a, &WorldGaussian::scale, 3); },
            "(count, 3) standard deviations in mm along each Gaussian's axes, ascending; read-only")
        .def_property_readonly(
            "rotations", [](const GaussianAsset& a) { return gaussianArray(a, &WorldGaussian::rotation, 4); },
            "(count, 4) unit quaternions (w, x, y, z), w >= 0, turning the world axes onto the "
            "Gaussian's (the columns of R, covariance = R diag(scales^2) R^T); read-only")
        .def_property_readonly(
            "amplitudes",
            [](const GaussianAsset& a) { return gaussianArray(a, &WorldGaussian::amplitude, a.params.channels); },
            "(count, channels) peak over the background in physical units (opacity x colour, "
            "mapped): the field is background + sum amplitude exp(-d^T C^-1 d / 2) within "
            "the asset's cutoff; read-only")
        .def_property_readonly("channels", [](const GaussianAsset& a) { return a.params.channels; })
        .def_property_readonly(
            "max_error",
            [](const GaussianAsset& a) {
                return a.residual ? py::object(py::float_(a.residual->bound)) : py::object(py::none());
            },
            "The residual layer's bound in the source's units (None without one), as `gvr info` lists it")
        .def_property_readonly("structures", &structuresOf,
                               "Structure names by label id (empty unless fitted by label)")
        .def("export", &exportVolume, "like"_a = py::none(), "voxel_size"_a = py::none(), "layers"_a = "all",
             "The field on a grid: the source's own (default), another volume's (like= a Volume or a file "
             "ingest reads), or voxels of voxel_size mm over the source's extent. layers: all (the Gaussians "
             "and the residual layer of fit(max_error=...), which holds its bound on the source's own grid "
             "only) or gaussians (the preview), as `gvr export --layers`")
        .def("probe", &probe, "points"_a, "layers"_a = "all",
             "Values in physical units at an (n, 3) array of source voxel indices. layers: all (with the residual "
             "layer of fit(max_error=...), its reconstruction: within the bound at voxel centres, trilinear "
             "between them) or gaussians (the preview), as `gvr probe --layers`")
        .def(
            "show",
            [](const GaussianAsset& a, const std::string& show, const std::string& hide) {
                return selectStructures(a, show, hide, "asset");
            },
            "structures"_a = "", "hide"_a = "",
            "The asset with only these structures of a fit by label (ids or names, comma-separated; empty: "
            "all), less those in hide, as gvr render --show and --hide select them");

    // New arguments come last, so that positional calls written before them still mean what they did.
    m.def("fit", &fit, "volume"_a, "ratio"_a = py::none(), "seconds"_a = py::none(), "gaussians"_a = 0,
          "iterations"_a = 0, "seed"_a = 1, "ablation"_a = "full", "labels"_a = "", "bricks"_a = 0,
          "halo"_a = kDefaultBrickHalo, "progress"_a = py::none(), "min_samples"_a = 0.0, "max_error"_a = py::none(),
          "Fit Gaussians to a Volume or a file (anything gvr ingest reads), as `gvr fit` does: as many as fit in the "
          "raw bytes / ratio "
          "(default 10; or exactly `gaussians`, not both), within `seconds` (default 300; or exactly `iterations`, "
          "reproducible byte for byte, not both). When the "
          "time gives each Gaussian fewer than 1000 voxel samples, a UserWarning says so, with the time that "
          "would; min_samples=N instead trades Gaussians for training (fewer, so a higher ratio). `progress` "
          "is called with a dict after each iteration. Ctrl-C stops the fit with KeyboardInterrupt. labels: fit "
          "by structure (all, or ids and names) from the volume's labels, as `gvr fit --labels`. bricks: fit in "
          "that many bricks of whole 8^3 leaves (each seeing `halo` voxels around it) and merge them, as `gvr fit "
          "--bricks`; the progress dict then says which brick. max_error: a number in the source's units, or a "
          "string such as '0.5%' of its data range: add a residual layer so that every voxel of asset.export() "
          "on the source's grid is within it (the Gaussians then default to a 400:1 preview), as `gvr fit "
          "--max-error`; or 'auto' with ratio: the smallest such bound with which the whole asset fits ratio "
          "(asset.max_error says which).");
    m.def("render", &render, "what"_a, "azimuth"_a = 30.0, "elevation"_a = 15.0,
          "size"_a = std::pair<int, int>(512, 512), "tf"_a = "", "supersample"_a = ShearWarpSettings{}.supersampling,
          "classify"_a = "points", "layers"_a = "all", "renderer"_a = "shear-warp",
          "step"_a = RayMarchSettings{}.stepVoxels, "samples"_a = 1, "label_style"_a = py::none(),
          "A view of an Asset, a Volume or a file of either as premultiplied RGBA float32, shape (height, "
          "width, 4), "
          "as `gvr render` draws it. tf: a preset (ct, ct-bone, mri, rgb; default: by the data), a JSON file "
          "as `gvr render --tf` and `--save-tf` use, or its points [[value, r, g, b, a], ...] in physical units. "
          "supersample: stack samples along each side of a pixel, 1 to 4, as `gvr render --supersample`. "
          "classify: points or segments (pre-integrated), as `gvr render --classify`. layers: all (an asset "
          "with the residual layer of fit(max_error=...) is drawn from its bounded reconstruction) or gaussians "
          "(the preview), as `gvr render --layers`. renderer: shear-warp, or raymarch (the reference), with step "
          "(voxels, at most 0.5) and samples (n x n rays a pixel), as `gvr render --renderer --step --samples`. "
          "label_style: per-structure colour and opacity of an asset fitted with labels, a dict {name or id: "
          "{'color': [r, g, b], 'opacity': factor}} or a JSON file of one, as `gvr render --label-style`");
    m.def(
        "evaluate",
        [](const Comparable& reference, const Comparable& test, bool resample, std::optional<double> peak,
           const std::string& mask, std::optional<double> threshold, const std::string& labels,
           const std::string& labelNames, const std::string& structures) {
            EvalOptions options;
            options.resample = resample;
            options.peak = peak;
            options.mask = mask;
            options.threshold = threshold;
            options.labels = labels;
            options.labelNames = labelNames;
            options.structures = structures;
            return evaluatePair(reference, test, options);
        },
        "reference"_a, "test"_a, "resample"_a = false, "peak"_a = py::none(), "mask"_a = "", "threshold"_a = py::none(),
        "labels"_a = "", "label_names"_a = "", "structures"_a = "",
        "Compare two Volumes, Assets or files: a dict with the keys of `gvr eval --json`. The options are "
        "eval's: mask and labels are files (a .vdb or any volume ingest reads, e.g. an atlas such as "
        "aal.nii.gz), label_names an \"ID NAME\" list for an atlas, structures ids or names to report.");
}
