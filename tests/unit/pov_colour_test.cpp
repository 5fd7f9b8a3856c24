// render/pov_colour.h does POV-Ray's float colour terms with a colour's channels in vector
// lanes. Each result is checked against the same operations written one channel at a time
// through volatile floats, which no optimiser can fold: a lane form that dropped a rounding
// (core/single.h) or changed an order would differ in the last bits for some of these values.
#include "render/pov_colour.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "float_channels.h"

namespace pvrt::povcolour {
namespace {

Color randomColour(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-0.5, 2.0);
  return {u(rng), u(rng), u(rng)};  // doubles with bits below a float's
}

TEST(PovColour, RoundedKeepsEachChannelsNearestFloat) {
  std::mt19937_64 rng(26);
  for (int i = 0; i < 1000; ++i) {
    const Color c = randomColour(rng);
    expectChannels(rounded(c), roundedOnce(c.r), roundedOnce(c.g), roundedOnce(c.b));
  }
  EXPECT_NE(toColor(rounded({1.33, 0.1, 0.7})).r, 1.33);
}

TEST(PovColour, DiffuseTermIsPovRaysFloatChain) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 1000; ++i) {
    const Color pigment = randomColour(rng), light = randomColour(rng);
    const double cosPower = u(rng), diffuseK = u(rng), attenuation = u(rng);
    const double k = cosPower * (diffuseK * attenuation);
    const FloatColour got = diffuse(widened(rounded(pigment)), k, rounded(light));
    auto channel = [&](double p, double l) {
      const volatile float product = scaledChannel(p, k);
      return roundedOnce(double(product * roundedOnce(l)));
    };
    expectChannels(got, channel(pigment.r, light.r), channel(pigment.g, light.g), channel(pigment.b, light.b));
  }
}

TEST(PovColour, AmbientAndHighlightAreSumsOfFloatProducts) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 1000; ++i) {
    const Color p = randomColour(rng), a = randomColour(rng), al = randomColour(rng), e = randomColour(rng);
    const double opacity = u(rng), h = u(rng);
    auto channel = [&](double pc, double ac, double alc, double ec) {
      const volatile float pa = roundedOnce(pc) * roundedOnce(ac);
      const volatile float paal = pa * roundedOnce(alc);
      const volatile float pe = roundedOnce(pc) * roundedOnce(ec);
      const volatile float sum = scaledChannel(paal, opacity) + scaledChannel(pe, opacity);
      return float(sum);
    };
    expectChannels(ambient(p, a, al, e, opacity), channel(p.r, a.r, al.r, e.r), channel(p.g, a.g, al.g, e.g),
                   channel(p.b, a.b, al.b, e.b));
    expectChannels(highlight(widened(rounded(p)), h), scaledChannel(p.r, h), scaledChannel(p.g, h),
                   scaledChannel(p.b, h));
  }
}

// ComputePhongColour's metallic tint: light x (1 + (m(1 - F)) x (pigment - 1)), every colour
// operation a float, then intensity x that; F 0 where acos is NaN (a cosine above 1).
TEST(PovColour, MetallicHighlightIsPovRaysFloatChain) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0), m(-0.5, 2.5);
  for (int i = 0; i < 1000; ++i) {
    const Color light = randomColour(rng), pigment = randomColour(rng);
    const double h = u(rng), metallic = double(float(m(rng)));
    const double nl = i == 0 ? std::nextafter(1.0, 2.0) : u(rng);
    const double x = std::fabs(std::acos(nl)) / 1.57079632679489661923;
    double f = 0.014567225 / ((x - 1.12) * (x - 1.12)) - 0.011612903;
    f = std::min(1.0, std::max(0.0, f));
    auto channel = [&](double lc, double pc) {
      const volatile float less = roundedOnce(pc) - 1.0f;
      const volatile float tint = 1.0f + scaledChannel(less, metallic * (1.0 - f));
      const volatile float cs = roundedOnce(lc) * tint;
      return scaledChannel(cs, h);
    };
    expectChannels(metallicHighlight(rounded(light), h, metallic, nl, rounded(pigment)), channel(light.r, pigment.r),
                   channel(light.g, pigment.g), channel(light.b, pigment.b));
  }
}

}  // namespace
}  // namespace pvrt::povcolour
