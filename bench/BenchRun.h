/// @file BenchRun.h
/// @brief Runs the benchmark's methods on one volume, each in its own gvr
/// process, and turns what they print into result rows.
#pragma once

#include "bench/BenchManifest.h"
#include "bench/BenchTable.h"

#include <functional>
#include <string>
#include <vector>

namespace gvr {

struct BenchContext {
    const BenchManifest* manifest = nullptr;
    std::string folder;      ///< the results folder, absolute
    std::string executable;  ///< gvr itself
    int fitThreads = 0;      ///< 0: all cores
    ResultsTable* table = nullptr;
    std::function<void(const BenchRow&)> onRow;  ///< called after each appended row
};

/// Runs the methods of @a units (all of one volume) that the table lacks, appending
/// a row for each: measured, or failed with the message of the step that failed.
void runVolumeUnits(const BenchContext& context, const std::vector<BenchUnit>& units);

}  // namespace gvr
