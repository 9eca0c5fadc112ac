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

/// The first line of results.csv: the columns, comma-separated, with its newline.
std::string resultsCsvHeader();

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
/// @throw InputError naming @a path when it is a link, is larger than a bench
///        writes, or holds what no run writes: another header, a status other than
///        ok/failed/skipped, text in a number's column, a measured row without its
///        bytes, or one (volume, ratio, method) twice.
std::vector<BenchRow> readResultsCsv(const std::string& path, std::size_t* tornBytes = nullptr);

/// The manifest a results folder was run from: its path, and a digest of its text
/// that tells two manifests apart wherever they lie (shards run on other machines
/// hold other paths).
struct ManifestRecord {
    std::string path;
    std::string digest;  ///< CRC-32 of its bytes, in hex; empty when unknown
};

/// The record of the manifest at @a path as it is now.
ManifestRecord manifestRecordOf(const std::string& path);

/// The record a results.json holds; empty when it holds none.
ManifestRecord recordedManifest(const std::string& resultsJson);

/// Writes results.json ({"manifest": ..., "manifest_crc32": ..., "rows": [...]},
/// typed values) atomically.
void writeResultsJson(const std::string& path, const ManifestRecord& manifest, const std::vector<BenchRow>& rows);

/// Writes a whole results.csv atomically (for --merge).
void writeResultsCsv(const std::string& path, const std::vector<BenchRow>& rows);

/// @throw InputError naming the first part of @a path below @a folder that is a
///        symbolic link: the bench writes and removes only what it made, and a link
///        planted in a results folder once had a run write through it.
void refuseLinksBelow(const std::string& folder, const std::string& path);

/// The live table of a run: thread-safe appends that reach the disk before returning.
class ResultsTable {
public:
    /// Without @a resume, a folder that already holds results is refused. With
    /// @a retryFailed, its failed rows are dropped so that they run again. The
    /// folder is locked while the table lives: a second bench in it is refused.
    /// @param knownMethods  the methods the manifest can run; a resumed row of any
    ///                      other is refused (empty: any)
    /// @throw InputError naming the folder, or the file in it that the bench did not
    ///        write (a link, a folder in place of a file, a table readResultsCsv refuses).
    ResultsTable(const std::string& folder, const std::string& manifestPath, bool resume, bool retryFailed = false,
                 const std::vector<std::string>& knownMethods = {});
    ~ResultsTable();
    ResultsTable(const ResultsTable&) = delete;
    ResultsTable& operator=(const ResultsTable&) = delete;

    std::optional<BenchRow> find(const std::string& key) const;
    void append(const BenchRow& row);
    std::vector<BenchRow> rows() const;

    std::string csvPath() const { return mFolder + "/results.csv"; }
    std::string jsonPath() const { return mFolder + "/results.json"; }

private:
    void load(bool resume, bool retryFailed, const std::vector<std::string>& knownMethods);

    std::string mFolder;
    ManifestRecord mManifest;
    int mLock = -1;  ///< the folder, held open with flock()
    std::vector<BenchRow> mRows;
    mutable std::mutex mMutex;
};

}  // namespace gvr
