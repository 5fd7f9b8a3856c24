// The load map's picture: the map in false colour, and under it a colour bar with labelled ticks.
#include "image/load_map_picture.h"

#include <gtest/gtest.h>

namespace pvrt {
namespace {

bool same(const Image& image, int x, int y, const Color& c) {
  const float* p = image.row(y) + size_t(x) * 3;
  return p[0] == float(c.r) && p[1] == float(c.g) && p[2] == float(c.b);
}

TEST(LoadMapPicture, CountsAreWrittenCompactly) {
  EXPECT_EQ(compactCount(0), "0");
  EXPECT_EQ(compactCount(950), "950");
  EXPECT_EQ(compactCount(1000), "1.0k");
  EXPECT_EQ(compactCount(12345), "12k");
  EXPECT_EQ(compactCount(999999), "1.0M");
  EXPECT_EQ(compactCount(3.4e6), "3.4M");
  EXPECT_EQ(compactCount(1.2e9), "1.2G");
}

TEST(LoadMapPicture, TheRampRunsFromTheLeastWorkToTheMost) {
  EXPECT_TRUE(loadMapColour(10, 10, 1000) == Color(0.0, 0.0, 0.05));
  EXPECT_TRUE(loadMapColour(1000, 10, 1000) == Color(1.0, 1.0, 0.6));
  EXPECT_TRUE(loadMapColour(5, 5, 5) == Color(0.0, 0.0, 0.05));  // a uniform map
}

TEST(LoadMapPicture, TheBarIsUnderTheMapWithItsEndsLabelled) {
  const int w = 64, h = 10;
  std::vector<float> load(size_t(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) load[size_t(y) * w + x] = float(20 + 100 * x);  // 20 to 6320
  const Image p = loadMapPicture(load, w, h);
  ASSERT_EQ(p.width(), w);
  ASSERT_EQ(p.height(), h + colourBarRows(w));
  // The map itself is unchanged by the bar.
  EXPECT_TRUE(same(p, 0, 0, loadMapColour(20, 20, 6320)));
  EXPECT_TRUE(same(p, w - 1, h - 1, loadMapColour(6320, 20, 6320)));
  // The bar's ends are the ramp's ends; the strip around them is white.
  const int barRow = h + 3 + 2;
  EXPECT_TRUE(same(p, 2, barRow, loadMapColour(20, 20, 6320)));
  EXPECT_TRUE(same(p, w - 3, barRow, loadMapColour(6320, 20, 6320)));
  EXPECT_TRUE(same(p, 0, barRow, Color(1, 1, 1)));
  // Labels: dark pixels under the left end ("20") and the right end ("6.3k").
  auto inked = [&](int x0, int x1) {
    int n = 0;
    for (int y = h + 12; y < p.height(); ++y)
      for (int x = x0; x < x1; ++x) n += same(p, x, y, Color(0, 0, 0));
    return n;
  };
  EXPECT_GT(inked(0, 8), 10);
  EXPECT_GT(inked(w - 16, w), 10);
}

TEST(LoadMapPicture, ANarrowMapStillGetsItsBar) {
  const std::vector<float> load(4, 7.0f);
  const Image p = loadMapPicture(load, 2, 2);
  EXPECT_EQ(p.height(), 2 + colourBarRows(2));
}

}  // namespace
}  // namespace pvrt
