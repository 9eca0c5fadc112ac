#include "pipeline/GaussianBvh.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace gvr {

namespace {

/// One Embree device for the process: creating one starts a thread pool.
RTCDevice sharedDevice() {
    static RTCDevice device = [] {
        RTCDevice created = rtcNewDevice(nullptr);
        if (!created) throw std::runtime_error("Embree: cannot create a device");
        return created;
    }();
    return device;
}

void boundsOfBox(const RTCBoundsFunctionArguments* args) {
    const auto* boxes = static_cast<const std::vector<Box>*>(args->geometryUserPtr);
    const Box& box = (*boxes)[args->primID];
    RTCBounds* out = args->bounds_o;
    out->lower_x = box.lower[0];
    out->lower_y = box.lower[1];
    out->lower_z = box.lower[2];
    out->upper_x = box.upper[0];
    out->upper_y = box.upper[1];
    out->upper_z = box.upper[2];
}

struct QueryState {
    const std::vector<Box>* boxes;
    const float* point;
    std::vector<std::uint32_t>* hits;
};

bool collectContaining(RTCPointQueryFunctionArguments* args) {
    auto* state = static_cast<QueryState*>(args->userPtr);
    if ((*state->boxes)[args->primID].contains(state->point)) state->hits->push_back(args->primID);
    return false;  // the query radius stays 0
}

struct OverlapState {
    const std::vector<Box>* boxes;
    const float* lower;
    const float* upper;
    std::vector<std::uint32_t>* hits;
};

/// The query sphere encloses the box, so Embree visits a superset; the exact
/// box test keeps the rest.
bool collectOverlapping(RTCPointQueryFunctionArguments* args) {
    auto* state = static_cast<OverlapState*>(args->userPtr);
    if ((*state->boxes)[args->primID].overlaps(state->lower, state->upper)) state->hits->push_back(args->primID);
    return false;
}

struct NearestState {
    const std::vector<Box>* boxes;
    std::size_t k;
    std::uint32_t exclude;
    std::vector<std::pair<float, std::uint32_t>>* nearest;
};

/// Keeps the k nearest centres seen so far and shrinks the query sphere to the
/// k-th distance, so that Embree skips everything farther away.
bool collectNearest(RTCPointQueryFunctionArguments* args) {
    auto* state = static_cast<NearestState*>(args->userPtr);
    if (args->primID == state->exclude) return false;
    const Box& box = (*state->boxes)[args->primID];
    const RTCPointQuery* query = args->query;
    const float dx = 0.5f * (box.lower[0] + box.upper[0]) - query->x;
    const float dy = 0.5f * (box.lower[1] + box.upper[1]) - query->y;
    const float dz = 0.5f * (box.lower[2] + box.upper[2]) - query->z;
    const float distance = std::sqrt(dx * dx + dy * dy + dz * dz);
    auto& nearest = *state->nearest;
    if (nearest.size() == state->k && distance >= nearest.back().first) return false;
    const std::pair<float, std::uint32_t> entry(distance, args->primID);
    nearest.insert(std::upper_bound(nearest.begin(), nearest.end(), entry), entry);
    if (nearest.size() > state->k) nearest.pop_back();
    if (nearest.size() < state->k) return false;
    args->query->radius = nearest.back().first;
    return true;
}

}  // namespace

GaussianBvh::~GaussianBvh() { release(); }

void GaussianBvh::release() {
    if (mScene) rtcReleaseScene(mScene);
    mScene = nullptr;
}

void GaussianBvh::clear() {
    release();
    std::vector<Box>().swap(mBoxes);
}

void GaussianBvh::build(std::vector<Box> boxes, bool fast) {
    release();
    mBoxes = std::move(boxes);
    if (mBoxes.empty()) return;
    RTCDevice device = sharedDevice();
    mScene = rtcNewScene(device);
    rtcSetSceneBuildQuality(mScene, fast ? RTC_BUILD_QUALITY_LOW : RTC_BUILD_QUALITY_MEDIUM);
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(geometry, unsigned(mBoxes.size()));
    rtcSetGeometryUserData(geometry, &mBoxes);
    rtcSetGeometryBoundsFunction(geometry, boundsOfBox, &mBoxes);
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(mScene, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(mScene);
    if (rtcGetDeviceError(device) != RTC_ERROR_NONE) {
        throw std::runtime_error("Embree: building the BVH over " + std::to_string(mBoxes.size()) +
                                 " Gaussians failed");
    }
}

void GaussianBvh::query(const float x[3], std::vector<std::uint32_t>& hits) const {
    hits.clear();
    if (!mScene) return;
    RTCPointQuery query;
    query.x = x[0];
    query.y = x[1];
    query.z = x[2];
    query.time = 0.0f;
    query.radius = 0.0f;
    RTCPointQueryContext context;
    rtcInitPointQueryContext(&context);
    QueryState state{&mBoxes, x, &hits};
    rtcPointQuery(mScene, &query, &context, collectContaining, &state);
}

void GaussianBvh::overlapping(const float lower[3], const float upper[3], std::vector<std::uint32_t>& hits) const {
    hits.clear();
    if (!mScene) return;
    RTCPointQuery query;
    query.x = 0.5f * (lower[0] + upper[0]);
    query.y = 0.5f * (lower[1] + upper[1]);
    query.z = 0.5f * (lower[2] + upper[2]);
    query.time = 0.0f;
    const float half[3] = {0.5f * (upper[0] - lower[0]), 0.5f * (upper[1] - lower[1]), 0.5f * (upper[2] - lower[2])};
    // Rounded up a little so that float error never shrinks the sphere inside the box.
    query.radius = 1.0001f * std::sqrt(half[0] * half[0] + half[1] * half[1] + half[2] * half[2]) + 1e-6f;
    RTCPointQueryContext context;
    rtcInitPointQueryContext(&context);
    OverlapState state{&mBoxes, lower, upper, &hits};
    rtcPointQuery(mScene, &query, &context, collectOverlapping, &state);
}

void GaussianBvh::nearestCentres(const float x[3], std::size_t k, std::uint32_t exclude,
                                 std::vector<std::pair<float, std::uint32_t>>& nearest) const {
    nearest.clear();
    if (!mScene || k == 0) return;
    RTCPointQuery query;
    query.x = x[0];
    query.y = x[1];
    query.z = x[2];
    query.time = 0.0f;
    query.radius = std::numeric_limits<float>::infinity();
    RTCPointQueryContext context;
    rtcInitPointQueryContext(&context);
    NearestState state{&mBoxes, k, exclude, &nearest};
    rtcPointQuery(mScene, &query, &context, collectNearest, &state);
}

}  // namespace gvr
