// Four-lane doubles (core/lanes.h) in the variant this build compiles: each operation
// gives, lane by lane, the scalar operation's bits.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "core/lanes.h"

namespace pvrt {
namespace {

using namespace lanes;

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(Lanes, SelectTakesEachLaneFromTheOperandItsBitNames) {
  const double a[4] = {1.5, -2.5, -0.0, NAN}, b[4] = {10, -0.0, 30, 40};
  for (unsigned bits = 0; bits < 16; ++bits) {
    double out[4];
    store(out, select(bits, load(a), load(b)));
    for (int i = 0; i < 4; ++i) EXPECT_TRUE(sameBits(out[i], (bits >> i & 1u) ? a[i] : b[i])) << bits << " " << i;
  }
}

TEST(Lanes, FloorAndEqualAreTheScalarOnes) {
  const double values[] = {-2.5, -2.0, -1e-300, -0.0, 0.0, 1e-300, 0.5, 1.0, 2.999999999999, 4503599627370497.0,
                           1e300, INFINITY, -INFINITY, NAN};
  for (double x : values)
    for (double y : values) {
      const double in[4] = {x, y, -x, -y};
      double out[4];
      store(out, lanes::floor(load(in)));
      unsigned same = 0;
      for (int i = 0; i < 4; ++i) {
        EXPECT_TRUE(sameBits(out[i], std::floor(in[i]))) << in[i];
        same |= (in[i] == out[i] ? 1u : 0u) << i;
      }
      EXPECT_EQ(equal(load(in), load(out)), same);
    }
}

}  // namespace
}  // namespace pvrt
