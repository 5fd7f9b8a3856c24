#include "parallel/schedule.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <set>

namespace pvrt {
namespace {

long coveredPixels(const WorkPlan& p) {
  long n = 0;
  for (const auto& it : p.items) n += it.pixels();
  return n;
}

TEST(Schedule, BlockGivesEachWorkerOneContiguousBlock) {
  const WorkPlan p = makeWorkPlan({Strategy::Block, 0, 32}, 10, 7, 3);
  ASSERT_EQ(p.items.size(), 3u);
  EXPECT_EQ(p.items[0].y0, 0);
  EXPECT_EQ(p.items[0].y1, 2);
  EXPECT_EQ(p.items[2].y1, 7);
  EXPECT_EQ(p.owner, (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(coveredPixels(p), 70);
}

TEST(Schedule, CyclicDealsRowsRoundRobin) {
  const WorkPlan p = makeWorkPlan({Strategy::Cyclic, 0, 32}, 4, 5, 2);
  ASSERT_EQ(p.items.size(), 5u);
  EXPECT_EQ(p.owner, (std::vector<int>{0, 1, 0, 1, 0}));
}

TEST(Schedule, TilesCoverTheImageExactlyOnce) {
  const WorkPlan p = makeWorkPlan({Strategy::Tiles, 0, 16}, 50, 33, 2);
  EXPECT_EQ(p.items.size(), 4u * 3u);
  EXPECT_EQ(coveredPixels(p), 50 * 33);
  EXPECT_TRUE(p.owner.empty());
}

// A granule (POV-Ray's block for adaptive antialiasing) turns rows into bands of that many
// rows and rounds tiles up to it, so no work item splits a block.
TEST(Schedule, AGranuleCutsOnlyOnItsMultiples) {
  for (Strategy st : {Strategy::Block, Strategy::Cyclic, Strategy::Dynamic, Strategy::Tiles}) {
    ScheduleSettings s{st, 0, 20};
    s.granule = 16;
    const WorkPlan p = makeWorkPlan(s, 50, 70, 3);
    EXPECT_EQ(coveredPixels(p), 50 * 70) << strategyName(st);
    for (const WorkItem& it : p.items) {
      EXPECT_EQ(it.x0 % 16, 0) << strategyName(st);
      EXPECT_EQ(it.y0 % 16, 0) << strategyName(st);
      EXPECT_TRUE(it.x1 % 16 == 0 || it.x1 == 50) << strategyName(st);
      EXPECT_TRUE(it.y1 % 16 == 0 || it.y1 == 70) << strategyName(st);
    }
  }
  ScheduleSettings cyclic{Strategy::Cyclic, 0, 32};
  cyclic.granule = 16;
  const WorkPlan p = makeWorkPlan(cyclic, 50, 70, 2);
  ASSERT_EQ(p.items.size(), 5u);  // bands 0-16, 16-32, 32-48, 48-64, 64-70
  EXPECT_EQ(p.items[4].y0, 64);
  EXPECT_EQ(p.items[4].y1, 70);
  EXPECT_EQ(p.owner, (std::vector<int>{0, 1, 0, 1, 0}));
  ScheduleSettings tiles{Strategy::Tiles, 0, 20};
  tiles.granule = 16;
  EXPECT_EQ(makeWorkPlan(tiles, 50, 70, 2).items.size(), 2u * 3u);  // 32 x 32 tiles
}

TEST(Schedule, MoreWorkersThanRowsLeavesNoEmptyBlock) {
  const WorkPlan p = makeWorkPlan({Strategy::Block, 0, 32}, 3, 2, 4);
  EXPECT_EQ(coveredPixels(p), 6);
  for (const auto& it : p.items) EXPECT_GT(it.pixels(), 0);
}

TEST(Schedule, OmpScheduleFromEnvironment) {
  setenv("OMP_SCHEDULE", "guided,4", 1);
  ScheduleSettings s;
  EXPECT_TRUE(scheduleFromEnvironment(s));
  EXPECT_EQ(s.strategy, Strategy::Guided);
  EXPECT_EQ(s.chunk, 4);
  setenv("OMP_SCHEDULE", "bogus", 1);
  EXPECT_FALSE(scheduleFromEnvironment(s));
  unsetenv("OMP_SCHEDULE");
}

TEST(Schedule, ParsesEveryName) {
  for (const char* n : {"block", "cyclic", "static", "dynamic", "guided", "runtime", "tiles"})
    EXPECT_STREQ(strategyName(parseStrategy(n)), n);
}

}  // namespace
}  // namespace pvrt
