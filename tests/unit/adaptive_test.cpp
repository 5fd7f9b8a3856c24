// POV-Ray's adaptive antialiasing (render/adaptive.h) on made-up pictures whose answers
// can be worked out by hand: which pixels get supersampled, and what they become.
#include "render/adaptive.h"

#include <gtest/gtest.h>

#include <functional>
#include <map>
#include <utility>

namespace pvrt {
namespace {

// A red picture given as a function of the sample position (pixel + offset), recording
// what the block algorithms ask of it. Red only, so that a colour distance is the
// difference of one channel.
struct FakeSource {
  std::function<float(double x, double y)> picture;
  int rays = 0;
  std::map<std::pair<int, int>, int> supersampled = {};  // pixel -> times
  std::map<std::pair<int, int>, FloatRgb> image = {};

  FloatRgb sample(int x, int y, double dx, double dy) {
    ++rays;
    return {picture(x + dx, y + dy), 0, 0};
  }
  void row(int x, int y, int count, double dx, double dy, FloatRgb* out) {
    for (int i = 0; i < count; ++i) out[i] = sample(x + i, y, dx, dy);
  }
  void several(int x, int y, const SubSample* offsets, int count, FloatRgb* out) {
    for (int k = 0; k < count; ++k) out[k] = sample(x, y, offsets[k].dx, offsets[k].dy);
  }
  // The centre plus a 3 x 3 grid at -1/3, 0, 1/3, as POV-Ray's +R3.
  FloatRgb supersample(int x, int y, FloatRgb first) {
    ++supersampled[{x, y}];
    float sum = first.r;
    for (int j = -1; j <= 1; ++j)
      for (int i = -1; i <= 1; ++i) sum += picture(x + i / 3.0, y + j / 3.0);
    return {sum / 10, 0, 0};
  }
  void put(int x, int y, FloatRgb c) { image[{x, y}] = c; }

  float at(int x, int y) { return image[{x, y}].r; }
  int times(int x, int y) { return supersampled.count({x, y}) ? supersampled[{x, y}] : 0; }
};

TEST(Adaptive, ColoursAreComparedAfterPovRaysAntialiasingGamma) {
  const ColourTest test(0.3);
  // Dark colours differ more after x^(1/2.5): 0 against 0.1 is 0.398 apart, 0.5 against
  // 0.6 only 0.057 (0.1 apart in linear terms either way).
  EXPECT_TRUE(test.differ({0, 0, 0}, {0.1f, 0, 0}));
  EXPECT_FALSE(test.differ({0.5f, 0, 0}, {0.6f, 0, 0}));
  // The channels' differences add up: 3 x 0.1 reaches the threshold where one does not.
  const float a = 0.5f, b = std::pow(std::pow(a, 0.4f) + 0.11f, 2.5f);
  EXPECT_FALSE(test.differ({a, a, a}, {b, a, a}));
  EXPECT_TRUE(test.differ({a, a, a}, {b, b, b}));
  // Negative channels count as 0.
  EXPECT_FALSE(test.differ({-1, 0, 0}, {0, 0, 0}));
}

TEST(Adaptive, Method1LeavesAFlatPictureAlone) {
  FakeSource s{[](double, double) { return 0.25f; }};
  antialiasBlockMethod1(0, 0, 8, 4, ColourTest(0.3), s);
  EXPECT_TRUE(s.supersampled.empty());
  // The block's centre rays plus its frame: the row above (8) and the column left (4).
  EXPECT_EQ(s.rays, 8 * 4 + 8 + 4);
  EXPECT_EQ(s.image.size(), 32u);
  EXPECT_EQ(s.at(3, 2), 0.25f);
}

TEST(Adaptive, Method1AtThresholdZeroSupersamplesEveryPixelOnce) {
  FakeSource s{[](double x, double y) { return float(x * 0.01 + y * 0.1); }};
  antialiasBlockMethod1(0, 0, 6, 5, ColourTest(0.0), s);
  EXPECT_EQ(s.supersampled.size(), 30u);
  for (const auto& [pixel, times] : s.supersampled) EXPECT_EQ(times, 1) << pixel.first << "," << pixel.second;
}

TEST(Adaptive, Method1SupersamplesBothSidesOfAnEdgeInsideABlock) {
  // Black left of x = 5, white from there: pixel 5 differs from its left neighbour, so
  // both 4 and 5 are supersampled, in every row, and nothing else is.
  FakeSource s{[](double x, double) { return x < 4.75 ? 0.0f : 1.0f; }};
  antialiasBlockMethod1(0, 0, 16, 3, ColourTest(0.3), s);
  EXPECT_EQ(s.supersampled.size(), 6u);
  for (int y = 0; y < 3; ++y) {
    EXPECT_EQ(s.times(4, y), 1);
    EXPECT_EQ(s.times(5, y), 1);
    EXPECT_EQ(s.at(3, y), 0.0f);
    EXPECT_EQ(s.at(4, y), 0.0f);  // its grid reaches 4.33: all black
    EXPECT_EQ(s.at(5, y), 0.7f);  // its grid's left column, at 4.67, is black
  }
}

TEST(Adaptive, Method1LeavesTheLastColumnOfABlockAloneAtAnEdgeOnTheBorder) {
  // The edge between the blocks [0,16) and [16,32): the second block compares pixel 16
  // with a fresh centre ray of pixel 15 that counts as done, and the first block never
  // compares pixel 15 with anything on its right. POV-Ray's +A0.3 images show this.
  FakeSource s{[](double x, double) { return x < 15.75 ? 0.0f : 1.0f; }};
  antialiasBlockMethod1(0, 0, 16, 2, ColourTest(0.3), s);
  antialiasBlockMethod1(16, 0, 32, 2, ColourTest(0.3), s);
  EXPECT_EQ(s.supersampled.size(), 2u);
  EXPECT_EQ(s.times(16, 0), 1);
  EXPECT_EQ(s.times(16, 1), 1);
}

TEST(Adaptive, Method1ComparesWithANeighboursSupersampledColour) {
  // Black above y = 1.75, white below: pixel (x, 2) differs from (x, 1), so both are
  // supersampled; (x, 2) becomes 0.7 (its grid's top row is black). Row 3 is white, as
  // its first-pass neighbours in row 2 were, but it is compared with 0.7: 0.133 apart
  // after the gamma. Under a threshold of 0.3 that is no difference; under 0.1 it is, and
  // row 3 is supersampled too.
  auto picture = [](double, double y) { return y < 1.75 ? 0.0f : 1.0f; };
  FakeSource s{picture};
  antialiasBlockMethod1(0, 0, 4, 4, ColourTest(0.3), s);
  EXPECT_EQ(s.supersampled.size(), 8u);
  for (int x = 0; x < 4; ++x) {
    EXPECT_EQ(s.times(x, 1), 1);
    EXPECT_EQ(s.times(x, 2), 1);
    EXPECT_EQ(s.at(x, 1), 0.0f);
    EXPECT_EQ(s.at(x, 2), 0.7f);
  }
  FakeSource t{picture};
  antialiasBlockMethod1(0, 0, 4, 4, ColourTest(0.1), t);
  EXPECT_EQ(t.supersampled.size(), 12u);
  for (int x = 0; x < 4; ++x) EXPECT_EQ(t.times(x, 3), 1);
}

TEST(Adaptive, Method2AtThresholdZeroIsTheTrapezoidRuleOnALattice) {
  // Full subdivision at +R3: a 5 x 5 lattice per pixel, whose mean of a linear ramp is its
  // value at the centre, exactly (every sum here is exact in float).
  FakeSource s{[](double x, double y) { return float(x + 8 * y); }};
  antialiasBlockMethod2(0, 0, 3, 2, 3, ColourTest(0.0), s);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x) EXPECT_EQ(s.at(x, y), float(x + 8 * y)) << x << "," << y;
  // Corners once for the block (4 x 3), then the 21 other lattice points of each pixel.
  EXPECT_EQ(s.rays, 4 * 3 + 6 * 21);
}

TEST(Adaptive, Method2OnlySplitsCellsWhoseCornersDiffer) {
  // A vertical edge at x = 1.1: only pixel 1's cells straddle it. Pixel 0's corners are
  // all black and pixel 2's all white.
  FakeSource s{[](double x, double) { return x < 1.1 ? 0.0f : 1.0f; }};
  antialiasBlockMethod2(0, 0, 3, 1, 2, ColourTest(0.3), s);
  EXPECT_EQ(s.at(0, 0), 0.0f);
  EXPECT_EQ(s.at(2, 0), 1.0f);
  // Pixel 1 ([0.5, 1.5]): one split at +R2 gives a 3 x 3 lattice at 0.5, 1, 1.5: the
  // columns are black, black, white, so its left quarters are 0, its right ones 1/2, and
  // it is 1/4.
  EXPECT_EQ(s.at(1, 0), 0.25f);
  EXPECT_EQ(s.rays, 4 * 2 + 5);
}

TEST(Adaptive, Method2AtDepthOneAveragesTheCorners) {
  FakeSource s{[](double x, double y) { return float(x * x + y); }};
  antialiasBlockMethod2(0, 0, 2, 1, 1, ColourTest(0.0), s);
  // Corners at x = -0.5, 0.5 (pixel 0): (0.25 + 0.25 + 0.25 + 0.25 + 2 * -0.5 + 2 * 0.5) / 4
  EXPECT_EQ(s.at(0, 0), 0.25f);
  EXPECT_EQ(s.rays, 3 * 2);
}

}  // namespace
}  // namespace pvrt
