// The Embree BVH against brute force on random configurations.

#include "pipeline/GaussianBvh.h"
#include "pipeline/GaussianField.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace gvr {
namespace {

std::vector<Box> randomBoxes(std::mt19937& random, std::size_t count) {
    std::uniform_real_distribution<float> position(0.0f, 50.0f), size(0.01f, 8.0f);
    std::vector<Box> boxes(count);
    for (Box& box : boxes) {
        for (int a = 0; a < 3; ++a) {
            box.lower[a] = position(random);
            box.upper[a] = box.lower[a] + size(random);
        }
    }
    return boxes;
}

TEST(GaussianBvh, ContainmentQueriesMatchBruteForce) {
    std::mt19937 random(42);
    std::uniform_real_distribution<float> position(-2.0f, 60.0f);
    for (std::size_t count : {1u, 7u, 500u, 5000u}) {
        const std::vector<Box> boxes = randomBoxes(random, count);
        GaussianBvh bvh;
        bvh.build(boxes, /*fast=*/count % 2 == 0);
        std::vector<std::uint32_t> hits;
        for (int q = 0; q < 2000; ++q) {
            const float x[3] = {position(random), position(random), position(random)};
            bvh.query(x, hits);
            std::sort(hits.begin(), hits.end());
            std::vector<std::uint32_t> expected;
            for (std::uint32_t i = 0; i < boxes.size(); ++i) {
                if (boxes[i].contains(x)) expected.push_back(i);
            }
            ASSERT_EQ(hits, expected) << count << " boxes, query " << q;
        }
    }
}

TEST(GaussianBvh, OverlapQueriesMatchBruteForce) {
    std::mt19937 random(3);
    std::uniform_real_distribution<float> position(-5.0f, 60.0f), size(0.0f, 12.0f);
    const std::vector<Box> boxes = randomBoxes(random, 3000);
    GaussianBvh bvh;
    bvh.build(boxes);
    std::vector<std::uint32_t> hits;
    for (int q = 0; q < 1000; ++q) {
        float lower[3], upper[3];
        for (int a = 0; a < 3; ++a) {
            lower[a] = position(random);
            upper[a] = lower[a] + (q % 10 == 0 ? 0.0f : size(random));  // points too
        }
        bvh.overlapping(lower, upper, hits);
        std::sort(hits.begin(), hits.end());
        std::vector<std::uint32_t> expected;
        for (std::uint32_t i = 0; i < boxes.size(); ++i) {
            if (boxes[i].overlaps(lower, upper)) expected.push_back(i);
        }
        ASSERT_EQ(hits, expected) << "query " << q;
    }
}

TEST(GaussianBvh, NearestCentresMatchBruteForce) {
    std::mt19937 random(7);
    std::vector<Box> points(3000);
    std::uniform_real_distribution<float> position(0.0f, 100.0f);
    for (Box& p : points) {
        for (int a = 0; a < 3; ++a) p.lower[a] = p.upper[a] = position(random);
    }
    GaussianBvh bvh;
    bvh.build(points);
    std::vector<std::pair<float, std::uint32_t>> nearest;
    for (std::uint32_t q = 0; q < 200; ++q) {
        const float* x = points[q].lower.data();
        bvh.nearestCentres(x, 3, q, nearest);
        std::vector<std::pair<float, std::uint32_t>> expected;
        for (std::uint32_t i = 0; i < points.size(); ++i) {
            if (i == q) continue;
            float d2 = 0.0f;
            for (int a = 0; a < 3; ++a) d2 += (points[i].lower[a] - x[a]) * (points[i].lower[a] - x[a]);
            expected.emplace_back(std::sqrt(d2), i);
        }
        std::partial_sort(expected.begin(), expected.begin() + 3, expected.end());
        ASSERT_EQ(nearest.size(), 3u);
        for (int k = 0; k < 3; ++k) {
            EXPECT_EQ(nearest[k].second, expected[k].second);
            EXPECT_NEAR(nearest[k].first, expected[k].first, 1e-4f);
        }
    }
}

TEST(GaussianField, BvhEvaluationEqualsSummingEveryGaussian) {
    std::mt19937 random(3);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f), position(0.0f, 20.0f);
    GaussianParameters params(300, 1);
    for (std::size_t i = 0; i < params.count(); ++i) {
        for (int a = 0; a < 3; ++a) params.at(kMeans, i)[a] = position(random);
        for (int k = 0; k < 4; ++k) params.at(kRotations, i)[k] = unit(random);
        for (int a = 0; a < 3; ++a) params.at(kLogScales, i)[a] = unit(random);
        params.at(kColours, i)[0] = unit(random);
    }
    const GaussianField field(params, 3.0f);
    std::vector<std::uint32_t> hits;
    for (int q = 0; q < 500; ++q) {
        const float x[3] = {position(random), position(random), position(random)};
        float viaBvh = 0.0f, everything = 0.0f;
        field.evaluate(x, &viaBvh, hits);
        for (const ActiveGaussian& g : field.gaussians()) accumulateValue(g, x, 9.0f, 1, &everything);
        EXPECT_NEAR(viaBvh, everything, 1e-5f);
    }
}

}  // namespace
}  // namespace gvr
