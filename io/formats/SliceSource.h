/// @file SliceSource.h
/// @brief A volume that can be decoded a slab of whole slices at a time.
///
/// Image stacks, DICOM series and raw files keep their slices apart on disk, so
/// ingest can stream them: it holds one slab of dense samples and the sparse grid
/// built so far, never the whole dense volume. Formats that compress or interleave
/// the volume as a whole (NIfTI, MGH, MetaImage, VDB) are read whole instead.
#pragma once

#include "io/DenseVolume.h"
#include "pipeline/Progress.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

namespace gvr {

struct ReadOptions;

class SliceSource {
public:
    virtual ~SliceSource() = default;

    /// The whole volume's dims, channels, type, rescale, geometry, modality and
    /// warnings, with no samples.
    const DenseVolume& layout() const { return mLayout; }

    /// The file or folder that errors about the volume as a whole name.
    const std::string& culprit() const { return mCulprit; }

    /// Decodes slices [first, first + count) into @a slab, reusing its buffer:
    /// slab becomes the layout with dims[2] = count.
    /// @throw InputError naming the file of a slice that is truncated or corrupt.
    void readSlab(std::int64_t first, std::int64_t count, DenseVolume& slab, const ProgressFn& progress = {}) const;

    /// Bytes of one decoded slice: width x height x channels x bytes a sample.
    std::uint64_t sliceBytes() const;

protected:
    SliceSource(DenseVolume layout, std::string culprit) : mLayout(std::move(layout)), mCulprit(std::move(culprit)) {}

    /// Decodes slices [first, first + count) to @a destination, which holds
    /// count * sliceBytes().
    virtual void readSlices(std::int64_t first, std::int64_t count, unsigned char* destination,
                            const ProgressFn& progress) const = 0;

    /// For sources whose slices decode independently: decodeSlice(index, destination)
    /// for each slice of the range, in parallel.
    void decodeEachSlice(std::int64_t first, std::int64_t count, unsigned char* destination, const ProgressFn& progress,
                         const std::function<void(std::int64_t, unsigned char*)>& decodeSlice) const;

private:
    DenseVolume mLayout;
    std::string mCulprit;
};

/// Every slice of @a source at once, after checking that the volume fits in memory.
DenseVolume readWholeVolume(const SliceSource& source, const ProgressFn& progress = {});

std::unique_ptr<SliceSource> openRawSource(const std::string& path, const ReadOptions& options);
/// @param files slices in stacking order; one file may hold many pages (multi-page TIFF).
std::unique_ptr<SliceSource> openImageStack(const std::vector<std::string>& files, const std::string& culprit,
                                            const ReadOptions& options);
std::unique_ptr<SliceSource> openDicomSeries(const std::string& folder, const ReadOptions& options);

}  // namespace gvr
