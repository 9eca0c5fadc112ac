#include "bench/ExternalCodec.h"

#include "bench/ChildProcess.h"
#include "io/guard/AtomicFile.h"
#include "workflow/BaselineCodecs.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

namespace gvr {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

const std::regex& placeholderPattern() {
    static const std::regex pattern(R"(\{([A-Za-z_]+)\})");
    return pattern;
}

bool isPlaceholder(const std::string& name) {
    for (const char* known : {"input", "compressed", "output", "nx", "ny", "nz", "param"}) {
        if (name == known) return true;
    }
    return false;
}

/// %.9g: a float parameter round-trips, and no codec sees "1e-05" written another way.
std::string parameterText(double param) {
    char text[32];
    std::snprintf(text, sizeof text, "%.9g", param);
    return text;
}

/// The most trials a size search makes: each step inside a bracket shrinks it by a
/// quarter at least, so 16 reach far finer than the 5 % the sizes need.
constexpr int kMaxTrials = 16;

/// One run of a template over every channel.
struct CommandRuns {
    double seconds = 0, peakRssMiB = 0;
};

class CodecRunner {
public:
    CodecRunner(const ExternalCodec& codec, const RawChannels& raw, std::string folder, std::string log)
        : mCodec(codec),
          mRaw(raw),
          mFolder(std::move(folder)),
          mLog(std::move(log)),
          mCompress(withProgramFound("compress", codec.compress)),
          mDecompress(withProgramFound("decompress", codec.decompress)),
          mDeadline(Clock::now() +
                    std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(codec.timeoutSeconds))) {}

    struct Trial {
        double param = 0;
        std::uint64_t bytes = 0;
        CommandRuns runs;
    };

    /// Compresses every channel with @a param into @a folder; the files' total size.
    Trial compress(double param, const std::string& folder) {
        Trial trial{param, 0, {}};
        for (std::size_t c = 0; c < mRaw.files.size(); ++c) {
            const std::string compressed = compressedFile(folder, c);
            fs::remove(compressed);
            run("compress", mCompress, c, param, compressed, "", trial.runs);
            std::error_code error;
            const std::uintmax_t size = fs::file_size(compressed, error);
            if (error || size == 0) {
                throw CodecFailure("compress (" + where(c, param) + ") wrote " +
                                   (error ? "no file " : "an empty file ") + compressed);
            }
            trial.bytes += size;
        }
        return trial;
    }

    /// Decompresses the kept files; the values, channels interleaved.
    std::vector<float> decompress(double param, CommandRuns& runs) {
        const std::uint64_t voxels = mRaw.voxels();
        const std::size_t channels = mRaw.files.size();
        std::vector<float> values(voxels * channels);
        std::vector<float> channel(voxels);
        for (std::size_t c = 0; c < channels; ++c) {
            const std::string output = mFolder + "/decoded.c" + std::to_string(c) + ".f32";
            fs::remove(output);
            run("decompress", mDecompress, c, param, compressedFile(mFolder, c), output, runs);
            readChannel(output, c, param, channel);
            fs::remove(output);
            for (std::uint64_t v = 0; v < voxels; ++v) values[v * channels + c] = channel[v];
        }
        return values;
    }

    static std::string compressedFile(const std::string& folder, std::size_t channel) {
        return folder + "/compressed.c" + std::to_string(channel);
    }

private:
    /// @a templateArgs with its program's path, looked up once for the whole row.
    static std::vector<std::string> withProgramFound(const std::string& step, std::vector<std::string> templateArgs) {
        const std::string program = findProgram(templateArgs.front());
        if (program.empty()) throw CodecFailure(step + ": program '" + templateArgs.front() + "' not found");
        templateArgs.front() = program;
        return templateArgs;
    }

    std::string where(std::size_t channel, double param) const {
        return "channel " + std::to_string(channel) + ", param " + parameterText(param);
    }

    std::vector<std::string> substitute(const std::vector<std::string>& templateArgs, std::size_t channel, double param,
                                        const std::string& compressed, const std::string& output) const {
        const auto value = [&](const std::string& name) -> std::string {
            if (name == "input") return mRaw.files[channel];
            if (name == "compressed") return compressed;
            if (name == "output") return output;
            if (name == "nx") return std::to_string(mRaw.dims.x());
            if (name == "ny") return std::to_string(mRaw.dims.y());
            if (name == "nz") return std::to_string(mRaw.dims.z());
            return parameterText(param);
        };
        std::vector<std::string> args;
        for (const std::string& arg : templateArgs) {
            std::string filled;
            std::size_t copied = 0;
            for (std::sregex_iterator m(arg.begin(), arg.end(), placeholderPattern()), end; m != end; ++m) {
                filled += arg.substr(copied, std::size_t(m->position()) - copied) + value((*m)[1].str());
                copied = std::size_t(m->position() + m->length());
            }
            args.push_back(filled + arg.substr(copied));
        }
        return args;
    }

    void run(const std::string& step, const std::vector<std::string>& templateArgs, std::size_t channel, double param,
             const std::string& compressed, const std::string& output, CommandRuns& runs) {
        const std::vector<std::string> args = substitute(templateArgs, channel, param, compressed, output);
        const double left = std::chrono::duration<double>(mDeadline - Clock::now()).count();
        const ChildResult result = left > 0 ? runChild(args, mLog, left) : ChildResult{};
        runs.seconds += result.seconds;
        runs.peakRssMiB = std::max(runs.peakRssMiB, result.peakRssMiB);
        if (left <= 0 || result.timedOut) {
            throw CodecFailure(step + " (" + where(channel, param) + ") ran past the row's time limit of " +
                               parameterText(mCodec.timeoutSeconds) + " s and was killed");
        }
        if (!result.ok()) {
            throw CodecFailure(step + " (" + where(channel, param) + ") failed (exit " +
                               std::to_string(result.exitCode) + ")" +
                               (result.lastError.empty() ? "" : ": " + result.lastError));
        }
    }

    void readChannel(const std::string& path, std::size_t channel, double param, std::vector<float>& values) const {
        const std::uint64_t expected = values.size() * sizeof(float);
        std::error_code error;
        const std::uintmax_t size = fs::file_size(path, error);
        const std::string dims = std::to_string(mRaw.dims.x()) + " x " + std::to_string(mRaw.dims.y()) + " x " +
                                 std::to_string(mRaw.dims.z());
        if (error) throw CodecFailure("decompress (" + where(channel, param) + ") wrote no file " + path);
        if (size != expected) {
            throw CodecFailure("decompress (" + where(channel, param) + ") wrote " + std::to_string(size) + " bytes; " +
                               dims + " float32 voxels are " + std::to_string(expected));
        }
        std::ifstream in(path, std::ios::binary);
        if (!in.read(reinterpret_cast<char*>(values.data()), std::streamsize(expected))) {
            throw CodecFailure("decompress: cannot read " + path);
        }
        const auto bad = std::find_if(values.begin(), values.end(), [](float v) { return !std::isfinite(v); });
        if (bad != values.end()) {
            throw CodecFailure("decompress (" + where(channel, param) + ") gave a non-finite value at voxel " +
                               std::to_string(bad - values.begin()) + " of " + dims);
        }
    }

    const ExternalCodec& mCodec;
    const RawChannels& mRaw;
    const std::string mFolder, mLog;
    const std::vector<std::string> mCompress, mDecompress;  ///< the templates, programs found
    const Clock::time_point mDeadline;                      ///< for the whole row
};

using Trial = CodecRunner::Trial;

/// How far a size lies from the target, on a log scale: 0 on it, negative below.
double miss(const Trial& trial, std::uint64_t target) { return std::log(double(trial.bytes) / double(target)); }

bool withinSlack(std::uint64_t bytes, std::uint64_t target) {
    return std::abs(double(bytes) / double(target) - 1.0) <= kTargetBytesSlack;
}

/// Where the next trial goes, on log(param). Between the two trials nearest to
/// each other in the parameter whose sizes lie on either side of the target: the
/// secant point, kept to the middle half of their interval so that the interval
/// shrinks by a quarter at least each time (codecs' sizes can jump, and need not
/// even be monotonic in a narrow range, as SZ3's are not). Without such a pair:
/// the secant through the two nearest trials, clamped to the range. nullopt when
/// that leads nowhere new: the target lies beyond the range's end, or between two
/// sizes that no parameter in between separates.
std::optional<double> nextTrial(const std::vector<Trial>& trials, std::uint64_t target, double lo, double hi) {
    if (trials.empty()) return 0.5 * (lo + hi);
    if (trials.size() == 1) return std::log(trials[0].param) + (hi - lo) / 8;
    const Trial *below = nullptr, *above = nullptr;
    for (const Trial& b : trials) {
        for (const Trial& a : trials) {
            if (!(miss(b, target) < 0 && miss(a, target) > 0)) continue;
            const double width = std::abs(std::log(a.param) - std::log(b.param));
            if (!below || width < std::abs(std::log(above->param) - std::log(below->param))) below = &b, above = &a;
        }
    }
    double x;
    if (below) {
        const double xb = std::log(below->param), xa = std::log(above->param);
        if (std::abs(xa - xb) < 1e-4) return std::nullopt;  // parameters 0.01 % apart: the same setting
        const double mb = miss(*below, target), ma = miss(*above, target);
        x = xb + std::clamp(mb / (mb - ma), 0.25, 0.75) * (xa - xb);
    } else {
        std::vector<const Trial*> nearest;
        for (const Trial& t : trials) nearest.push_back(&t);
        std::sort(nearest.begin(), nearest.end(), [&](const Trial* a, const Trial* b) {
            return std::abs(miss(*a, target)) < std::abs(miss(*b, target));
        });
        const double x0 = std::log(nearest[0]->param), x1 = std::log(nearest[1]->param);
        const double m0 = miss(*nearest[0], target), m1 = miss(*nearest[1], target);
        x = (m0 == m1) ? (std::abs(x0 - lo) > std::abs(x0 - hi) ? lo : hi) : x0 - m0 * (x1 - x0) / (m1 - m0);
        x = std::clamp(x, lo, hi);
    }
    for (const Trial& t : trials) {
        if (std::abs(std::log(t.param) - x) < 1e-9) return std::nullopt;
    }
    return x;
}

}  // namespace

std::string unknownPlaceholder(const std::vector<std::string>& templateArgs) {
    for (const std::string& arg : templateArgs) {
        for (std::sregex_iterator m(arg.begin(), arg.end(), placeholderPattern()), end; m != end; ++m) {
            if (!isPlaceholder((*m)[1].str())) return m->str();
        }
    }
    return "";
}

std::string findProgram(const std::string& program) {
    const auto runnable = [](const fs::path& p) { return fs::is_regular_file(p) && access(p.c_str(), X_OK) == 0; };
    if (program.find('/') != std::string::npos) return runnable(program) ? fs::absolute(program).string() : "";
    const char* path = std::getenv("PATH");
    std::istringstream folders(path ? path : "");
    for (std::string folder; std::getline(folders, folder, ':');) {
        const fs::path candidate = fs::path(folder.empty() ? "." : folder) / program;
        if (runnable(candidate)) return fs::absolute(candidate).string();
    }
    return "";
}

RawChannels writeRawChannels(const FloatVolume& volume, const std::string& folder) {
    RawChannels raw;
    raw.dims = volume.dims;
    std::vector<float> channel(volume.voxelCount());
    for (int c = 0; c < volume.channels; ++c) {
        for (std::size_t v = 0; v < channel.size(); ++v) channel[v] = volume.values[v * volume.channels + c];
        raw.files.push_back(folder + "/channel" + std::to_string(c) + ".f32");
        writeAtomically(raw.files.back(), [&](const std::string& temporary) {
            std::ofstream out(temporary, std::ios::binary);
            out.write(reinterpret_cast<const char*>(channel.data()), std::streamsize(channel.size() * sizeof(float)));
            if (!out.flush()) throw CodecFailure("cannot write " + raw.files.back());
        });
    }
    return raw;
}

CodecResult runExternalCodec(const ExternalCodec& codec, const RawChannels& raw, std::uint64_t targetBytes,
                             const std::string& folder, const std::string& logPath) {
    for (const auto* templateArgs : {&codec.compress, &codec.decompress}) {
        if (templateArgs->empty()) throw CodecFailure("codec " + codec.name + " has an empty command");
        if (const std::string unknown = unknownPlaceholder(*templateArgs); !unknown.empty()) {
            throw CodecFailure("unknown placeholder " + unknown + " in codec " + codec.name +
                               "'s command; known: {input} {compressed} {output} {nx} {ny} {nz} {param}");
        }
    }
    CodecRunner runner(codec, raw, folder, logPath);
    const std::string trialFolder = folder + "/trial";
    fs::create_directories(trialFolder);
    const double lo = std::log(codec.paramMin), hi = std::log(codec.paramMax);
    std::vector<Trial> trials;
    std::optional<Trial> best;
    while (int(trials.size()) < kMaxTrials) {
        const std::optional<double> x = nextTrial(trials, targetBytes, lo, hi);
        if (!x) break;
        trials.push_back(runner.compress(std::exp(*x), trialFolder));
        std::ofstream(logPath, std::ios::app)
            << codec.name << ": param " << parameterText(trials.back().param) << " -> " << trials.back().bytes
            << " bytes (target " << targetBytes << ")\n";
        if (!best || std::abs(miss(trials.back(), targetBytes)) < std::abs(miss(*best, targetBytes))) {
            best = trials.back();
            for (std::size_t c = 0; c < raw.files.size(); ++c) {
                fs::rename(CodecRunner::compressedFile(trialFolder, c), CodecRunner::compressedFile(folder, c));
            }
        }
        if (withinSlack(best->bytes, targetBytes)) break;
    }
    fs::remove_all(trialFolder);
    CodecResult result;
    result.bytes = best->bytes;
    result.param = best->param;
    result.matched = withinSlack(best->bytes, targetBytes);
    result.compressSeconds = best->runs.seconds;
    CommandRuns decompression;
    result.values = runner.decompress(best->param, decompression);
    result.decompressSeconds = decompression.seconds;
    result.peakRssMiB = std::max(best->runs.peakRssMiB, decompression.peakRssMiB);
    return result;
}

}  // namespace gvr
