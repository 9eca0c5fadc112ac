// Figures as gvr writes them: an infinite PSNR stays readable in JSON and text.

#include "io/Figures.h"

#include <gtest/gtest.h>

#include <limits>

namespace gvr {
namespace {

TEST(Figures, InfinityIsAWordAndNumbersStayNumbers) {
    const double inf = std::numeric_limits<double>::infinity();
    EXPECT_EQ(jsonNumber(inf), "inf");
    EXPECT_EQ(jsonNumber(-inf), "-inf");
    EXPECT_EQ(jsonNumber(38.125).get<double>(), 38.125);
    EXPECT_EQ(formatDb(38.126), "38.13");  // two places, rounded
    EXPECT_EQ(formatDb(inf), "inf");
    const nlohmann::json report = {{"psnr", jsonNumber(inf)}};
    EXPECT_EQ(report.dump(), "{\"psnr\":\"inf\"}");
}

}  // namespace
}  // namespace gvr
