/// @file BenchTable.h
/// @brief The benchmark's results: one row per (volume, ratio, method), appended
/// to results.csv and flushed as each run ends, mirrored in results.json.
///
/// results.csv is the record; results.json is rebuilt from it after every row, so
/// a killed run loses at most the run it was in, and --resume carries on from the
/// rows already there.
#pragma once

#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace gvr {

/// The columns of results.csv, in order (see BenchCommand.cpp for their meaning).
const std::vector<std::string>& benchColumns();

/// volume|ratio|method: what --resume and --merge match rows by.
std::string benchRowKey(const std::string& volume, const std::string& ratio, const std::string& method);

struct BenchRow {
    std::map<std::string, std::string> cells;  ///< column -> text as in the CSV; missing = empty

    void set(const std::string& column, const std::string& text);
    void set(const std::string& column, double value);  ///< "inf" for +infinity
    void setList(const std::string& column, const std::vector<std::string>& items);
    std::string get(const std::string& column) const;
    std::optional<double> number(const std::string& column) const;  ///< unset when empty or not a number
    std::vector<std::string> list(const std::string& column) const;

    std::string key() const;  ///< benchRowKey of this row
};

/// Reads a results.csv. A last line without its newline was cut short by a kill
/// and is left out; @a tornBytes (when given) receives its length.
/// @throw InputError naming @a path when the header is not ours.
std::vector<BenchRow> readResultsCsv(const std::string& path, std::size_t* tornBytes = nullptr);

/// Writes results.json ({"manifest": ..., "rows": [...]}, typed values) atomically.
void writeResultsJson(const std::string& path, const std::string& manifestPath, const std::vector<BenchRow>& rows);

/// Writes a whole results.csv atomically (for --merge).
void writeResultsCsv(const std::string& path, const std::vector<BenchRow>& rows);

/// The live table of a run: thread-safe appends that reach the disk before returning.
class ResultsTable {
public:
    /// Without @a resume, a folder that already holds results is refused. With
    /// @a retryFailed, its failed rows are dropped so that they run again.
    /// @throw InputError naming the folder.
    ResultsTable(const std::string& folder, const std::string& manifestPath, bool resume, bool retryFailed = false);

    std::optional<BenchRow> find(const std::string& key) const;
    void append(const BenchRow& row);
    std::vector<BenchRow> rows() const;

    std::string csvPath() const { return mFolder + "/results.csv"; }
    std::string jsonPath() const { return mFolder + "/results.json"; }

private:
    std::string mFolder, mManifestPath;
    std::vector<BenchRow> mRows;
    mutable std::mutex mMutex;
};

}  // namespace gvr
