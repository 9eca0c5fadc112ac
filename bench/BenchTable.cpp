#include "bench/BenchTable.h"

#include "io/AtomicFile.h"
#include "io/Figures.h"
#include "io/JsonText.h"
#include "pipeline/Error.h"

#include <nlohmann/json.hpp>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

namespace gvr {

namespace fs = std::filesystem;

const std::vector<std::string>& benchColumns() {
    static const std::vector<std::string> columns = {
        "volume",  "ratio",         "method",      "status",      "message",     "bytes",
        "ratio_raw", "ratio_float32", "bits_per_voxel", "psnr",    "fg_psnr",     "ssim",
        "ms_ssim", "render_psnr",   "render_ssim", "compress_s",  "decompress_s", "peak_rss_mib",
        "render_fps", "detail",     "fit_log",     "views",       "truth_views"};
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

std::string csvHeader() {
    std::string line;
    for (const std::string& column : benchColumns()) line += (line.empty() ? "" : ",") + column;
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

std::string benchRowKey(const std::string& volume, const std::string& ratio, const std::string& method) {
    return volume + "|" + ratio + "|" + method;
}

std::string BenchRow::key() const { return benchRowKey(get("volume"), get("ratio"), get("method")); }

std::vector<BenchRow> readResultsCsv(const std::string& path, std::size_t* tornBytes) {
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
    if (!std::getline(lines, line) || line + "\n" != csvHeader()) {
        throw InputError(path, "is not a gvr bench results.csv (its header differs)");
    }
    std::vector<BenchRow> rows;
    while (std::getline(lines, line)) {
        const std::vector<std::string> cells = splitCsv(line);
        if (cells.size() != benchColumns().size()) {
            throw InputError(path, "row " + std::to_string(rows.size() + 1) + " has " + std::to_string(cells.size()) +
                                       " cells, not " + std::to_string(benchColumns().size()));
        }
        BenchRow row;
        for (std::size_t c = 0; c < cells.size(); ++c) row.cells[benchColumns()[c]] = cells[c];
        rows.push_back(row);
    }
    return rows;
}

void writeResultsJson(const std::string& path, const std::string& manifestPath, const std::vector<BenchRow>& rows) {
    nlohmann::json out = {{"manifest", manifestPath}, {"rows", nlohmann::json::array()}};
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
    std::string text = csvHeader();
    for (const BenchRow& row : rows) text += csvLine(row);
    writeText(path, text);
}

namespace {

/// A folder resumed with another manifest would mix two benchmarks' rows in one report.
void checkSameManifest(const std::string& folder, const std::string& resultsJson, const std::string& manifestPath) {
    std::ifstream in(resultsJson);
    const nlohmann::json results = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
    if (results.is_discarded() || !results.is_object() || !results.contains("manifest")) return;  // rebuilt from the CSV
    const std::string earlier = results["manifest"].is_string() ? results["manifest"].get<std::string>() : "";
    std::error_code error;
    if (earlier == manifestPath || fs::equivalent(earlier, manifestPath, error)) return;
    throw InputError(folder, "holds the results of " + earlier + "; resume it with that manifest, or choose another folder");
}

}  // namespace

ResultsTable::ResultsTable(const std::string& folder, const std::string& manifestPath, bool resume,
                           bool retryFailed)
    : mFolder(folder), mManifestPath(manifestPath) {
    fs::create_directories(folder);
    const bool exists = fs::exists(csvPath()) && fs::file_size(csvPath()) > 0;
    if (exists && !resume) {
        throw InputError(folder, "already holds results; pass --resume to carry on, or choose another folder");
    }
    if (exists) checkSameManifest(folder, jsonPath(), manifestPath);
    if (!exists) {
        writeResultsCsv(csvPath(), {});
    } else {
        std::size_t torn = 0;
        mRows = readResultsCsv(csvPath(), &torn);
        if (torn > 0) fs::resize_file(csvPath(), fs::file_size(csvPath()) - torn);
        if (retryFailed) {
            mRows.erase(std::remove_if(mRows.begin(), mRows.end(),
                                       [](const BenchRow& row) { return row.get("status") != "ok"; }),
                        mRows.end());
            writeResultsCsv(csvPath(), mRows);
        }
    }
    writeResultsJson(jsonPath(), mManifestPath, mRows);
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
    const int fd = open(csvPath().c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
    const bool written = fd >= 0 && write(fd, line.data(), line.size()) == ssize_t(line.size()) && fsync(fd) == 0;
    if (fd >= 0) close(fd);
    if (!written) throw InputError(csvPath(), "cannot append a row");
    mRows.push_back(row);
    writeResultsJson(jsonPath(), mManifestPath, mRows);
}

std::vector<BenchRow> ResultsTable::rows() const {
    std::lock_guard<std::mutex> lock(mMutex);
    return mRows;
}

}  // namespace gvr
