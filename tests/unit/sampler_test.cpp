#include "render/sampler.h"

#include <gtest/gtest.h>

#include "core/error.h"

namespace pvrt {
namespace {

TEST(Sampler, PovOneSampleIsTheCentre) {
  PixelSampler s({SamplerKind::Pov, 1, 0});
  std::vector<SubSample> o;
  s.offsets(3, 4, o);
  ASSERT_EQ(o.size(), 1u);
  EXPECT_EQ(o[0].dx, 0);
  EXPECT_EQ(o[0].dy, 0);
}

TEST(Sampler, PovR3IsCentrePlusThreeByThreeGrid) {
  PixelSampler s({SamplerKind::Pov, 9, 0});
  std::vector<SubSample> o;
  s.offsets(0, 0, o);
  ASSERT_EQ(o.size(), 10u);
  EXPECT_EQ(s.count(), 10);
  EXPECT_DOUBLE_EQ(o[1].dx, -1.0 / 3);
  EXPECT_NEAR(o[2].dx, 0.0, 1e-16);  // POV-Ray's running sum reaches -5.55e-17 there
  EXPECT_DOUBLE_EQ(o[9].dy, 1.0 / 3);
}

// POV-Ray's SupersampleOnePixel adds the step to a running offset; the offsets it reaches
// are not -1/3, 0, 1/3 in their last bits, and a sample row on a checker cell boundary
// goes the way those bits say (issue 26 item 1).
TEST(Sampler, PovOffsetsAreTheAccumulatedOnesBitForBit) {
  PixelSampler s({SamplerKind::Pov, 9, 0});
  std::vector<SubSample> o;
  s.offsets(0, 0, o);
  ASSERT_EQ(o.size(), 10u);
  const double want[3] = {-0.33333333333333337, -5.551115123125783e-17, 0.33333333333333326};
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(o[1 + 3 * j + i].dx, want[i]) << i << "," << j;
      EXPECT_EQ(o[1 + 3 * j + i].dy, want[j]) << i << "," << j;
    }
}

TEST(Sampler, GridHasNoCentreRay) {
  PixelSampler s({SamplerKind::Grid, 4, 0});
  std::vector<SubSample> o;
  s.offsets(0, 0, o);
  ASSERT_EQ(o.size(), 4u);
  EXPECT_DOUBLE_EQ(o[0].dx, -0.25);
  EXPECT_DOUBLE_EQ(o[3].dy, 0.25);
}

TEST(Sampler, JitterStaysInItsStratumAndDependsOnlyOnPixelAndSeed) {
  PixelSampler s({SamplerKind::Jitter, 16, 7});
  std::vector<SubSample> a, b, c;
  s.offsets(5, 9, a);
  s.offsets(5, 9, b);
  s.offsets(6, 9, c);
  ASSERT_EQ(a.size(), 16u);
  for (size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].dx, b[k].dx);
    const int i = int(k % 4), j = int(k / 4);
    EXPECT_GE(a[k].dx, -0.5 + i / 4.0);
    EXPECT_LT(a[k].dx, -0.5 + (i + 1) / 4.0);
    EXPECT_GE(a[k].dy, -0.5 + j / 4.0);
    EXPECT_LT(a[k].dy, -0.5 + (j + 1) / 4.0);
  }
  EXPECT_NE(a[0].dx, c[0].dx);
}

TEST(Sampler, NonSquareSppIsAUsageError) {
  try {
    PixelSampler s({SamplerKind::Grid, 5, 0});
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ExitCode::Usage);
    EXPECT_STREQ(e.what(), "--spp must be a perfect square (1, 4, 9, 16, ...), got 5");
  }
}

TEST(Sampler, ParsesNames) {
  EXPECT_EQ(parseSamplerKind("jitter"), SamplerKind::Jitter);
  EXPECT_THROW(parseSamplerKind("random"), Error);
}

}  // namespace
}  // namespace pvrt
