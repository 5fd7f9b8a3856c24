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
