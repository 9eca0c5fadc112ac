#include "workflow/BrickTeam.h"

#include <gtest/gtest.h>

namespace gvr {
namespace {

/// A team of @a size where this process is rank 0 and nothing travels: enough to
/// see how owners() shares out the bricks.
class PaperTeam final : public BrickTeam {
public:
    explicit PaperTeam(int size) : mSize(size) {}
    int rank() const override { return 0; }
    int size() const override { return mSize; }
    std::size_t threadsPerRank() const override { return 1; }
    std::vector<BrickOutcome> gather(std::vector<BrickOutcome> mine, const std::vector<int>&) const override {
        return mine;
    }
    void broadcast(std::string&) const override {}
    void abortUnlessAlone(const std::exception&) const override {}

private:
    int mSize;
};

TEST(BrickTeam, OwnersGiveTheLargestBudgetsFirstToTheLeastLoadedRank) {
    std::vector<Brick> bricks(5);
    const std::size_t budgets[] = {10, 50, 30, 40, 20};
    for (std::size_t b = 0; b < bricks.size(); ++b) {
        bricks[b].index = b;
        bricks[b].budget = budgets[b];
    }
    // By hand, with the loads before each step: 50 to rank 0 (0, 0); 40 to rank 1 (50, 0);
    // 30 to rank 1 (50, 40); 20 to rank 0 (50, 70); 10 to rank 0 (70, 70: the first on a tie).
    EXPECT_EQ(PaperTeam(2).owners(bricks), (std::vector<int>{0, 0, 1, 1, 0}));
    EXPECT_EQ(SoloTeam().owners(bricks), (std::vector<int>(5, 0)));
}

TEST(BrickTeam, SoloGatherPutsOutcomesInBrickOrder) {
    std::vector<BrickOutcome> mine = {{2, 0, true, "c"}, {0, 0, true, "a"}, {1, 0, false, "oops"}};
    const std::vector<BrickOutcome> all = SoloTeam().gather(mine, {0, 0, 0});
    ASSERT_EQ(all.size(), 3u);
    EXPECT_EQ(all[0].bytes, "a");
    EXPECT_FALSE(all[1].ok);
    EXPECT_EQ(all[2].bytes, "c");
}

}  // namespace
}  // namespace gvr
