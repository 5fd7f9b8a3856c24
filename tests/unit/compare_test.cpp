// image/compare.h: the golden verdict's counts and thresholds on small made-up images.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "image/compare.h"

namespace pvrt {
namespace {

// Two 2 x 2 images, 12 channels: two differ by 1 level, one by 3.
TEST(Compare, CountsAndTheOffByOneBound) {
  std::vector<uint8_t> a(12, 100), b(12, 100);
  b[0] = 101;
  b[5] = 99;
  b[7] = 103;
  const CompareResult r = compareImages8(a, b, 2, 2);
  EXPECT_EQ(r.channels, 12);
  EXPECT_EQ(r.over0, 3);
  EXPECT_EQ(r.over1, 1);
  EXPECT_EQ(r.over2, 1);
  EXPECT_EQ(r.maxError, 3);
  EXPECT_FALSE(r.pass({2, 1.0}));   // 3 levels
  EXPECT_TRUE(r.pass({3, 1.0}));    // no bound on the channels off by 1
  EXPECT_TRUE(r.pass({3, 1.0, 2}));
  EXPECT_FALSE(r.pass({3, 1.0, 1}));  // two are off by 1
  EXPECT_FALSE(r.pass({3, 0.0, 2}));  // one is over 1 level
}

}  // namespace
}  // namespace pvrt
