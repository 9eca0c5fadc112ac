#include "io/formats/JsonText.h"

#include <gtest/gtest.h>

namespace gvr {
namespace {

TEST(JsonText, AByteThatIsNotUtf8IsWrittenAsAReplacementCharacter) {
    // A Linux file name "x\xff.vdb" in --json output was an internal error (type_error 316).
    const nlohmann::json report{{"output", "x\xff.vdb"}};
    EXPECT_EQ(jsonText(report), "{\"output\":\"x\xef\xbf\xbd.vdb\"}");
    EXPECT_EQ(jsonText(nlohmann::json{{"a", 1}}, 2), "{\n  \"a\": 1\n}");
}

TEST(JsonText, WellFormedUtf8IsToldFromEveryMalformedKind) {
    for (const char* good : {"", "ascii", "caf\xc3\xa9", "\xe2\x82\xac", "\xf0\x9f\x98\x80", "\xf4\x8f\xbf\xbf"}) {
        EXPECT_TRUE(isUtf8(good)) << good;
    }
    for (const char* bad : {"\xe9", "\xc3", "\xc3(", "\xc0\xaf", "\xe0\x80\xaf", "\xed\xa0\x80", "\xf4\x90\x80\x80",
                            "\xf8\x88\x80\x80\x80", "\x80"}) {
        EXPECT_FALSE(isUtf8(bad)) << bad;  // lone, cut, overlong, surrogate, beyond U+10FFFF, 5-byte, continuation
    }
}

}  // namespace
}  // namespace gvr
