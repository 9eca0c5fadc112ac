#include "bench/BenchRun.h"

#include "bench/ChildProcess.h"
#include "bench/ExternalCodec.h"
#include "io/formats/GridFile.h"
#include "pipeline/Error.h"
#include "pipeline/FloatVolume.h"
#include "pipeline/VolumeMetadata.h"
#include "render/RayMarcher.h"
#include "workflow/BaselineCodecs.h"
#include "workflow/FramePath.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace gvr {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

/// A step of a run that failed; its message becomes the row's.
struct StepFailure : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// A run that cannot start on this machine (a codec's program is missing): the row
/// is marked skipped, not failed.
struct RunSkipped : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// A number from gvr's JSON: "inf" is +infinity, null or anything else NaN.
double jsonDouble(const json& value) { return value.is_number() ? value.get<double>() : NAN; }

/// A PSNR from eval's JSON, where a perfect match is a null beside an MSE of 0.
double psnrIn(const json& psnr, const json& mse) {
    if (psnr.is_null() && mse.is_number() && mse.get<double>() == 0.0) return INFINITY;
    return jsonDouble(psnr);
}

/// What a compressor left behind for evaluation.
struct Reconstruction {
    double bytes = 0, compressSeconds = NAN, decompressSeconds = NAN, peakRssMiB = 0;
    std::string grid;         ///< reconstruction on the source's grid, for eval
    std::string renderInput;  ///< what the renderer reads: the asset itself for gvr
    std::string detail, fitLog;
};

/// The frames `gvr render -o folder/stem.png --orbit frames` writes.
std::vector<std::string> framePaths(const std::string& folder, const std::string& stem, int frames) {
    std::vector<std::string> paths;
    for (int f = 0; f < frames; ++f) paths.push_back(framePath(folder + "/" + stem + ".png", f, frames));
    return paths;
}

class VolumeRunner {
public:
    VolumeRunner(const BenchContext& context, const BenchVolume& volume)
        : mContext(context),
          mVolume(volume),
          mPlan(context.manifest->render),
          mWork(context.folder + "/work/" + volume.name) {}

    void run(const std::vector<BenchUnit>& units) {
        std::string failure;
        const bool pending = hasPendingRows(units);
        try {
            if (pending) prepare();
        } catch (const StepFailure& error) {
            failure = error.what();
        }
        for (const BenchUnit& unit : units) {
            for (const std::string& method : unit.methods) {
                BenchRow row = baseRow(unit, method);
                if (mContext.table->find(row.key())) continue;
                if (failure.empty()) {
                    measure(unit, method, row);
                } else {
                    fail(row, failure);
                }
                mContext.table->append(row);
                if (mContext.onRow) mContext.onRow(row);
            }
        }
        std::error_code ignored;
        if (pending)
            fs::remove_all(mWork + "/raw", ignored);  // as large as the volume in float32, and rewritten each run
    }

private:
    bool hasPendingRows(const std::vector<BenchUnit>& units) const {
        for (const BenchUnit& unit : units) {
            for (const std::string& method : unit.methods) {
                if (!mContext.table->find(baseRow(unit, method).key())) return true;
            }
        }
        return false;
    }

    /// Runs `gvr ARGS --json`; its JSON output. @throw StepFailure naming @a step.
    json gvr(const std::string& step, std::vector<std::string> args, const std::string& log,
             ChildResult* measured = nullptr) {
        args.insert(args.begin(), mContext.executable);
        args.push_back("--json");
        const ChildResult result = runChild(args, log);
        if (measured) *measured = result;
        if (!result.ok()) {
            std::string message = result.lastError;
            for (const std::string prefix : {"gvr: error: ", "gvr: "}) {
                if (message.rfind(prefix, 0) == 0) message = message.substr(prefix.size());
            }
            throw StepFailure(step + " failed (exit " + std::to_string(result.exitCode) +
                              "): " + (message.empty() ? "no message; see " + relative(log) : message));
        }
        const json output = json::parse(result.output, nullptr, /*allow_exceptions=*/false);
        if (output.is_discarded()) throw StepFailure(step + " printed no JSON; see " + relative(log));
        return output;
    }

    std::string relative(const std::string& path) const {
        return fs::path(path).lexically_relative(mContext.folder).string();
    }

    /// The source as a grid, its size in bytes, and ray-marched views of it.
    void prepare() {
        refuseLinksBelow(mContext.folder, mWork + "/raw");
        fs::create_directories(mWork);
        const std::string log = mWork + "/log.txt";
        mSource = mWork + "/source.vdb";
        if (!fs::exists(mSource)) {
            std::vector<std::string> args = {"ingest", mVolume.input, "-o", mSource, "-q"};
            args.insert(args.end(), mVolume.ingestArgs.begin(), mVolume.ingestArgs.end());
            gvr("ingest", args, log);
        }
        readSourceSize();
        mTf = mWork + "/tf.json";
        mTruth = framePaths(mWork, "truth", mPlan.views);
        const bool rendered = fs::exists(mTf) && std::all_of(mTruth.begin(), mTruth.end(),
                                                             [](const std::string& p) { return fs::exists(p); });
        if (!rendered) {
            std::vector<std::string> args = renderArgs(mSource, mWork + "/truth.png");
            // The anti-aliased reference, several rays a pixel: every render-quality figure's.
            args.insert(args.end(), {"--renderer", "raymarch", "--samples", std::to_string(kReferenceRaysPerSide),
                                     "--save-tf", mTf});
            if (!mPlan.tf.empty()) args.insert(args.end(), {"--tf", mPlan.tf});
            gvr("reference render", args, log);
        }
    }

    void readSourceSize() {
        try {
            const auto grids = readGridMetadataFile(mSource);
            const std::optional<VolumeMetadata> metadata = readVolumeMetadata(*chooseVolumeGrid(*grids, mSource));
            if (!metadata) throw StepFailure("ingest: " + relative(mSource) + " has no gvr metadata");
            mRawBytes = double(metadata->rawSourceBytes());
            mVoxels = double(metadata->dims.x()) * metadata->dims.y() * metadata->dims.z();
            mChannels = metadata->channels;
        } catch (const InputError& error) {
            throw StepFailure(std::string("ingest: ") + error.what());
        }
    }

    std::vector<std::string> renderArgs(const std::string& input, const std::string& output) const {
        return {"render",      input,
                "-o",          output,
                "--orbit",     std::to_string(mPlan.views),
                "--azimuth",   "0",
                "--elevation", std::to_string(mPlan.elevation),
                "--size",      mPlan.size,
                "-q"};
    }

    BenchRow baseRow(const BenchUnit& unit, const std::string& method) const {
        BenchRow row;
        row.set("volume", mVolume.name);
        row.set("ratio", ratioText(unit.ratio));
        row.set("method", method);
        return row;
    }

    static void fail(BenchRow& row, const std::string& message) {
        row.set("status", "failed");
        row.set("message", message);
    }

    void measure(const BenchUnit& unit, const std::string& method, BenchRow& row) {
        const std::string folder = mContext.folder + "/runs/" + mVolume.name + "/" +
                                   (unit.ratio ? "r" + ratioText(unit.ratio) + "/" : std::string()) + method;
        try {
            refuseLinksBelow(mContext.folder, folder);
            fs::remove_all(folder);  // leftovers of a killed attempt
            fs::create_directories(folder);
            const ExternalCodec* codec = mContext.manifest->codec(method);
            const Reconstruction r = isFitMethod(method) ? fit(unit, method, folder)
                                     : codec             ? external(unit, *codec, folder)
                                                         : baseline(unit, method, folder);
            recordSize(r, row);
            evaluateVolume(r, folder, row);
            evaluateViews(r, folder, row);
            fs::remove(r.grid);  // large, and fully described by the row
            row.set("status", "ok");
        } catch (const StepFailure& error) {
            fail(row, error.what());
        } catch (const RunSkipped& skipped) {
            row.set("status", "skipped");
            row.set("message", skipped.what());
        } catch (const std::exception& error) {
            fail(row, std::string("bench: ") + error.what());
        }
    }

    Reconstruction fit(const BenchUnit& unit, const std::string& method, const std::string& folder) {
        const std::string log = folder + "/log.txt", asset = folder + "/asset.gvr";
        Reconstruction r;
        r.fitLog = folder + "/fit.csv";
        const bool bounded = method == "gvr+bound";
        std::vector<std::string> args = {"fit",        mSource,
                                         "-o",         asset,
                                         "--ratio",    ratioText(unit.ratio),
                                         "--ablation", method == "gvr" || bounded ? "full" : method,
                                         "--log",      r.fitLog,
                                         "-q"};
        if (bounded) args.insert(args.end(), {"--max-error", "auto"});
        const FitBudget& budget = mVolume.fit;
        if (budget.iterations) {
            args.insert(args.end(), {"--iterations", std::to_string(*budget.iterations)});
        } else {
            args.insert(args.end(), {"--time", std::to_string(budget.seconds)});
        }
        const bool threadsGiven = std::find(budget.args.begin(), budget.args.end(), "--threads") != budget.args.end();
        if (mContext.fitThreads > 0 && !threadsGiven) {
            args.insert(args.end(), {"--threads", std::to_string(mContext.fitThreads)});
        }
        args.insert(args.end(), budget.args.begin(), budget.args.end());
        ChildResult fitRun, exportRun;
        const json fitted = gvr("fit", args, log, &fitRun);
        r.bytes = double(fs::file_size(asset));
        r.compressSeconds = jsonDouble(fitted["seconds"]);
        r.grid = folder + "/reconstruction.vdb";
        gvr("export", {"export", asset, "-o", r.grid, "-q"}, log, &exportRun);
        r.decompressSeconds = exportRun.seconds;
        r.peakRssMiB = std::max(fitRun.peakRssMiB, exportRun.peakRssMiB);
        r.renderInput = asset;
        r.detail = std::to_string(fitted.value("gaussians", 0)) + " Gaussians, " +
                   std::to_string(fitted.value("iterations", 0)) + " iterations";
        if (bounded) {
            std::ostringstream bound;
            bound << ", every voxel within " << jsonDouble(fitted["residual_layer"]["max_error"]);
            r.detail += bound.str();
        }
        return r;
    }

    /// gvr's asset size at this ratio: what the ZFP runs match.
    double gvrBytes(const BenchUnit& unit) const {
        BenchRow gvrRow = baseRow(unit, "gvr");
        const std::optional<BenchRow> found = mContext.table->find(gvrRow.key());
        const std::optional<double> bytes = found ? found->number("bytes") : std::nullopt;
        if (!found || found->get("status") != "ok" || !bytes) {
            throw StepFailure("needs the size of gvr's asset at this ratio, but method gvr " +
                              std::string(found ? "failed" : "was not run"));
        }
        return *bytes;
    }

    Reconstruction baseline(const BenchUnit& unit, const std::string& method, const std::string& folder) {
        const std::string log = folder + "/log.txt";
        Reconstruction r;
        r.grid = r.renderInput = folder + "/reconstruction.vdb";
        const bool zfp = method.rfind("zfp", 0) == 0;
        const std::string stream = folder + (zfp ? "/stream.zfp" : "/stream.vdb");
        std::vector<std::string> args = {"baseline", mSource, "-o", r.grid, "--stream", stream, "-q", "--method"};
        if (method == "zfp-accuracy") {
            args.insert(args.end(), {"zfp-accuracy", "--target-bytes", std::to_string(std::uint64_t(gvrBytes(unit)))});
        } else if (method == "zfp-rate") {
            const double rate = 8.0 * gvrBytes(unit) / (mVoxels * mChannels);
            args.insert(args.end(), {"zfp-rate", "--rate", std::to_string(rate)});
        } else if (method.rfind("down", 0) == 0) {
            args.insert(args.end(), {"downsample", "--factor", method.substr(4)});
        } else {
            args.push_back(method);
        }
        ChildResult run;
        const json result = gvr("baseline", args, log, &run);
        r.bytes = double(fs::file_size(stream));
        r.compressSeconds = jsonDouble(result["compress_s"]);
        r.decompressSeconds = jsonDouble(result["decompress_s"]);
        r.peakRssMiB = run.peakRssMiB;
        r.detail = baselineDetail(result);
        return r;
    }

    /// The size an external codec aims at: gvr's asset's where the manifest runs gvr,
    /// else the target ratio's share of the raw source.
    std::uint64_t codecTarget(const BenchUnit& unit) const {
        const auto& methods = mContext.manifest->methods;
        if (std::find(methods.begin(), methods.end(), "gvr") != methods.end()) return std::uint64_t(gvrBytes(unit));
        return std::max<std::uint64_t>(1, std::uint64_t(std::llround(mRawBytes / *unit.ratio)));
    }

    Reconstruction external(const BenchUnit& unit, const ExternalCodec& codec, const std::string& folder) {
        for (const auto* args : {&codec.compress, &codec.decompress}) {
            if (findProgram(args->front()).empty()) {
                throw RunSkipped("codec " + codec.name + ": program '" + args->front() + "' not found" +
                                 (args->front().find('/') == std::string::npos ? " on PATH" : ""));
            }
        }
        const std::uint64_t target = codecTarget(unit);
        const RawChannels& raw = rawChannels();
        CodecResult result;
        try {
            result = runExternalCodec(codec, raw, target, folder, folder + "/log.txt");
        } catch (const CodecFailure& error) {
            throw StepFailure(codec.name + ": " + error.what());
        }
        Reconstruction r;
        r.bytes = double(result.bytes);
        r.compressSeconds = result.compressSeconds;
        r.decompressSeconds = result.decompressSeconds;
        r.peakRssMiB = result.peakRssMiB;
        r.grid = r.renderInput = folder + "/reconstruction.vdb";
        FloatVolume decoded;
        decoded.dims = mRawPlacement.dims;
        decoded.channels = mRawPlacement.channels;
        decoded.worldFromIndex = mRawPlacement.worldFromIndex;
        decoded.values = std::move(result.values);
        try {
            writeGridFile(r.grid, {reconstructionOf(*mSourceShell, std::move(decoded), folder + "/compressed.c0")});
        } catch (const InputError& error) {
            throw StepFailure(std::string("reconstruction: ") + error.what());
        }
        std::ostringstream detail;
        detail << std::setprecision(4) << "param " << result.param;
        if (!result.matched) detail << " (size not matched within 5%)";
        r.detail = detail.str();
        return r;
    }

    /// The source's channels as raw float32 files, written on first use, with the
    /// source's grid kept without its voxels for the reconstructions.
    const RawChannels& rawChannels() {
        if (!mRaw.files.empty()) return mRaw;
        try {
            const auto grids = readGridFile(mSource);
            const openvdb::GridBase::Ptr grid = chooseVolumeGrid(*grids, mSource);
            const FloatVolume samples = sampleGrid(*grid, volumeBox(*grid));
            fs::create_directories(mWork + "/raw");
            mRaw = writeRawChannels(samples, mWork + "/raw");
            mRawPlacement.dims = samples.dims;
            mRawPlacement.channels = samples.channels;
            mRawPlacement.worldFromIndex = samples.worldFromIndex;
            mSourceShell = grid->copyGridWithNewTree();
        } catch (const InputError& error) {
            throw StepFailure(std::string("raw channels: ") + error.what());
        } catch (const CodecFailure& error) {
            throw StepFailure(std::string("raw channels: ") + error.what());
        }
        return mRaw;
    }

    static std::string baselineDetail(const json& result) {
        std::ostringstream text;
        text << std::setprecision(4);
        if (result.contains("tolerance")) text << "tolerance " << jsonDouble(result["tolerance"]);
        if (result.contains("rate")) text << "rate " << jsonDouble(result["rate"]) << " bits/value";
        if (result.contains("factor")) text << "factor " << result["factor"];
        if (result.contains("matched") && !result["matched"].get<bool>()) text << " (size not matched within 5%)";
        return text.str();
    }

    void recordSize(const Reconstruction& r, BenchRow& row) const {
        row.set("bytes", r.bytes);
        row.set("ratio_raw", mRawBytes / r.bytes);
        row.set("ratio_float32", mVoxels * mChannels * 4.0 / r.bytes);
        row.set("bits_per_voxel", 8.0 * r.bytes / mVoxels);
        row.set("compress_s", r.compressSeconds);
        row.set("decompress_s", r.decompressSeconds);
        row.set("peak_rss_mib", r.peakRssMiB);
        row.set("detail", r.detail);
        if (!r.fitLog.empty()) row.set("fit_log", relative(r.fitLog));
    }

    void evaluateVolume(const Reconstruction& r, const std::string& folder, BenchRow& row) {
        const json e = gvr("eval", {"eval", mSource, r.grid}, folder + "/log.txt");
        row.set("psnr", psnrIn(e["psnr"], e["mse"]));
        row.set("fg_psnr", psnrIn(e["fg_psnr"], e["fg_mse"]));
        for (const char* key : {"ssim", "ms_ssim", "max_error"}) row.set(key, jsonDouble(e[key]));
    }

    /// Renders the views and scores each against the ray-marched original.
    void evaluateViews(const Reconstruction& r, const std::string& folder, BenchRow& row) {
        const std::string log = folder + "/log.txt";
        std::vector<std::string> args = renderArgs(r.renderInput, folder + "/view.png");
        args.insert(args.end(), {"--tf", mTf});
        const json frames = gvr("render", args, log)["frames"];
        double totalMs = 0;
        for (const json& frame : frames) totalMs += jsonDouble(frame["total_ms"]);
        row.set("render_fps", frames.size() * 1000.0 / totalMs);
        const std::vector<std::string> views = framePaths(folder, "view", mPlan.views);
        double psnr = 0, ssim = 0;
        for (std::size_t v = 0; v < views.size(); ++v) {
            const json e = gvr("view eval", {"eval", mTruth[v], views[v]}, log);
            psnr += psnrIn(e["rendering"]["psnr"], e["mse"]) / views.size();
            ssim += jsonDouble(e["ssim"]) / views.size();
        }
        row.set("render_psnr", psnr);
        row.set("render_ssim", ssim);
        std::vector<std::string> viewNames, truthNames;
        for (const std::string& p : views) viewNames.push_back(relative(p));
        for (const std::string& p : mTruth) truthNames.push_back(relative(p));
        row.setList("views", viewNames);
        row.setList("truth_views", truthNames);
    }

    const BenchContext& mContext;
    const BenchVolume& mVolume;
    const RenderPlan& mPlan;
    const std::string mWork;
    std::string mSource, mTf;
    std::vector<std::string> mTruth;
    double mRawBytes = 0, mVoxels = 0;
    int mChannels = 1;
    RawChannels mRaw;
    FloatVolume mRawPlacement;                 ///< dims, channels and placement of mRaw; no values
    openvdb::GridBase::ConstPtr mSourceShell;  ///< the source's name, transform and metadata
};

}  // namespace

void runVolumeUnits(const BenchContext& context, const std::vector<BenchUnit>& units) {
    if (units.empty()) return;
    VolumeRunner(context, context.manifest->volumes[units.front().volume]).run(units);
}

}  // namespace gvr
