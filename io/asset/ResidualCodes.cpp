#include "io/asset/ResidualCodes.h"

#include "io/asset/RangeCoder.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdlib>
#include <stdexcept>

namespace gvr {

namespace {

constexpr int kLongestCode = 30;                // the bit length of kMaxResidualCode
constexpr int kExactLength = kLongestCode + 1;  // the "length" that says: stored exactly
constexpr int kBuckets = 16;
constexpr std::uint32_t kLargeMagnitude = 1u << 12;  // an exact neighbour counts as this large

static_assert(kMaxResidualCode == (1 << kLongestCode) - 1, "a code's length must fit the unary alphabet");

/// The adaptive probabilities of one channel's codes.
struct CodeModel {
    BitModel zero[kBuckets];
    BitModel longer[kBuckets][kExactLength];    ///< [bucket][n - 1]: is the length more than n?
    BitModel bits[kExactLength][kLongestCode];  ///< [length][bit position] under the top bit
    BitModel negative[9];                       ///< by the signs of the codes before and above
};

std::uint32_t magnitudeOf(std::int32_t code) {
    return code == kResidualExact ? kLargeMagnitude : std::min(std::uint32_t(std::abs(code)), kLargeMagnitude);
}

int signOf(std::int32_t code) { return code == kResidualExact ? 0 : (code > 0) - (code < 0); }

int lengthOf(std::uint32_t magnitude) { return 32 - __builtin_clz(magnitude); }

/// The codes already coded around one voxel, as its context.
struct Neighbourhood {
    std::int32_t before = 0, above = 0, behind = 0, otherChannel = 0;

    /// 0..3 for activities 0..3, then two buckets an octave.
    int bucket() const {
        const std::uint32_t activity =
            magnitudeOf(before) + magnitudeOf(above) + magnitudeOf(behind) + 2 * magnitudeOf(otherChannel);
        if (activity < 4) return int(activity);
        const int octave = lengthOf(activity) - 1;
        const int upperHalf = int((activity >> (octave - 1)) & 1);
        return std::min(kBuckets - 1, 4 + 2 * (octave - 2) + upperHalf);
    }
    int signContext() const { return (signOf(before) + 1) * 3 + signOf(above) + 1; }
};

/// Walks one slab's voxels in the layer's order, channels innermost, handing each
/// code's place and neighbourhood to @a visit (codes before it already final).
template <typename Visit>
void walkSlab(const ResidualLayer& layer, int slab, Visit visit) {
    const int nx = layer.dims.x(), ny = layer.dims.y(), channels = layer.channels;
    const int begin = slab * kResidualSlabSlices, end = std::min(layer.dims.z(), begin + kResidualSlabSlices);
    const std::size_t row = std::size_t(nx) * channels, slice = row * ny;
    const std::int32_t* codes = layer.codes.data();
    for (int k = begin; k < end; ++k) {
        for (int j = 0; j < ny; ++j) {
            for (int i = 0; i < nx; ++i) {
                const std::size_t voxel = (std::size_t(k) * ny + j) * row + std::size_t(i) * channels;
                for (int c = 0; c < channels; ++c) {
                    const std::size_t at = voxel + c;
                    Neighbourhood around;
                    if (i > 0) around.before = codes[at - channels];
                    if (j > 0) around.above = codes[at - row];
                    if (k > begin) around.behind = codes[at - slice];
                    if (c > 0) around.otherChannel = codes[at - 1];
                    visit(at, c, around);
                }
            }
        }
    }
}

void encodeCode(RangeEncoder& coder, CodeModel& model, const Neighbourhood& around, std::int32_t code) {
    const int bucket = around.bucket();
    coder.encode(model.zero[bucket], code != 0);
    if (code == 0) return;
    const std::uint32_t magnitude = code == kResidualExact ? 0 : std::uint32_t(std::abs(code));
    const int length = code == kResidualExact ? kExactLength : lengthOf(magnitude);
    for (int n = 1; n < length; ++n) coder.encode(model.longer[bucket][n - 1], true);
    if (length < kExactLength) coder.encode(model.longer[bucket][length - 1], false);
    if (code == kResidualExact) return;
    for (int bit = length - 2; bit >= 0; --bit) coder.encode(model.bits[length][bit], (magnitude >> bit) & 1);
    coder.encode(model.negative[around.signContext()], code < 0);
}

std::int32_t decodeCode(RangeDecoder& coder, CodeModel& model, const Neighbourhood& around) {
    const int bucket = around.bucket();
    if (!coder.decode(model.zero[bucket])) return 0;
    int length = 1;
    while (length < kExactLength && coder.decode(model.longer[bucket][length - 1])) ++length;
    if (length == kExactLength) return kResidualExact;
    std::uint32_t magnitude = 1;
    for (int bit = length - 2; bit >= 0; --bit)
        magnitude = (magnitude << 1) | std::uint32_t(coder.decode(model.bits[length][bit]));
    const auto code = std::int32_t(magnitude);
    return coder.decode(model.negative[around.signContext()]) ? -code : code;
}

}  // namespace

std::vector<std::string> encodeResidualCodes(const ResidualLayer& layer) {
    std::vector<std::string> streams(std::size_t(residualSlabCount(layer.dims)));
    tbb::parallel_for(0, int(streams.size()), [&](int slab) {
        RangeEncoder coder;
        std::vector<CodeModel> models(std::size_t(layer.channels));
        walkSlab(layer, slab, [&](std::size_t at, int c, const Neighbourhood& around) {
            encodeCode(coder, models[c], around, layer.codes[at]);
        });
        streams[slab] = coder.finish();
    });
    return streams;
}

void decodeResidualCodes(const std::vector<std::string_view>& streams, ResidualLayer& layer) {
    if (streams.size() != std::size_t(residualSlabCount(layer.dims))) {
        throw std::runtime_error("residual codes: not one stream per slab");
    }
    std::vector<char> overran(streams.size(), 0);
    tbb::parallel_for(0, int(streams.size()), [&](int slab) {
        RangeDecoder coder(streams[slab]);
        std::vector<CodeModel> models(std::size_t(layer.channels));
        walkSlab(layer, slab, [&](std::size_t at, int c, const Neighbourhood& around) {
            layer.codes[at] = decodeCode(coder, models[c], around);
        });
        overran[slab] = coder.overran();
    });
    if (std::count(overran.begin(), overran.end(), 1) != 0)
        throw std::runtime_error("residual codes: a stream is cut short");
}

}  // namespace gvr
