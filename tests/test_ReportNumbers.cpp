// Figures as gvr writes them: an infinite PSNR is null in JSON and "inf" in text.

#include "workflow/ReportNumbers.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace gvr {
namespace {

TEST(ReportNumbers, InfinityIsNullInJsonAWordInTextAndNumbersStayNumbers) {
    const double inf = std::numeric_limits<double>::infinity();
    EXPECT_TRUE(jsonNumber(inf).is_null());
    EXPECT_TRUE(jsonNumber(-inf).is_null());
    EXPECT_TRUE(jsonNumber(std::nan("")).is_null());
    EXPECT_EQ(jsonNumber(38.125).get<double>(), 38.125);
    EXPECT_EQ(formatDb(38.126), "38.13");  // two places, rounded
    EXPECT_EQ(formatDb(inf), "inf");
    const nlohmann::json report = {{"psnr", jsonNumber(inf)}};
    EXPECT_EQ(report.dump(), "{\"psnr\":null}");
}

}  // namespace
}  // namespace gvr
