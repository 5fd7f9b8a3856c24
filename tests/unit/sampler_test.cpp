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
  EXPECT_DOUBLE_EQ(o[2].dx, 0.0);
  EXPECT_DOUBLE_EQ(o[9].dy, 1.0 / 3);
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
