// Ingest benchmark: throughput and peak memory per data set. Figures are printed,
// not asserted; the target is a peak of at most 2x the volume as float32.
//
//   bench_ingest                     runs the default shared data sets
//   bench_ingest INPUT [INPUT ...]   runs these instead
//
// Each input runs in a child process of its own, so peak memory is per input.

#include "io/Ingest.h"

#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

double residentMiB() {
    std::ifstream status("/proc/self/status");
    std::string key;
    while (status >> key) {
        double kib;
        if (key == "VmRSS:" && status >> kib) return kib / 1024.0;
    }
    return 0.0;
}

double peakResidentMiB() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return usage.ru_maxrss / 1024.0;
}

std::uint64_t bytesOnDisk(const std::string& path) {
    namespace fs = std::filesystem;
    if (!fs::is_directory(path)) return fs::file_size(path);
    std::uint64_t total = 0;
    for (const auto& entry : fs::directory_iterator(path)) total += entry.file_size();
    return total;
}

int benchOne(const std::string& input) {
    const double baselineMiB = residentMiB();
    const auto start = std::chrono::steady_clock::now();
    const gvr::IngestResult result = gvr::ingest(input, gvr::IngestOptions{});
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const auto metadata = result.grid->metaValue<openvdb::Vec3i>("gvr_dims");
    const int channels = result.grid->metaValue<int>("gvr_channels");
    const double floatMiB = double(metadata.x()) * metadata.y() * metadata.z() * channels * 4 / 1048576.0;
    const double peakMiB = peakResidentMiB();
    std::printf(
        "%-45s %4dx%4dx%4d  %7.2f s  %8.1f MB/s decoded float32  %7.1f MB/s from disk\n"
        "%-45s peak RSS %.0f MiB (%.0f MiB above start) = %.2fx the float32 volume "
        "(%.0f MiB); target <= 2x\n",
        input.c_str(), metadata.x(), metadata.y(), metadata.z(), seconds, floatMiB * 1.048576 / seconds,
        bytesOnDisk(input) / 1e6 / seconds, "", peakMiB, peakMiB - baselineMiB, (peakMiB - baselineMiB) / floatMiB,
        floatMiB);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        if (argc == 3 && std::string(argv[1]) == "--one") return benchOne(argv[2]);
        std::vector<std::string> inputs(argv + 1, argv + argc);
        if (inputs.empty()) {
            inputs = {GVR_SHARED_DATA "/ct-head-visible-human-png", GVR_SHARED_DATA "/ct-chest-ricord-512"};
        }
        int failures = 0;
        for (const std::string& input : inputs) {
            const std::string command = "'" + std::string(argv[0]) + "' --one '" + input + "'";
            failures += std::system(command.c_str()) != 0;
        }
        return failures == 0 ? 0 : 1;
    } catch (const std::exception& error) {
        std::fprintf(stderr, "bench_ingest: %s\n", error.what());
        return 1;
    }
}
