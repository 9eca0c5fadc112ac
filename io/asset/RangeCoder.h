/// @file RangeCoder.h
/// @brief An adaptive binary range coder: bits coded against probabilities that
/// learn as they go, so that a bit its context makes near-certain costs a
/// small fraction of a bit.
///
/// The coder is the one of LZMA (a 32-bit range, carries propagated through a
/// cached byte), with 16-bit probabilities; each context mixes a fast and a slow
/// estimate, which follows both a local change and a long-run rate.
/// The decoder reads zeros past the end of its bytes, so a cut or corrupted stream
/// decodes to wrong bits, never out of bounds: callers check what they decode.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace gvr {

/// The probability that a context's next bit is 0, learnt from its past bits.
class BitModel {
public:
    std::uint32_t zeroProbability() const { return (mFast + mSlow) >> 1; }  ///< of 2^16, in [1, 2^16)
    void update(bool bit) {
        if (bit) {
            mFast -= mFast >> kFastShift;
            mSlow -= mSlow >> kSlowShift;
        } else {
            mFast += (kOne - mFast) >> kFastShift;
            mSlow += (kOne - mSlow) >> kSlowShift;
        }
    }

private:
    static constexpr std::uint32_t kOne = 1u << 16;
    static constexpr int kFastShift = 4, kSlowShift = 7;
    std::uint32_t mFast = kOne / 2, mSlow = kOne / 2;
};

class RangeEncoder {
public:
    void encode(BitModel& model, bool bit) {
        const std::uint32_t bound = (mRange >> 16) * model.zeroProbability();
        if (bit) {
            mLow += bound;
            mRange -= bound;
        } else {
            mRange = bound;
        }
        model.update(bit);
        while (mRange < kTop) {
            mRange <<= 8;
            shiftLow();
        }
    }
    /// The coded bytes; the encoder is spent after this.
    std::string finish() {
        for (int n = 0; n < 5; ++n) shiftLow();
        return std::move(mBytes);
    }

private:
    static constexpr std::uint32_t kTop = 1u << 24;
    void shiftLow() {
        if (std::uint32_t(mLow) < 0xff000000u || (mLow >> 32) != 0) {
            const auto carry = std::uint8_t(mLow >> 32);
            for (std::uint8_t byte = mCache; mPending != 0; --mPending, byte = 0xff)
                mBytes.push_back(char(byte + carry));
            mCache = std::uint8_t(mLow >> 24);
        }
        ++mPending;
        mLow = (mLow & 0x00ffffffu) << 8;
    }
    std::uint64_t mLow = 0;
    std::uint32_t mRange = 0xffffffffu;
    std::uint8_t mCache = 0;
    std::uint64_t mPending = 1;
    std::string mBytes;
};

class RangeDecoder {
public:
    explicit RangeDecoder(std::string_view bytes) : mBytes(bytes) {
        for (int n = 0; n < 5; ++n) mCode = (mCode << 8) | nextByte();
    }
    bool decode(BitModel& model) {
        const std::uint32_t bound = (mRange >> 16) * model.zeroProbability();
        const bool bit = mCode >= bound;
        if (bit) {
            mCode -= bound;
            mRange -= bound;
        } else {
            mRange = bound;
        }
        model.update(bit);
        while (mRange < kTop) {
            mRange <<= 8;
            mCode = (mCode << 8) | nextByte();
        }
        return bit;
    }
    /// Whether the decoder has read past its bytes (a stream cut short or corrupted).
    bool overran() const { return mAt > mBytes.size() + 4; }

private:
    static constexpr std::uint32_t kTop = 1u << 24;
    std::uint32_t nextByte() { return mAt < mBytes.size() ? std::uint8_t(mBytes[mAt++]) : (++mAt, 0u); }
    std::string_view mBytes;
    std::size_t mAt = 0;
    std::uint32_t mCode = 0, mRange = 0xffffffffu;
};

}  // namespace gvr
