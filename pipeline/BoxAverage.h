/// @file BoxAverage.h
/// @brief Box-filter downsampling of a dense volume: what the downsampling baseline
/// codec and MS-SSIM's coarser scales both reduce a volume by.
#pragma once

#include <openvdb/openvdb.h>
#include <tbb/parallel_for.h>

namespace gvr {

/// For each coarse sample (i, j, k) of @a coarseDims, the mean of the fine samples
/// from factor * (i, j, k) up to factor * (i + 1, j + 1, k + 1), clipped to
/// @a fineDims (so a box at a far edge may hold fewer): addFine(x, y, z, sums) adds
/// fine sample (x, y, z)'s channels to sums, and store(i, j, k, means) takes the means.
/// Sums are in double, in z, y, x order, the same for any number of threads.
template <typename AddFine, typename Store>
void forEachBoxAverage(const openvdb::Coord& coarseDims, const openvdb::Coord& factor, const openvdb::Coord& fineDims,
                       int channels, const AddFine& addFine, const Store& store) {
    tbb::parallel_for(0, coarseDims.z(), [&](int k) {
        for (int j = 0; j < coarseDims.y(); ++j) {
            for (int i = 0; i < coarseDims.x(); ++i) {
                const openvdb::Coord first(i * factor.x(), j * factor.y(), k * factor.z());
                const openvdb::Coord end = openvdb::Coord::minComponent(first + factor, fineDims);
                double sums[3] = {0.0, 0.0, 0.0};
                for (int z = first.z(); z < end.z(); ++z) {
                    for (int y = first.y(); y < end.y(); ++y) {
                        for (int x = first.x(); x < end.x(); ++x) addFine(x, y, z, sums);
                    }
                }
                const openvdb::Coord size = end - first;
                const double count = double(size.x()) * size.y() * size.z();
                double means[3];
                for (int c = 0; c < channels; ++c) means[c] = sums[c] / count;
                store(i, j, k, means);
            }
        }
    });
}

}  // namespace gvr
