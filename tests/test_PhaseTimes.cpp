#include "workflow/PhaseTimes.h"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

namespace gvr {
namespace {

TEST(PhaseTimes, LapsAreInOrderAndAddUpToTheTotal) {
    PhaseTimes phases;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    phases.lap("load");
    phases.lap("fit");
    const nlohmann::json json = phases.json();
    EXPECT_GE(json.at("load").get<double>(), 0.015);
    EXPECT_LT(json.at("fit").get<double>(), json.at("load").get<double>());
    EXPECT_DOUBLE_EQ(json.at("total").get<double>(), json.at("load").get<double>() + json.at("fit").get<double>());
    EXPECT_DOUBLE_EQ(phases.total(), json.at("total").get<double>());

    const std::string text = phases.text();
    EXPECT_EQ(text.rfind("load ", 0), 0u) << text;
    EXPECT_LT(text.find(" s, fit "), text.find("; total ")) << text;
}

TEST(PhaseTimes, NoLapsIsATotalOfNothing) { EXPECT_EQ(PhaseTimes().json(), (nlohmann::json{{"total", 0.0}})); }

}  // namespace
}  // namespace gvr
