// render/pov_colour.h does POV-Ray's float colour terms with a colour's channels in vector
// lanes. Each result is checked against the same operations written one channel at a time
// through volatile floats, which no optimiser can fold: a lane form that dropped a rounding
// (core/single.h) or changed an order would differ in the last bits for some of these values.
#include <gtest/gtest.h>

#include <random>

#include "float_channels.h"

#include "render/pov_colour.h"

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

}  // namespace
}  // namespace pvrt::povcolour
