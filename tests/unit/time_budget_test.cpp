#include "render/time_budget.h"

#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.h"
#include "test_scenes.h"

namespace pvrt {
namespace {

// 100 pixels at 0.01 s per camera ray: one camera ray per pixel costs 1 s.
constexpr long kPixels = 100;
const std::vector<CostPoint> kProportional = {{1, 0.01}};
// 0.01 s a pixel whatever its rays, plus 0.001 s a ray: measured at 1 and 17 rays.
const std::vector<CostPoint> kAffine = {{17, 0.027}, {1, 0.011}};

TEST(TimeBudget, CameraRaysAreTheSamplersCount) {
  for (SamplerKind kind : {SamplerKind::Pov, SamplerKind::Grid, SamplerKind::Jitter})
    for (int c : {1, 4, 9, 16, 64, 1024})
      EXPECT_EQ(cameraRaysPerPixel(kind, c), double(PixelSampler(SamplerSettings{kind, c, 0}).count())) << c;
}

TEST(TimeBudget, OnePointPredictsInProportionToTheRays) {
  EXPECT_DOUBLE_EQ(predictSecondsPerPixel(kProportional, 16), 0.16);
  EXPECT_DOUBLE_EQ(predictSecondsPerPixel(kProportional, 17), 0.17);
}

TEST(TimeBudget, TwoPointsGiveTheLineThroughThem) {
  EXPECT_NEAR(predictSecondsPerPixel(kAffine, 5), 0.015, 1e-12);   // between
  EXPECT_NEAR(predictSecondsPerPixel(kAffine, 17), 0.027, 1e-12);  // measured
  EXPECT_NEAR(predictSecondsPerPixel(kAffine, 65), 0.075, 1e-12);  // beyond, on the line
}

TEST(TimeBudget, ExtrapolationRisesByHalfToAllOfTheCostPerRay) {
  // Noise made 17 rays cheaper than 1: beyond, at least half the last point's cost a ray is added.
  EXPECT_NEAR(predictSecondsPerPixel({{1, 0.05}, {17, 0.04}}, 100), 0.05 + 0.5 * 0.05 / 17 * 83, 1e-12);
  // A slope above the last point's cost per ray is cut to it.
  EXPECT_NEAR(predictSecondsPerPixel({{1, 0.001}, {2, 0.1}}, 4), 0.2, 1e-12);
}

TEST(TimeBudget, ChoosesTheLargestSquareThatFits) {
  // pov: c = n*n traces n*n + 1 rays; proportional: 1 s a ray per pixel.
  EXPECT_EQ(chooseSamplesPerPixel(SamplerKind::Grid, kPixels, kProportional, 16.0), 16);
  EXPECT_EQ(chooseSamplesPerPixel(SamplerKind::Grid, kPixels, kProportional, 15.9), 9);
  EXPECT_EQ(chooseSamplesPerPixel(SamplerKind::Pov, kPixels, kProportional, 16.0), 9);  // 17 s for c = 16
  EXPECT_EQ(chooseSamplesPerPixel(SamplerKind::Grid, kPixels, kProportional, 1e9, 1000), 961);  // capped
  // Affine: c = 16 (17 rays) costs 2.7 s, c = 25 (26 rays) 3.6 s.
  EXPECT_EQ(chooseSamplesPerPixel(SamplerKind::Pov, kPixels, kAffine, 3.5), 16);
  EXPECT_EQ(chooseSamplesPerPixel(SamplerKind::Pov, kPixels, kAffine, 3.6 + 1e-9), 25);
}

TEST(TimeBudget, JitterTakesAnyWholeNumberThatFits) {
  EXPECT_EQ(chooseSamplesPerPixel(SamplerKind::Jitter, kPixels, kProportional, 20.0), 20);
  EXPECT_EQ(chooseSamplesPerPixel(SamplerKind::Jitter, kPixels, kProportional, 19.99), 19);
  EXPECT_EQ(chooseSamplesPerPixel(SamplerKind::Jitter, kPixels, kProportional, 2.5), 2);
  EXPECT_EQ(chooseSamplesPerPixel(SamplerKind::Jitter, kPixels, kProportional, 1e9, 1000), 1000);  // capped
  // Affine: c = 20 costs 1 + 2 = 3.0 s.
  EXPECT_EQ(chooseSamplesPerPixel(SamplerKind::Jitter, kPixels, kAffine, 3.0 + 1e-9), 20);
}

TEST(TimeBudget, SmallerCountsAreOnesTheSamplerTakes) {
  EXPECT_EQ(nextSmallerCount(SamplerKind::Pov, 25), 16);
  EXPECT_EQ(nextSmallerCount(SamplerKind::Grid, 4), 1);
  EXPECT_EQ(nextSmallerCount(SamplerKind::Jitter, 20), 15);
  EXPECT_EQ(nextSmallerCount(SamplerKind::Jitter, 3), 2);
  for (SamplerKind kind : {SamplerKind::Pov, SamplerKind::Jitter}) EXPECT_EQ(nextSmallerCount(kind, 1), 1);
  EXPECT_TRUE(takesAnyCount(SamplerKind::Jitter));
  EXPECT_FALSE(takesAnyCount(SamplerKind::Pov));
}

TEST(TimeBudget, AtLeastOneSampleEvenWhenNothingFits) {
  EXPECT_EQ(chooseSamplesPerPixel(SamplerKind::Pov, kPixels, kProportional, 0.5), 1);
}

TEST(TimeBudget, ChoiceIsMonotoneInTheBudget) {
  for (SamplerKind kind : {SamplerKind::Pov, SamplerKind::Grid, SamplerKind::Jitter})
    for (const auto& points : {kProportional, kAffine, std::vector<CostPoint>{{1, 0.05}, {17, 0.04}, {50, 0.3}}}) {
      int previous = 0;
      for (double budget = 0.25; budget < 1e5; budget *= 1.1) {
        const int c = chooseSamplesPerPixel(kind, kPixels, points, budget);
        EXPECT_GE(c, previous) << "budget " << budget;
        if (!takesAnyCount(kind)) {
          EXPECT_GT(perfectSquareRoot(c), 0) << c;
        }
        previous = c;
      }
      EXPECT_GT(previous, 1);
    }
}

TEST(TimeBudget, RejectsBudgetsThatAreNotPositive) {
  const Scene scene = buildScene(loadSceneString("<scene><sphere center=\"0 0 3\" radius=\"1\"/></scene>", "t.xml"));
  for (double b : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN()}) {
    try {
      planForBudget(scene, test::settings(8, 8), b);
      FAIL() << "accepted " << b;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ExitCode::Usage);
    }
  }
}

TEST(TimeBudget, PilotsRenderASampleOfTheImageAtItsResolution) {
  const Scene scene = buildScene(loadSceneString("<scene><sphere center=\"0 0 3\" radius=\"1\"/></scene>", "t.xml"));
  const BudgetPlan plan = planForBudget(scene, test::settings(160, 96), 5.0, 0.0, 64);
  ASSERT_GE(plan.pilotSamples.size(), 1u);
  EXPECT_EQ(plan.pilotSamples.front(), 1);
  // Every 17th of 60 tiles of 16 x 16: tiles 0, 17, 34 and 51.
  EXPECT_DOUBLE_EQ(plan.pilotShare, 4.0 / 60.0);
  for (size_t i = 1; i < plan.pilotSamples.size(); ++i) EXPECT_GT(plan.pilotSamples[i], plan.pilotSamples[i - 1]);
  EXPECT_EQ(plan.points.size(), plan.pilotSamples.size());
  EXPECT_GT(perfectSquareRoot(plan.samplesPerPixel), 0);
  EXPECT_LE(plan.samplesPerPixel, 64);
  EXPECT_GT(plan.pilotSeconds, 0);
}

TEST(TimeBudget, TimeAlreadySpentLeavesLess) {
  const Scene scene = buildScene(loadSceneString("<scene><sphere center=\"0 0 3\" radius=\"1\"/></scene>", "t.xml"));
  const BudgetPlan plan = planForBudget(scene, test::settings(64, 64), 1.0, 2.0);
  EXPECT_EQ(plan.samplesPerPixel, 1);
  EXPECT_FALSE(plan.fits);
  EXPECT_EQ(plan.pilotSamples.size(), 1u);
}

}  // namespace
}  // namespace pvrt
