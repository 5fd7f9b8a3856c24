// render/pov_secondary.h does POV-Ray's float colour arithmetic for reflected and transmitted
// light. Each result is checked against the same operations of trace.cpp written one
// channel at a time through volatile floats, and against values where the double
// arithmetic pvrt used before gives a different float.
#include <gtest/gtest.h>

#include <random>

#include "float_channels.h"

#include "render/pov_secondary.h"

namespace pvrt::povcolour {
namespace {

Color randomColour(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  return {roundedOnce(u(rng)), roundedOnce(u(rng)), roundedOnce(u(rng))};  // stored as floats, as finishes are
}

// ComputeReflectivity, case 0: frac x max + (1 - frac) x min, each product a float.
TEST(PovSecondary, StandardReflectivityIsTwoFloatProductsAdded) {
  std::mt19937_64 rng(26);
  std::uniform_real_distribution<double> u(0.01, 0.99);
  for (int i = 0; i < 1000; ++i) {
    ReflectionDesc r;
    r.min = randomColour(rng), r.max = randomColour(rng);
    r.falloff = roundedOnce(1 + 3 * u(rng));
    const double cosI = u(rng);
    const double frac = std::pow(1.0 - cosI, r.falloff);
    auto channel = [&](double mx, double mn) {
      const volatile float a = scaledChannel(float(mx), frac), b = scaledChannel(float(mn), 1.0 - frac);
      return float(a + b);
    };
    const Reflectivity got = reflectivity(r, cosI, 1.0);
    expectChannels(got.colour, channel(r.max.r, r.min.r), channel(r.max.g, r.min.g), channel(r.max.b, r.min.b));
    EXPECT_EQ(got.weightFactor, std::max(r.max.maxComponent(), r.min.maxComponent()));
  }
}

// A plain `reflection 0.4` is blended with itself, as POV-Ray does: not always 0.4f.
TEST(PovSecondary, EqualMinAndMaxAreStillBlended) {
  ReflectionDesc r;
  r.min = r.max = Color(roundedOnce(0.4));
  r.falloff = roundedOnce(1.7);
  int differ = 0;
  for (int i = 1; i < 1000; ++i) {
    const double cosI = i / 1000.0;
    const double frac = std::pow(1.0 - cosI, r.falloff);
    const volatile float a = scaledChannel(0.4f, frac), b = scaledChannel(0.4f, 1.0 - frac);
    const float expected = a + b;
    EXPECT_EQ(toColor(reflectivity(r, cosI, 1.0).colour).r, double(expected));
    differ += expected != 0.4f;
  }
  EXPECT_GT(differ, 0);  // so the blend is not the identity this test would miss
}

TEST(PovSecondary, FresnelFactorInPovRaysOrder) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.01, 0.99);
  for (int i = 0; i < 1000; ++i) {
    ReflectionDesc r;
    r.fresnel = true;
    r.min = randomColour(rng), r.max = randomColour(rng);
    const double cosI = u(rng), ior = roundedOnce(1 + u(rng));
    const double g = std::sqrt(ior * ior + cosI * cosI - 1.0);
    double f = 0.5 * ((g - cosI) * (g - cosI) / ((g + cosI) * (g + cosI)));
    f = f * (1.0 + (cosI * (g + cosI) - 1.0) * (cosI * (g + cosI) - 1.0) /
                       ((cosI * (g - cosI) + 1.0) * (cosI * (g - cosI) + 1.0)));
    f = std::min(1.0, std::max(0.0, f));
    auto channel = [&](double mx, double mn) {
      const volatile float a = scaledChannel(float(mx), f), b = scaledChannel(float(mn), 1.0 - f);
      return float(a + b);
    };
    const float cr = channel(r.max.r, r.min.r), cg = channel(r.max.g, r.min.g), cb = channel(r.max.b, r.min.b);
    const Reflectivity got = reflectivity(r, cosI, ior);
    expectChannels(got.colour, cr, cg, cb);
    EXPECT_EQ(got.weightFactor, double(std::max(cr, std::max(cg, cb))));
  }
}

TEST(PovSecondary, MetallicTintScalesEachFloatChannel) {
  const FloatColour rho{0.3f, 0.6f, 0.05f};
  const Color pigment(roundedOnce(0.2), roundedOnce(0.7), roundedOnce(0.4));
  const double cosI = 0.35, metallic = roundedOnce(0.3);
  const double x = std::fabs(std::acos(cosI)) / 1.57079632679489661923;
  const double F = std::min(1.0, std::max(0.0, 0.014567225 / ((x - 1.12) * (x - 1.12)) - 0.011612903));
  auto channel = [&](float c, double p) { return scaledChannel(c, 1.0 + metallic * (1.0 - F) * (p - 1.0)); };
  expectChannels(metallicReflection(rho, metallic, cosI, pigment), channel(0.3f, pigment.r),
                 channel(0.6f, pigment.g), channel(0.05f, pigment.b));
  // acos of a cosine a rounding above 1 is NaN; POV-Ray's max(0, F) makes F 0: the full tint.
  const Color tinted = toColor(metallicReflection(rho, 1.0, std::nextafter(1.0, 2.0), pigment));
  EXPECT_EQ(tinted.r, double(scaledChannel(0.3f, pigment.r)));
}

TEST(PovSecondary, FilterAndFadeAreFloatColours) {
  FilterColor pig;
  pig.rgb = Color(roundedOnce(0.2), roundedOnce(0.7), roundedOnce(0.4));
  pig.filter = roundedOnce(0.3), pig.transmit = roundedOnce(0.2);
  auto filterChannel = [&](double c) {
    const volatile float product = float(c) * float(pig.filter);
    return float(product + float(pig.transmit));
  };
  const FloatColour filter = transmittedFilter(pig);
  expectChannels(filter, filterChannel(pig.rgb.r), filterChannel(pig.rgb.g), filterChannel(pig.rgb.b));

  InteriorDesc in;
  in.fadeColor = Color(roundedOnce(0.5), roundedOnce(0.8), roundedOnce(0.1));
  in.fadeDistance = roundedOnce(1.7), in.fadePower = 2;
  const double depth = 0.9;
  const double att = 1.0 + std::pow(depth / in.fadeDistance, in.fadePower);
  auto fadeChannel = [&](double c) {
    const volatile float rest = 1.0f - float(c);
    const volatile float quotient = roundedOnce(double(rest) / att);
    return float(float(c) + quotient);
  };
  expectChannels(interiorFade(in, depth), fadeChannel(in.fadeColor.r), fadeChannel(in.fadeColor.g),
                 fadeChannel(in.fadeColor.b));
  in.fadePower = 1001;
  auto expChannel = [&](double c) {
    const volatile float e = scaledChannel(-(1.0f - float(c)), depth / in.fadeDistance);
    return std::exp(float(e));
  };
  expectChannels(interiorFade(in, depth), expChannel(in.fadeColor.r), expChannel(in.fadeColor.g),
                 expChannel(in.fadeColor.b));
}

}  // namespace
}  // namespace pvrt::povcolour
