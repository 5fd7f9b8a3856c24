// How a pixel's value is formed from samples that are not finite (render/pixel_value.h):
// channel by channel, as POV-Ray sums them in float and writes them.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "render/pixel_value.h"

namespace pvrt {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// A NaN channel of one sample (a negative red raised to a reflection exponent) makes that
// channel of the pixel 0, as POV-Ray's output does; the pixel's green and blue keep every
// sample, the NaN one's included (they were all black before: 0.5 instead of 0.75 below).
TEST(PixelValue, ANaNChannelIsZeroAndTheOtherChannelsKeepTheSample) {
  Color samples[2] = {{kNaN, 1.0, 0.5}, {0.25, 0.5, 0.5}};
  RenderStats stats;
  const bool finite = finiteSamples(samples, 2, stats);
  EXPECT_FALSE(finite);
  EXPECT_EQ(stats.nonFiniteSamples, 1u);
  EXPECT_TRUE(std::isnan(samples[0].r)) << "the census counts a sample, it does not change it";
  PixelSum sum;
  for (const Color& c : samples) sum.add(c);
  Image image(1, 1);
  setPixel(image, 0, 0, sum.mean(2), finite, stats);
  EXPECT_EQ(image.row(0)[0], 0.0f);
  EXPECT_EQ(image.row(0)[1], 0.75f);
  EXPECT_EQ(image.row(0)[2], 0.5f);
  EXPECT_EQ(stats.nonFinitePixels, 1u);
}

// An infinite channel sums to infinity (white in 8 bits, the largest float in the image),
// and +inf with -inf to NaN (0), channel by channel, as POV-Ray's float sum gives them.
TEST(PixelValue, InfiniteChannelsSumAsFloats) {
  Color samples[2] = {{kInf, kInf, 0.5}, {0.5, -kInf, 0.5}};
  RenderStats stats;
  const bool finite = finiteSamples(samples, 2, stats);
  EXPECT_EQ(stats.nonFiniteSamples, 2u);
  PixelSum sum;
  for (const Color& c : samples) sum.add(c);
  Image image(1, 1);
  setPixel(image, 0, 0, sum.mean(2), finite, stats);
  EXPECT_EQ(image.row(0)[0], std::numeric_limits<float>::max());
  EXPECT_EQ(image.row(0)[1], 0.0f);
  EXPECT_EQ(image.row(0)[2], 0.5f);
}

TEST(PixelValue, FiniteSamplesAreLeftAsTheyAre) {
  Color samples[1] = {{0.1, 0.2, 0.3}};
  RenderStats stats;
  EXPECT_TRUE(finiteSamples(samples, 1, stats));
  Image image(1, 1);
  PixelSum sum;
  sum.add(samples[0]);
  setPixel(image, 0, 0, sum.mean(1), true, stats);
  EXPECT_EQ(image.row(0)[1], 0.2f);
  EXPECT_EQ(stats.nonFiniteSamples + stats.nonFinitePixels, 0u);
}

}  // namespace
}  // namespace pvrt
