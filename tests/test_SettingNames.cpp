// How library messages name settings, and how a front end respells them.

#include "pipeline/SettingNames.h"

#include <gtest/gtest.h>

namespace gvr {
namespace {

std::string asFlags(const std::string& message) {
    return respellSettings(message, [](const std::string& key, const std::string& value) {
        return "--" + key + (value.empty() ? "" : " " + value);
    });
}

TEST(SettingNames, RespellsKeysAndValues) {
    EXPECT_EQ(asFlags("`lr` must be positive"), "--lr must be positive");
    EXPECT_EQ(asFlags("scan.nii: pass `nan_to=VALUE` to replace them"),
              "scan.nii: pass --nan_to VALUE to replace them");
    EXPECT_EQ(asFlags("`azimuth`/`elevation`: angles"), "--azimuth/--elevation: angles");
    EXPECT_EQ(asFlags("`volume=3` is out of range"), "--volume 3 is out of range");
    EXPECT_EQ(asFlags("no settings here"), "no settings here");
    EXPECT_EQ(asFlags(""), "");
}

TEST(SettingNames, LeavesOtherBackquotesAlone) {
    // File names and library texts may hold backquotes of their own.
    EXPECT_EQ(asFlags("it`s `Not A Key` here"), "it`s `Not A Key` here");
    EXPECT_EQ(asFlags("`odd file`.nii: `lr` must be positive"), "`odd file`.nii: --lr must be positive");
    EXPECT_EQ(asFlags("unclosed `lr"), "unclosed `lr");
    EXPECT_EQ(asFlags("``"), "``");
    EXPECT_EQ(asFlags("`=3`"), "`=3`");
    EXPECT_EQ(asFlags("`9lives`"), "`9lives`");
}

}  // namespace
}  // namespace gvr
