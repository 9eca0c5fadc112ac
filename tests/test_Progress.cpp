// ProgressCounter: fractions forwarded in rising order from many threads, and
// nothing at all without a listener or without work.

#include "pipeline/Progress.h"

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include <vector>

namespace gvr {
namespace {

TEST(Progress, FractionsRiseToOneFromManyThreads) {
    std::vector<double> seen;
    const ProgressFn report = [&](double fraction) { seen.push_back(fraction); };
    ProgressCounter counter(report, 1000);
    tbb::parallel_for(0, 1000, [&](int) { counter.advance(); });
    ASSERT_EQ(seen.size(), 1000u);
    for (std::size_t n = 0; n < seen.size(); ++n) EXPECT_DOUBLE_EQ(seen[n], double(n + 1) / 1000.0);
}

TEST(Progress, NoListenerOrNoWorkReportsNothing) {
    const ProgressFn none;
    ProgressCounter silent(none, 10);
    silent.advance();  // an empty function is never called
    int calls = 0;
    const ProgressFn counting = [&](double) { ++calls; };
    ProgressCounter empty(counting, 0);
    empty.advance();
    EXPECT_EQ(calls, 0) << "no fraction of zero items, and no division by zero";
}

}  // namespace
}  // namespace gvr
