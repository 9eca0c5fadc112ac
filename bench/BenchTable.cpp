#include "bench/BenchTable.h"

#include "io/formats/JsonText.h"
#include "io/guard/AtomicFile.h"
#include "pipeline/Error.h"
#include "workflow/ReportNumbers.h"

#include <fcntl.h>
#include <nlohmann/json.hpp>
#include <sys/file.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace gvr {

namespace fs = std::filesystem;

const std::vector<std::string>& benchColumns() {
    static const std::vector<std::string> columns = {
        "volume",       "ratio",         "method",         "status",      "message",    "bytes",
        "ratio_raw",    "ratio_float32", "bits_per_voxel", "psnr",        "fg_psnr",    "ssim",
        "ms_ssim",      "max_error",     "render_psnr",    "render_ssim", "compress_s", "decompress_s",
        "peak_rss_mib", "render_fps",    "detail",         "fit_log",     "views",      "truth_views"};
    return columns;
}

namespace {

const std::set<std::string>& textColumns() {
    static const std::set<std::string> columns = {"volume", "method", "status", "message", "detail", "fit_log"};
    return columns;
}

bool isListColumn(const std::string& column) { return column == "views" || column == "truth_views"; }

std::string csvCell(const std::string& text) {
    if (text.find_first_of(",\"\n") == std::string::npos) return text;
    std::string quoted = "\"";
    for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
    return quoted + "\"";
}

std::string csvLine(const BenchRow& row) {
    std::string line;
    for (const std::string& column : benchColumns()) {
        line += (line.empty() ? "" : ",") + csvCell(row.get(column));
    }
    return line + "\n";
}

/// One CSV record (RFC 4180 quoting; cells never hold newlines, set() removes them).
std::vector<std::string> splitCsv(const std::string& line) {
    std::vector<std::string> cells(1);
    bool quoted = false;
    for (std::size_t i = 0; i < line.size(); ++i) {
        const char c = line[i];
        if (quoted && c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
            cells.back() += '"';
            ++i;
        } else if (c == '"') {
            quoted = !quoted;
        } else if (c == ',' && !quoted) {
            cells.emplace_back();
        } else {
            cells.back() += c;
        }
    }
    return cells;
}

nlohmann::json typedCell(const BenchRow& row, const std::string& column) {
    if (isListColumn(column)) return row.list(column);
    const std::string text = row.get(column);
    if (textColumns().count(column)) return text;
    const std::optional<double> value = row.number(column);
    return value ? jsonNumber(*value) : nlohmann::json(nullptr);
}

void writeText(const std::string& path, const std::string& text) {
    writeAtomically(path, [&](const std::string& temporary) {
        std::ofstream out(temporary, std::ios::binary);
        out << text;
        if (!out.flush()) throw InputError(path, "cannot write");
    });
}

}  // namespace

void BenchRow::set(const std::string& column, const std::string& text) {
    std::string clean = text;
    for (char& c : clean) {
        if (c == '\n' || c == '\r') c = ' ';
    }
    cells[column] = clean;
}

void BenchRow::set(const std::string& column, double value) {
    if (std::isinf(value) && value > 0) {
        cells[column] = "inf";
    } else if (std::isfinite(value)) {
        char text[32];
        std::snprintf(text, sizeof text, "%.10g", value);
        cells[column] = text;
    } else {
        cells[column] = "";
    }
}

void BenchRow::setList(const std::string& column, const std::vector<std::string>& items) {
    std::string joined;
    for (const std::string& item : items) joined += (joined.empty() ? "" : ";") + item;
    set(column, joined);
}

std::string BenchRow::get(const std::string& column) const {
    const auto it = cells.find(column);
    return it == cells.end() ? std::string() : it->second;
}

std::optional<double> BenchRow::number(const std::string& column) const {
    const std::string text = get(column);
    if (text == "inf") return INFINITY;
    char* end = nullptr;
    const double value = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0') return std::nullopt;
    return value;
}

std::vector<std::string> BenchRow::list(const std::string& column) const {
    std::vector<std::string> items;
    std::istringstream in(get(column));
    for (std::string item; std::getline(in, item, ';');) {
        if (!item.empty()) items.push_back(item);
    }
    return items;
}

std::string resultsCsvHeader() {
    std::string line;
    for (const std::string& column : benchColumns()) line += (line.empty() ? "" : ",") + column;
    return line + "\n";
}

std::string benchRowKey(const std::string& volume, const std::string& ratio, const std::string& method) {
    return volume + "|" + ratio + "|" + method;
}

std::string BenchRow::key() const { return benchRowKey(get("volume"), get("ratio"), get("method")); }

namespace {

/// What a run writes in a row's cells: a status the bench knows, numbers where numbers
/// go, and a size for each measured row. Anything else did not come from a run.
void checkRowCells(const std::string& path, const BenchRow& row, std::size_t index) {
    const std::string where = "row " + std::to_string(index) + " (" + row.key() + ")";
    const std::string status = row.get("status");
    if (status != "ok" && status != "failed" && status != "skipped") {
        throw InputError(path, where + " has status '" + status + "', which the bench never writes");
    }
    for (const std::string& column : benchColumns()) {
        if (textColumns().count(column) || isListColumn(column) || row.get(column).empty()) continue;
        if (!row.number(column))
            throw InputError(path, where + ": " + column + " is '" + row.get(column) + "', not a number");
    }
    if (status == "ok" && !(row.number("bytes").value_or(0.0) > 0.0)) {
        throw InputError(path, where + " is measured but has no size in bytes");
    }
}

/// More than any benchmark writes (a row is about a kilobyte): a file this large
/// is not a results table, and reading it whole once hung --resume.
constexpr std::uintmax_t kLargestResultsCsv = 64u << 20;

}  // namespace

std::vector<BenchRow> readResultsCsv(const std::string& path, std::size_t* tornBytes) {
    std::error_code error;
    const fs::file_status status = fs::symlink_status(path, error);
    if (fs::is_symlink(status))
        throw InputError(path, "is a symbolic link; the bench reads and writes only files it made");
    if (fs::exists(status) && !fs::is_regular_file(status)) throw InputError(path, "is not a regular file");
    if (fs::exists(status) && fs::file_size(path) > kLargestResultsCsv) {
        throw InputError(path, "is " + std::to_string(fs::file_size(path)) + " bytes, more than a bench writes (" +
                                   std::to_string(kLargestResultsCsv >> 20) + " MiB at most)");
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path, "cannot open the results");
    std::stringstream buffer;
    buffer << in.rdbuf();
    std::string text = buffer.str();
    const std::size_t complete = text.rfind('\n') == std::string::npos ? 0 : text.rfind('\n') + 1;
    if (tornBytes) *tornBytes = text.size() - complete;
    text.resize(complete);
    std::istringstream lines(text);
    std::string line;
    if (!std::getline(lines, line) || line + "\n" != resultsCsvHeader()) {
        throw InputError(path, "is not a gvr bench results.csv (its header differs)");
    }
    std::vector<BenchRow> rows;
    std::map<std::string, std::size_t> seen;  // key -> row number
    while (std::getline(lines, line)) {
        const std::vector<std::string> cells = splitCsv(line);
        if (cells.size() != benchColumns().size()) {
            throw InputError(path, "row " + std::to_string(rows.size() + 1) + " has " + std::to_string(cells.size()) +
                                       " cells, not " + std::to_string(benchColumns().size()));
        }
        BenchRow row;
        for (std::size_t c = 0; c < cells.size(); ++c) row.cells[benchColumns()[c]] = cells[c];
        checkRowCells(path, row, rows.size() + 1);
        if (const auto earlier = seen.find(row.key()); earlier != seen.end()) {
            throw InputError(path, "row " + std::to_string(rows.size() + 1) + " repeats row " +
                                       std::to_string(earlier->second) + " (" + row.key() + ")");
        }
        seen[row.key()] = rows.size() + 1;
        rows.push_back(row);
    }
    return rows;
}

ManifestRecord manifestRecordOf(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return {path, ""};
    std::stringstream text;
    text << in.rdbuf();
    const std::string bytes = text.str();
    const uLong crc = crc32(crc32(0L, Z_NULL, 0), reinterpret_cast<const Bytef*>(bytes.data()), uInt(bytes.size()));
    char hex[9];
    std::snprintf(hex, sizeof hex, "%08lx", crc);
    return {path, hex};
}

ManifestRecord recordedManifest(const std::string& resultsJson) {
    std::ifstream in(resultsJson);
    const nlohmann::json document = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
    ManifestRecord record;
    if (document.is_discarded() || !document.is_object()) return record;
    if (document.contains("manifest") && document["manifest"].is_string()) record.path = document["manifest"];
    if (document.contains("manifest_crc32") && document["manifest_crc32"].is_string()) {
        record.digest = document["manifest_crc32"];
    }
    return record;
}

void writeResultsJson(const std::string& path, const ManifestRecord& manifest, const std::vector<BenchRow>& rows) {
    nlohmann::json out = {{"manifest", manifest.path}, {"rows", nlohmann::json::array()}};
    if (!manifest.digest.empty()) out["manifest_crc32"] = manifest.digest;
    for (const BenchRow& row : rows) {
        nlohmann::json typed = nlohmann::json::object();
        nlohmann::json infinite = nlohmann::json::array();
        for (const std::string& column : benchColumns()) {
            typed[column] = typedCell(row, column);
            if (typed[column].is_null() && row.number(column) == INFINITY) infinite.push_back(column);
        }
        // JSON has no infinity: a lossless row's PSNRs are null, and named here.
        typed["infinite"] = infinite;
        out["rows"].push_back(typed);
    }
    writeText(path, jsonText(out, 1) + "\n");
}

void writeResultsCsv(const std::string& path, const std::vector<BenchRow>& rows) {
    std::string text = resultsCsvHeader();
    for (const BenchRow& row : rows) text += csvLine(row);
    writeText(path, text);
}

void refuseLinksBelow(const std::string& folder, const std::string& path) {
    const fs::path relative = fs::path(path).lexically_relative(folder);
    fs::path walked = folder;
    for (const fs::path& part : relative) {
        if (part == "." || part.empty()) continue;
        walked /= part;
        if (fs::is_symlink(walked)) {
            throw InputError(walked.string(), "is a symbolic link; the bench writes and removes only what it made");
        }
    }
}

namespace {

/// A folder resumed with another manifest would mix two benchmarks' rows in one
/// report, and so would one whose manifest was edited since: the rows were run with
/// its old budgets. Folders written before digests were kept are judged by path.
void checkSameManifest(const std::string& folder, const std::string& resultsJson, const ManifestRecord& manifest) {
    const ManifestRecord earlier = recordedManifest(resultsJson);
    if (earlier.path.empty()) return;  // rebuilt from the CSV
    if (!earlier.digest.empty() && earlier.digest != manifest.digest) {
        throw InputError(folder, "holds the results of " + earlier.path + " as it was (CRC-32 " + earlier.digest +
                                     "), not of " + manifest.path + " as it is (" + manifest.digest +
                                     "); resume with that manifest, or run the edited one into another folder");
    }
    std::error_code error;
    if (!earlier.digest.empty() || earlier.path == manifest.path ||
        fs::equivalent(earlier.path, manifest.path, error)) {
        return;
    }
    throw InputError(
        folder, "holds the results of " + earlier.path + "; resume it with that manifest, or choose another folder");
}

/// What a bench leaves in its results folder: each is a file or folder it made, never a link.
const std::vector<std::string>& ownEntries() {
    static const std::vector<std::string> entries = {
        "results.csv", "results.json", "codecs.json", "codecs.log", "run.json", "bench_report.py",
        "report.md",   "report.log",   "plots",       "runs",       "work"};
    return entries;
}

void checkOwnEntries(const std::string& folder) {
    for (const std::string& entry : ownEntries()) {
        const fs::path path = fs::path(folder) / entry;
        refuseLinksBelow(folder, path.string());
        const bool isFolder = entry == "plots" || entry == "runs" || entry == "work";
        if (fs::exists(path) && (isFolder ? !fs::is_directory(path) : !fs::is_regular_file(path))) {
            throw InputError(path.string(), std::string("is not a ") + (isFolder ? "folder" : "regular file") +
                                                " as the bench writes it");
        }
    }
}

/// The folder held open with an exclusive flock(): two benches appending to one
/// results.csv once wrote each row twice.
int lockFolder(const std::string& folder) {
    const int fd = open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) throw InputError(folder, "cannot open the results folder");
    if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
        close(fd);
        throw InputError(folder, "is in use by another gvr bench; wait for it to end, or choose another folder");
    }
    return fd;
}

void refuseOtherMethods(const std::string& path, const std::vector<BenchRow>& rows,
                        const std::vector<std::string>& knownMethods) {
    if (knownMethods.empty()) return;
    for (std::size_t r = 0; r < rows.size(); ++r) {
        const std::string method = rows[r].get("method");
        if (std::find(knownMethods.begin(), knownMethods.end(), method) == knownMethods.end()) {
            throw InputError(path, "row " + std::to_string(r + 1) + " (" + rows[r].key() + ") is of method '" + method +
                                       "', which neither gvr nor the manifest's codecs name");
        }
    }
}

}  // namespace

ResultsTable::ResultsTable(const std::string& folder, const std::string& manifestPath, bool resume, bool retryFailed,
                           const std::vector<std::string>& knownMethods)
    : mFolder(folder), mManifest(manifestRecordOf(manifestPath)) {
    fs::create_directories(folder);
    mLock = lockFolder(folder);
    try {
        load(resume, retryFailed, knownMethods);
    } catch (...) {
        close(mLock);
        throw;
    }
}

ResultsTable::~ResultsTable() { close(mLock); }

void ResultsTable::load(bool resume, bool retryFailed, const std::vector<std::string>& knownMethods) {
    checkOwnEntries(mFolder);
    const bool exists = fs::exists(csvPath()) && fs::file_size(csvPath()) > 0;
    if (exists && !resume) {
        throw InputError(mFolder, "already holds results; pass --resume to carry on, or choose another folder");
    }
    if (exists) checkSameManifest(mFolder, jsonPath(), mManifest);
    if (!exists) {
        writeResultsCsv(csvPath(), {});
    } else {
        std::size_t torn = 0;
        mRows = readResultsCsv(csvPath(), &torn);
        refuseOtherMethods(csvPath(), mRows, knownMethods);
        if (torn > 0) fs::resize_file(csvPath(), fs::file_size(csvPath()) - torn);
        if (retryFailed) {
            mRows.erase(std::remove_if(mRows.begin(), mRows.end(),
                                       [](const BenchRow& row) { return row.get("status") != "ok"; }),
                        mRows.end());
            writeResultsCsv(csvPath(), mRows);
        }
    }
    writeResultsJson(jsonPath(), mManifest, mRows);
}

std::optional<BenchRow> ResultsTable::find(const std::string& key) const {
    std::lock_guard<std::mutex> lock(mMutex);
    for (const BenchRow& row : mRows) {
        if (row.key() == key) return row;
    }
    return std::nullopt;
}

void ResultsTable::append(const BenchRow& row) {
    std::lock_guard<std::mutex> lock(mMutex);
    const std::string line = csvLine(row);
    const int fd = open(csvPath().c_str(), O_WRONLY | O_APPEND | O_CLOEXEC | O_NOFOLLOW);
    const bool written = fd >= 0 && write(fd, line.data(), line.size()) == ssize_t(line.size()) && fsync(fd) == 0;
    if (fd >= 0) close(fd);
    if (!written) throw InputError(csvPath(), "cannot append a row");
    mRows.push_back(row);
    writeResultsJson(jsonPath(), mManifest, mRows);
}

std::vector<BenchRow> ResultsTable::rows() const {
    std::lock_guard<std::mutex> lock(mMutex);
    return mRows;
}

}  // namespace gvr
