/// @file GaussianBvh.h
/// @brief Which Gaussians reach a point: an Embree 3 BVH over their truncated bounds.
///
/// Build it once per set of positions (build, then query many times, as with
/// rtcCommitScene); queries are const and thread-safe.
#pragma once

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

typedef struct RTCSceneTy* RTCScene;

namespace gvr {

struct Box {
    std::array<float, 3> lower, upper;

    bool contains(const float x[3]) const {
        return x[0] >= lower[0] && x[0] <= upper[0] && x[1] >= lower[1] && x[1] <= upper[1] && x[2] >= lower[2] &&
               x[2] <= upper[2];
    }
    bool overlaps(const float otherLower[3], const float otherUpper[3]) const {
        for (int a = 0; a < 3; ++a) {
            if (otherUpper[a] < lower[a] || otherLower[a] > upper[a]) return false;
        }
        return true;
    }
};

class GaussianBvh {
public:
    GaussianBvh() = default;
    ~GaussianBvh();
    GaussianBvh(const GaussianBvh&) = delete;
    GaussianBvh& operator=(const GaussianBvh&) = delete;

    /// Rebuilds over @a boxes (index space; box i belongs to Gaussian i).
    /// @param fast  a quicker, looser build for structures rebuilt every iteration
    void build(std::vector<Box> boxes, bool fast = false);

    /// Replaces @a hits with the indices of the boxes that contain @a x, in the
    /// traversal's order: sort what you sum over if the result must not depend on it.
    void query(const float x[3], std::vector<std::uint32_t>& hits) const;

    /// Replaces @a hits with the indices of the boxes that overlap the box from
    /// @a lower to @a upper, in the traversal's order.
    void overlapping(const float lower[3], const float upper[3], std::vector<std::uint32_t>& hits) const;

    /// Replaces @a nearest with up to @a k (distance, index) pairs: the boxes whose
    /// centres are closest to @a x, nearest first, leaving out box @a exclude.
    void nearestCentres(const float x[3], std::size_t k, std::uint32_t exclude,
                        std::vector<std::pair<float, std::uint32_t>>& nearest) const;

    /// Frees the BVH and its boxes: queries then find nothing.
    void clear();

    std::size_t size() const { return mBoxes.size(); }
    const std::vector<Box>& boxes() const { return mBoxes; }

private:
    void release();

    std::vector<Box> mBoxes;
    RTCScene mScene = nullptr;
};

}  // namespace gvr
