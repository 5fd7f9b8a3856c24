#include "render/accuracy.h"

#include <cmath>

#include <gtest/gtest.h>

#include "core/error.h"

namespace pvrt {
namespace {

TEST(Accuracy, IdenticalImagesHaveNoError) {
  const std::vector<uint8_t> a{10, 20, 30, 40, 50, 60};
  const ImageError e = imageError8(a, a);
  EXPECT_EQ(e.rmse, 0);
  EXPECT_TRUE(std::isinf(e.psnr));
  EXPECT_EQ(e.shareOver1, 0);
}

TEST(Accuracy, ErrorIsInLevelsAndCountsPixelsOverOneLevel) {
  const std::vector<uint8_t> ref{10, 20, 30, 40, 50, 60};
  const std::vector<uint8_t> test{13, 20, 30, 41, 50, 60};  // pixel 0: 3 levels off, pixel 1: 1 level
  const ImageError e = imageError8(test, ref);
  EXPECT_DOUBLE_EQ(e.rmse, std::sqrt(10.0 / 6.0));
  EXPECT_DOUBLE_EQ(e.psnr, 20 * std::log10(255 / std::sqrt(10.0 / 6.0)));
  EXPECT_DOUBLE_EQ(e.shareOver1, 0.5);
}

TEST(Accuracy, SizesMustMatch) {
  EXPECT_THROW(imageError8({1, 2, 3}, {1, 2, 3, 4, 5, 6}), Error);
  EXPECT_THROW(imageError(Image(2, 2), Image(2, 3)), Error);
}

// error = 10 / sqrt(t / 1 s): a Monte Carlo curve, a straight line in log-log.
const std::vector<CurvePoint> kCurve{{1, 10}, {100, 1}, {4, 5}};

TEST(Accuracy, ReadsCurvesInLogLogSpace) {
  EXPECT_NEAR(*errorAtTime(kCurve, 25), 2.0, 1e-12);
  EXPECT_NEAR(*timeAtError(kCurve, 2.0), 25.0, 1e-9);
  EXPECT_NEAR(*errorAtTime(kCurve, 4), 5.0, 1e-12);
  EXPECT_FALSE(errorAtTime(kCurve, 0.5));
  EXPECT_FALSE(errorAtTime(kCurve, 200));
  EXPECT_FALSE(timeAtError(kCurve, 0.5));
  EXPECT_FALSE(timeAtError(kCurve, 11));
}

TEST(Accuracy, CommonReadingsAreReachedByEveryCurve) {
  const std::vector<std::vector<CurvePoint>> curves{kCurve, {{2, 8}, {50, 3}}};
  EXPECT_EQ(commonTime(curves), 50);
  EXPECT_EQ(commonError(curves), 3);
}

TEST(Accuracy, NearestPerfectSquare) {
  EXPECT_EQ(nearestPerfectSquare(0.3), 1);
  EXPECT_EQ(nearestPerfectSquare(16), 16);
  EXPECT_EQ(nearestPerfectSquare(8), 9);
  EXPECT_EQ(nearestPerfectSquare(12), 9);
  EXPECT_EQ(nearestPerfectSquare(32), 36);
  EXPECT_EQ(nearestPerfectSquare(48), 49);
}

}  // namespace
}  // namespace pvrt
