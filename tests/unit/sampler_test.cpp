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

TEST(Sampler, NonSquareSppIsAUsageErrorForGridAndPov) {
  for (SamplerKind kind : {SamplerKind::Grid, SamplerKind::Pov}) {
    try {
      PixelSampler s({kind, 5, 0});
      FAIL() << "expected an error";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ExitCode::Usage);
      EXPECT_EQ(std::string(e.what()), std::string("--spp must be a perfect square (1, 4, 9, 16, ...) for --sampler ") +
                                           samplerName(kind) + ", got 5 (--sampler jitter takes any c)");
    }
  }
}

TEST(Sampler, ZeroOrNegativeSppIsAUsageErrorForEverySampler) {
  for (SamplerKind kind : {SamplerKind::Grid, SamplerKind::Pov, SamplerKind::Jitter})
    for (int c : {0, -4}) {
      try {
        PixelSampler s({kind, c, 0});
        FAIL() << "expected an error for c = " << c;
      } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::Usage);
        EXPECT_EQ(std::string(e.what()), "--spp must be a positive whole number, got " + std::to_string(c));
      }
    }
}

TEST(Sampler, StratumRowsIsTheLargestDivisorNotAboveTheRoot) {
  EXPECT_EQ(stratumRows(1), 1);
  EXPECT_EQ(stratumRows(2), 1);
  EXPECT_EQ(stratumRows(7), 1);
  EXPECT_EQ(stratumRows(8), 2);
  EXPECT_EQ(stratumRows(12), 3);
  EXPECT_EQ(stratumRows(16), 4);
  EXPECT_EQ(stratumRows(24), 4);
  EXPECT_EQ(stratumRows(256), 16);
  EXPECT_EQ(stratumRows(1 << 16), 256);
  EXPECT_EQ(stratumRows(65521), 1);  // the largest prime below 2^16
}

// Every c from 1 to 300: exactly c samples, one in each cell of the rows x cols strata
// (each cell hit once), the same offsets on every call, different ones for another pixel.
TEST(Sampler, JitterTakesAnyCAndFillsEveryStratumOnce) {
  std::vector<SubSample> a, b, other;
  for (int c = 1; c <= 300; ++c) {
    PixelSampler s({SamplerKind::Jitter, c, 11});
    ASSERT_EQ(s.count(), c);
    s.offsets(17, 3, a);
    s.offsets(17, 3, b);
    s.offsets(18, 3, other);
    ASSERT_EQ(a.size(), size_t(c));
    const int rows = stratumRows(c), cols = c / rows;
    ASSERT_EQ(rows * cols, c);
    std::vector<int> hits(size_t(c), 0);
    for (int k = 0; k < c; ++k) {
      EXPECT_EQ(a[k].dx, b[k].dx);
      EXPECT_EQ(a[k].dy, b[k].dy);
      ASSERT_GE(a[k].dx, -0.5);
      ASSERT_LT(a[k].dx, 0.5);
      ASSERT_GE(a[k].dy, -0.5);
      ASSERT_LT(a[k].dy, 0.5);
      const int i = int((a[k].dx + 0.5) * cols), j = int((a[k].dy + 0.5) * rows);
      EXPECT_EQ(j * cols + i, k) << "c=" << c << " sample " << k << " left its stratum";
      ++hits[size_t(j * cols + i)];
    }
    for (int h : hits) EXPECT_EQ(h, 1) << "c=" << c;
    if (c > 1) {
      EXPECT_NE(a[0].dx, other[0].dx) << "c=" << c;
    }
  }
}

// c = 8 (the paper's figures): 2 rows of 4 columns; the mean offset of a stratified set is
// near the pixel centre over many pixels, as it must be for an unbiased estimate.
TEST(Sampler, JitterEightIsTwoRowsOfFourAndCentredOnAverage) {
  PixelSampler s({SamplerKind::Jitter, 8, 3});
  std::vector<SubSample> o;
  double sx = 0, sy = 0;
  int n = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      s.offsets(x, y, o);
      for (int k = 0; k < 8; ++k) {
        EXPECT_EQ(int((o[k].dx + 0.5) * 4), k % 4);
        EXPECT_EQ(int((o[k].dy + 0.5) * 2), k / 4);
        sx += o[k].dx;
        sy += o[k].dy;
        ++n;
      }
    }
  EXPECT_NEAR(sx / n, 0.0, 0.01);
  EXPECT_NEAR(sy / n, 0.0, 0.01);
}

// Squares keep the n x n strata and the very same offsets as before any c was allowed
// (images rendered with --sampler jitter at square c do not change). The pinned values are
// what the square-only sampler (commit 9fa70c3) gave for pixel (5, 9), seed 7, c = 16.
TEST(Sampler, JitterAtASquareKeepsItsSquareStrata) {
  PixelSampler s16({SamplerKind::Jitter, 16, 7});
  EXPECT_EQ(stratumRows(16), 4);
  std::vector<SubSample> o;
  s16.offsets(5, 9, o);
  ASSERT_EQ(o.size(), 16u);
  for (int k = 0; k < 16; ++k) {
    EXPECT_EQ(int((o[k].dx + 0.5) * 4), k % 4);
    EXPECT_EQ(int((o[k].dy + 0.5) * 4), k / 4);
  }
  EXPECT_EQ(o[0].dx, -0x1.062eddb4edf45p-2);
  EXPECT_EQ(o[0].dy, -0x1.94cf151054932p-2);
  EXPECT_EQ(o[5].dx, -0x1.21d1742f8236ep-3);
  EXPECT_EQ(o[5].dy, -0x1.fd00b00cd150ap-3);
  EXPECT_EQ(o[15].dx, 0x1.802d4f5aed0c6p-2);
  EXPECT_EQ(o[15].dy, 0x1.fa8a707d2f27ap-2);
}

TEST(Sampler, SequenceSampleKDoesNotDependOnC) {
  SamplerSettings few{SamplerKind::Sequence, 5, 3}, many{SamplerKind::Sequence, 37, 3};
  std::vector<SubSample> a, b, c;
  PixelSampler(few).offsets(4, 9, a);
  PixelSampler(many).offsets(4, 9, b);
  ASSERT_EQ(a.size(), 5u);
  ASSERT_EQ(b.size(), 37u);
  for (size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].dx, b[k].dx);
    EXPECT_EQ(a[k].dy, b[k].dy);
  }
  for (const SubSample& o : b) {
    EXPECT_GE(o.dx, -0.5);
    EXPECT_LT(o.dx, 0.5);
    EXPECT_GE(o.dy, -0.5);
    EXPECT_LT(o.dy, 0.5);
  }
  // A pass's window is the tail of the whole.
  many.firstSample = 32;
  PixelSampler(many).offsets(4, 9, c);
  ASSERT_EQ(c.size(), 5u);
  for (size_t k = 0; k < c.size(); ++k) EXPECT_EQ(c[k].dx, b[32 + k].dx);
  // Another pixel or seed, other points.
  PixelSampler(few).offsets(5, 9, c);
  EXPECT_NE(c[0].dx, a[0].dx);
  PixelSampler({SamplerKind::Sequence, 5, 4}).offsets(4, 9, c);
  EXPECT_NE(c[0].dx, a[0].dx);
}

TEST(Sampler, SequenceSpreadsEveryPrefixOverThePixel) {
  // Each quarter of the pixel holds about a quarter of the first c samples, for every c.
  for (int c = 4; c <= 256; ++c) {
    std::vector<SubSample> o;
    PixelSampler({SamplerKind::Sequence, c, 11}).offsets(2, 3, o);
    int quarter[4] = {};
    for (const SubSample& s : o) ++quarter[(s.dx < 0 ? 0 : 1) + (s.dy < 0 ? 0 : 2)];
    for (int q : quarter) {
      EXPECT_GE(q, c / 4 - 2) << "c = " << c;
      EXPECT_LE(q, c / 4 + 3) << "c = " << c;
    }
  }
}

TEST(Sampler, SequenceSamplesAreTracedEachOnItsOwn) {
  // The shadow cache restarts at every sample of sequence (passes may cut a pixel anywhere),
  // only at a pixel's first for the others.
  const PixelSampler seq({SamplerKind::Sequence, 300, 0}), jitter({SamplerKind::Jitter, 300, 0});
  for (int k = 0; k < 300; ++k) {
    EXPECT_TRUE(seq.restartsAt(k)) << k;
    EXPECT_EQ(jitter.restartsAt(k), k == 0) << k;
  }
  SamplerSettings s{SamplerKind::Sequence, 10, 0};
  s.firstSample = 3;
  EXPECT_EQ(PixelSampler(s).firstSample(), 3);
  s.firstSample = 10;  // nothing left to trace
  EXPECT_THROW(PixelSampler{s}, Error);
  s.firstSample = -1;
  EXPECT_THROW(PixelSampler{s}, Error);
  s.firstSample = 3;
  s.kind = SamplerKind::Jitter;  // its samples depend on c: no passes
  EXPECT_THROW(PixelSampler{s}, Error);
}

TEST(Sampler, ParsesNames) {
  EXPECT_EQ(parseSamplerKind("jitter"), SamplerKind::Jitter);
  EXPECT_EQ(parseSamplerKind("sequence"), SamplerKind::Sequence);
  EXPECT_THROW(parseSamplerKind("random"), Error);
}

}  // namespace
}  // namespace pvrt
