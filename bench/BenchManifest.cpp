#include "bench/BenchManifest.h"

#include "io/guard/InputFile.h"
#include "pipeline/Error.h"

#include <nlohmann/json.hpp>
#include <toml++/toml.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <set>
#include <sstream>

namespace gvr {

namespace fs = std::filesystem;
using nlohmann::json;

const std::vector<std::string>& benchMethods() {
    static const std::vector<std::string> methods = {"gvr",      "gvr+bound", "A1",           "A2",       "A3",
                                                     "A4",       "A5",        "zfp-accuracy", "zfp-rate", "vdb-blosc",
                                                     "vdb-half", "down2",     "down3",        "down4"};
    return methods;
}

const std::vector<std::string>& defaultBenchMethods() {
    static const std::vector<std::string> methods = [] {
        std::vector<std::string> all = benchMethods();
        all.erase(std::find(all.begin(), all.end(), "gvr+bound"));
        return all;
    }();
    return methods;
}

bool isRatioFree(const std::string& method) {
    return method == "vdb-blosc" || method == "vdb-half" || method.rfind("down", 0) == 0;
}

bool isFitMethod(const std::string& method) {
    return method == "gvr" || method == "gvr+bound" ||
           (method.size() == 2 && method[0] == 'A' && method[1] >= '1' && method[1] <= '5');
}

namespace {

/// A parser callback that records in @a duplicate the first key an object holds
/// twice: the JSON parser keeps the last silently, so a manifest would run what its
/// writer did not mean. (TOML refuses duplicate keys itself.)
json::parser_callback_t duplicateKeyFinder(std::string& duplicate) {
    auto keysByDepth = std::make_shared<std::vector<std::set<std::string>>>();
    return [keysByDepth, &duplicate](int depth, json::parse_event_t event, json& parsed) {
        if (event == json::parse_event_t::object_start) {
            keysByDepth->resize(std::size_t(depth) + 1);
            keysByDepth->back().clear();
        } else if (event == json::parse_event_t::key) {
            const std::size_t object = std::size_t(depth) - 1;  // a key lies one level below its object's start
            const std::string name = parsed.get<std::string>();
            if (object < keysByDepth->size() && !(*keysByDepth)[object].insert(name).second && duplicate.empty()) {
                duplicate = name;
            }
        }
        return true;
    };
}

/// TOML manifests become the same JSON document, so there is one reader of keys.
json parseDocument(const std::string& path) {
    requireRegularFile(path);
    std::ifstream in(path);
    if (!in) throw InputError(path, "cannot open the manifest");
    std::stringstream text;
    text << in.rdbuf();
    const std::string extension = fs::path(path).extension().string();
    if (extension == ".toml") {
        try {
            std::ostringstream asJson;
            asJson << toml::json_formatter{toml::parse(text.str(), path)};
            return json::parse(asJson.str());
        } catch (const toml::parse_error& error) {
            throw InputError(path, "not valid TOML at line " + std::to_string(error.source().begin.line) + ": " +
                                       std::string(error.description()));
        }
    }
    std::string duplicate;
    const json document = json::parse(text.str(), duplicateKeyFinder(duplicate), /*allow_exceptions=*/false);
    if (document.is_discarded()) throw InputError(path, "not valid JSON (TOML manifests must end in .toml)");
    if (!duplicate.empty()) throw InputError(path, "the key '" + duplicate + "' appears twice in one object");
    return document;
}

/// "scans/ch2.nii.gz" -> "ch2".
std::string nameFromPath(const std::string& path) {
    fs::path name = fs::path(path).filename();
    if (name.extension() == ".gz") name = name.stem();
    return name.stem().string();
}

constexpr std::size_t kLongestName = 64;
constexpr const char* kNameCharacters = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789._+-";

/// The largest side of the bench's views: views to compare, each ray-marched again
/// as the reference at every ratio (8192 x 8192 views took far too long).
constexpr int kLargestViewSide = 2048;

class ManifestReader {
public:
    explicit ManifestReader(std::string path) : mPath(std::move(path)) {}

    [[noreturn]] void fail(const std::string& where, const std::string& problem) const {
        throw InputError(mPath, where + ": " + problem);
    }

    void onlyKeys(const json& object, const std::string& where, const std::set<std::string>& allowed) const {
        if (!object.is_object()) fail(where, "must be a table/object");
        for (const auto& [key, value] : object.items()) {
            if (!allowed.count(key)) fail(where, "unknown key '" + key + "'");
        }
    }

    std::string text(const json& value, const std::string& where) const {
        if (!value.is_string()) fail(where, "must be a string");
        return value.get<std::string>();
    }

    /// A count: 0.5 views once became 0 and a render PSNR of 0.
    std::int64_t wholeNumber(const json& value, const std::string& where, double most = 1e6) const {
        const double number = positive(value, where);
        if (number != std::floor(number) || number > most)
            fail(where, "must be a whole number up to " + std::to_string(std::int64_t(most)));
        return std::int64_t(number);
    }

    double positive(const json& value, const std::string& where) const {
        if (!value.is_number() || !std::isfinite(value.get<double>()) || value.get<double>() <= 0) {
            fail(where, "must be a positive number");
        }
        return value.get<double>();
    }

    std::vector<std::string> strings(const json& value, const std::string& where) const {
        if (!value.is_array()) fail(where, "must be a list of strings");
        std::vector<std::string> out;
        for (const json& item : value) {
            if (!item.is_string()) fail(where, "must be a list of strings");
            out.push_back(item.get<std::string>());
        }
        return out;
    }

    std::vector<double> ratios(const json& value, const std::string& where) const {
        if (!value.is_array() || value.empty()) fail(where, "must be a non-empty list of ratios");
        std::vector<double> out;
        for (const json& item : value) {
            const double r = positive(item, where);
            if (r <= 1.0) fail(where, "a target ratio must be above 1");
            if (std::find(out.begin(), out.end(), r) != out.end()) fail(where, "lists " + ratioText(r) + " twice");
            out.push_back(r);
        }
        return out;
    }

    FitBudget fit(const json& value, FitBudget budget, const std::string& where) const {
        onlyKeys(value, where, {"seconds", "iterations", "args"});
        if (value.contains("seconds")) budget.seconds = positive(value["seconds"], where + ".seconds");
        if (value.contains("iterations")) {
            budget.iterations = std::uint64_t(wholeNumber(value["iterations"], where + ".iterations", 1e9));
        }
        if (value.contains("args")) budget.args = strings(value["args"], where + ".args");
        return budget;
    }

    RenderPlan render(const json& value) const {
        onlyKeys(value, "render", {"size", "views", "elevation", "tf"});
        RenderPlan plan;
        if (value.contains("size")) plan.size = viewSize(text(value["size"], "render.size"));
        if (value.contains("views")) plan.views = int(wholeNumber(value["views"], "render.views"));
        if (value.contains("elevation")) {
            if (!value["elevation"].is_number()) fail("render.elevation", "must be a number of degrees");
            plan.elevation = value["elevation"].get<double>();
        }
        if (value.contains("tf")) {  // a preset name, or a JSON file beside the manifest
            plan.tf = text(value["tf"], "render.tf");
            if (fs::path(plan.tf).extension() == ".json") plan.tf = resolve(plan.tf);
        }
        if (plan.views > 360) fail("render.views", "at most 360");
        return plan;
    }

    std::string viewSize(const std::string& size) const {
        int width = 0, height = 0;
        char x = 0;
        std::istringstream in(size);
        if (!(in >> width >> x >> height) || x != 'x' || !(in >> std::ws).eof() || width < 1 || height < 1 ||
            width > kLargestViewSide || height > kLargestViewSide) {
            fail("render.size", "'" + size + "' is not WIDTHxHEIGHT of 1 to " + std::to_string(kLargestViewSide) +
                                    " pixels each, e.g. 256x256");
        }
        return size;
    }

    std::vector<std::string> methods(const json& value, const std::vector<ExternalCodec>& codecs) const {
        std::vector<std::string> out = strings(value, "methods");
        std::vector<std::string> known = benchMethods();
        for (const ExternalCodec& codec : codecs) known.push_back(codec.name);
        for (const std::string& m : out) {
            if (std::find(known.begin(), known.end(), m) == known.end()) {
                std::string list;
                for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
                fail("methods",
                     "unknown method '" + m + "'; known: " + list + " (and codecs declared under \"codecs\")");
            }
        }
        if (out.empty()) fail("methods", "must name at least one method");
        return out;
    }

    std::vector<ExternalCodec> codecs(const json& value) const {
        if (!value.is_object()) fail("codecs", "must be a table/object of codec name -> commands");
        std::vector<ExternalCodec> out;
        for (const auto& [name, spec] : value.items()) out.push_back(codec(name, spec));
        return out;
    }

    ExternalCodec codec(const std::string& name, const json& spec) const {
        const std::string where = "codecs." + name;
        const auto& builtIn = benchMethods();
        if (std::find(builtIn.begin(), builtIn.end(), name) != builtIn.end())
            fail(where, "is a built-in method's name");
        checkName(name, where);
        onlyKeys(spec, where, {"compress", "decompress", "param", "version", "timeout"});
        ExternalCodec codec;
        codec.name = name;
        for (const char* key : {"compress", "decompress"}) {
            if (!spec.contains(key)) fail(where, std::string("needs a \"") + key + "\" command");
            std::vector<std::string> args = strings(spec[key], where + "." + key);
            if (args.empty() || args.front().empty()) fail(where + "." + key, "must start with the program");
            if (args.front().find('/') != std::string::npos) args.front() = resolve(args.front());
            (std::string(key) == "compress" ? codec.compress : codec.decompress) = args;
        }
        if (!spec.contains("param") || !spec["param"].is_array() || spec["param"].size() != 2) {
            fail(where + ".param", "must be [smallest, largest]: the quality parameter's search range");
        }
        codec.paramMin = positive(spec["param"][0], where + ".param");
        codec.paramMax = positive(spec["param"][1], where + ".param");
        if (codec.paramMin >= codec.paramMax) fail(where + ".param", "the smallest must lie below the largest");
        if (spec.contains("version")) {
            if (spec["version"].is_string()) {
                codec.version = spec["version"].get<std::string>();
            } else {
                codec.versionCommand = strings(spec["version"], where + ".version");
                if (codec.versionCommand.empty()) fail(where + ".version", "must be a text or a command");
                if (codec.versionCommand.front().find('/') != std::string::npos) {
                    codec.versionCommand.front() = resolve(codec.versionCommand.front());
                }
            }
        }
        if (spec.contains("timeout")) codec.timeoutSeconds = positive(spec["timeout"], where + ".timeout");
        return codec;
    }

    /// Names become folders, CSV cells and plot names: ".." once made a row write
    /// beside the results, and a name with a '/' let one row's folder hold another's.
    void checkName(const std::string& name, const std::string& where) const {
        const bool safe = !name.empty() && name.size() <= kLongestName && name.front() != '.' &&
                          name.find_first_not_of(kNameCharacters) == std::string::npos;
        if (!safe) {
            fail(where, "'" + name + "' is not a name: up to " + std::to_string(kLongestName) +
                            " letters, digits, '.', '_', '+' or '-', not starting with '.'");
        }
    }

    BenchVolume volume(const json& value, std::size_t index, const std::vector<double>& ratios,
                       const FitBudget& fitBudget) const {
        const std::string where = "volumes[" + std::to_string(index) + "]";
        onlyKeys(value, where, {"name", "input", "ingest", "ratios", "fit"});
        if (!value.contains("input")) fail(where, "needs an \"input\" path");
        BenchVolume v;
        v.input = resolve(text(value["input"], where + ".input"));
        v.name = value.contains("name") ? text(value["name"], where + ".name") : nameFromPath(v.input);
        checkName(v.name, where + ".name");
        if (value.contains("ingest")) v.ingestArgs = strings(value["ingest"], where + ".ingest");
        v.ratios = value.contains("ratios") ? this->ratios(value["ratios"], where + ".ratios") : ratios;
        v.fit = value.contains("fit") ? fit(value["fit"], fitBudget, where + ".fit") : fitBudget;
        return v;
    }

    /// Relative paths are relative to the manifest. Missing files are left for ingest
    /// to judge, so that a missing volume becomes a failed row, not a refused manifest.
    std::string resolve(const std::string& given) const {
        const fs::path p(given);
        const fs::path full = p.is_absolute() ? p : fs::absolute(fs::path(mPath).parent_path() / p);
        return full.lexically_normal().string();
    }

private:
    std::string mPath;
};

}  // namespace

BenchManifest readBenchManifest(const std::string& path) {
    const json document = parseDocument(path);
    const ManifestReader reader(path);
    reader.onlyKeys(document, "top level", {"name", "ratios", "methods", "codecs", "fit", "render", "volumes"});
    BenchManifest manifest;
    manifest.path = path;
    if (document.contains("codecs")) manifest.codecs = reader.codecs(document["codecs"]);
    if (document.contains("methods")) {
        manifest.methods = reader.methods(document["methods"], manifest.codecs);
    } else {
        manifest.methods = defaultBenchMethods();
        for (const ExternalCodec& codec : manifest.codecs) manifest.methods.push_back(codec.name);
    }
    const std::vector<double> ratios =
        document.contains("ratios") ? reader.ratios(document["ratios"], "ratios") : std::vector<double>{10.0};
    const FitBudget budget = document.contains("fit") ? reader.fit(document["fit"], FitBudget{}, "fit") : FitBudget{};
    if (document.contains("render")) manifest.render = reader.render(document["render"]);
    if (!document.contains("volumes") || !document["volumes"].is_array() || document["volumes"].empty()) {
        reader.fail("volumes", "must list at least one volume");
    }
    std::set<std::string> names;
    for (std::size_t i = 0; i < document["volumes"].size(); ++i) {
        manifest.volumes.push_back(reader.volume(document["volumes"][i], i, ratios, budget));
        if (!names.insert(manifest.volumes.back().name).second) {
            reader.fail("volumes[" + std::to_string(i) + "]", "duplicate name '" + manifest.volumes.back().name + "'");
        }
    }
    return manifest;
}

std::vector<BenchUnit> benchUnits(const BenchManifest& manifest, int shard, int shards) {
    // In benchMethods() order, then the codecs', whatever the manifest's: ZFP and the
    // codecs match the size of gvr's asset, so gvr runs first.
    std::vector<std::string> order = benchMethods();
    for (const ExternalCodec& codec : manifest.codecs) order.push_back(codec.name);
    std::vector<std::string> chosen;
    for (const std::string& m : order) {
        if (std::find(manifest.methods.begin(), manifest.methods.end(), m) != manifest.methods.end())
            chosen.push_back(m);
    }
    std::vector<BenchUnit> all;
    for (std::size_t v = 0; v < manifest.volumes.size(); ++v) {
        BenchUnit ratioFree{v, std::nullopt, {}};
        for (const std::string& m : chosen) {
            if (isRatioFree(m)) ratioFree.methods.push_back(m);
        }
        if (!ratioFree.methods.empty()) all.push_back(ratioFree);
        for (double r : manifest.volumes[v].ratios) {
            BenchUnit unit{v, r, {}};
            for (const std::string& m : chosen) {
                if (!isRatioFree(m)) unit.methods.push_back(m);
            }
            if (!unit.methods.empty()) all.push_back(unit);
        }
    }
    std::vector<BenchUnit> mine;
    for (std::size_t i = 0; i < all.size(); ++i) {
        if (int(i % std::size_t(shards)) == shard) mine.push_back(all[i]);
    }
    return mine;
}

const ExternalCodec* BenchManifest::codec(const std::string& method) const {
    const auto found =
        std::find_if(codecs.begin(), codecs.end(), [&](const ExternalCodec& c) { return c.name == method; });
    return found == codecs.end() ? nullptr : &*found;
}

std::string ratioText(std::optional<double> ratio) {
    if (!ratio) return "";
    // The shortest text that reads back as the same number: with six digits, 8 and
    // 8.0000001 were one row.
    char text[32];
    const auto written = std::to_chars(text, text + sizeof text, *ratio);
    return std::string(text, written.ptr);
}

}  // namespace gvr
