#include "render/time_budget.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "core/error.h"
#include "test_scenes.h"

namespace pvrt {
namespace {

// 100 pixels at 0.01 s per camera ray: one camera ray per pixel costs 1 s.
constexpr long kPixels = 100;
constexpr double kPerSample = 0.01;

TEST(TimeBudget, PredictionCountsTheSamplersRays) {
  EXPECT_DOUBLE_EQ(predictRenderSeconds(SamplerKind::Grid, 16, kPixels, kPerSample), 16.0);
  EXPECT_DOUBLE_EQ(predictRenderSeconds(SamplerKind::Pov, 16, kPixels, kPerSample), 17.0);  // + centre ray
  EXPECT_DOUBLE_EQ(predictRenderSeconds(SamplerKind::Pov, 1, kPixels, kPerSample), 1.0);
}

TEST(TimeBudget, ChoosesTheLargestSquareThatFits) {
  EXPECT_EQ(chooseSamplesPerPixel(SamplerKind::Grid, kPixels, kPerSample, 16.0), 16);
  EXPECT_EQ(chooseSamplesPerPixel(SamplerKind::Grid, kPixels, kPerSample, 15.9), 9);
  EXPECT_EQ(chooseSamplesPerPixel(SamplerKind::Pov, kPixels, kPerSample, 16.0), 9);  // 17 s for c = 16
  EXPECT_EQ(chooseSamplesPerPixel(SamplerKind::Jitter, kPixels, kPerSample, 1e9, 1000), 961);  // capped
}

TEST(TimeBudget, AtLeastOneSampleEvenWhenNothingFits) {
  EXPECT_EQ(chooseSamplesPerPixel(SamplerKind::Pov, kPixels, kPerSample, 0.5), 1);
}

TEST(TimeBudget, ChoiceIsMonotoneInTheBudget) {
  for (SamplerKind kind : {SamplerKind::Pov, SamplerKind::Grid, SamplerKind::Jitter}) {
    int previous = 0;
    for (double budget = 0.25; budget < 1e5; budget *= 1.1) {
      const int c = chooseSamplesPerPixel(kind, kPixels, kPerSample, budget);
      EXPECT_GE(c, previous) << "budget " << budget;
      EXPECT_GT(perfectSquareRoot(c), 0) << c;
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

TEST(TimeBudget, PilotRendersASixteenthOfThePixels) {
  const Scene scene = buildScene(loadSceneString("<scene><sphere center=\"0 0 3\" radius=\"1\"/></scene>", "t.xml"));
  const BudgetPlan plan = planForBudget(scene, test::settings(40, 20), 5.0, 64);
  EXPECT_EQ(plan.pilotWidth, 10);
  EXPECT_EQ(plan.pilotHeight, 5);
  EXPECT_GT(perfectSquareRoot(plan.samplesPerPixel), 0);
  EXPECT_LE(plan.samplesPerPixel, 64);
  EXPECT_GT(plan.secondsPerSample, 0);
}

}  // namespace
}  // namespace pvrt
