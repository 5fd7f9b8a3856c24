// Values POV-Ray keeps in single precision reach pvrt's shading rounded to the nearest
// float (core/single.h). The reference rounding here goes through memory, where no
// optimiser can drop it; GCC 12's vectoriser dropped the one in the material table for
// four neighbouring fields (interior ior and fades), so each field is checked.
#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "core/single.h"
#include "render/light.h"
#include "render/material.h"

namespace pvrt {
namespace {

double viaMemory(double v) {
  volatile float f = float(v);
  return double(f);
}

// Values with bits below a float's: each must change when rounded.
constexpr double kIor = 1.33, kFadeDistance = 2.1, kFadePower = 1.7;
const Color kColor{0.1, 0.7, 0.3};

TEST(Single, RoundsToTheNearestFloat) {
  for (double v : {1.33, 0.1, -2.7, 1e-30, 3.4e38}) EXPECT_EQ(single(v), viaMemory(v)) << v;
  EXPECT_NE(single(1.33), 1.33);
  EXPECT_EQ(single(1.33), 1.3300000429153442);
}

TEST(Single, RoundsEveryLaneOfAnArray) {
  // The shape of code GCC 12 vectorised without rounding: four neighbouring doubles.
  double in[4] = {kIor, kFadeDistance, kFadePower, 0.1}, out[4];
  for (int i = 0; i < 4; ++i) out[i] = single(in[i]);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(out[i], viaMemory(in[i])) << i;
}

// A colour's three channels rounded at once (the AVX path) give each channel's rounding.
TEST(Single, ColourChannelsEachRounded) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> v(-2, 2);
  for (int i = 0; i < 10000; ++i) {
    const Color c{v(rng), v(rng) * 1e-20, v(rng) * 1e30};
    const Color r = single(c);
    ASSERT_EQ(r.r, viaMemory(c.r));
    ASSERT_EQ(r.g, viaMemory(c.g));
    ASSERT_EQ(r.b, viaMemory(c.b));
  }
  const Vec3 p = single(Vec3{0.1, 0.2, 0.3});
  EXPECT_EQ(p.y, viaMemory(0.2));
}

TEST(Single, MaterialTableRoundsInteriorFinishAndPigment) {
  MaterialDesc m;
  m.pigment.color = {kColor, 0.37, 0.11};
  m.finish.edit([](FinishDesc& f) {
    f.ambient = Color(0.13);
    f.diffuse = 0.61;
    f.phong = 0.33;
    f.reflection.max = Color(0.03);
    f.reflection.min = Color(0.03);
  });
  m.interior.edit([](InteriorDesc& in) {
    in.ior = kIor;
    in.fadeDistance = kFadeDistance;
    in.fadePower = kFadePower;
    in.fadeColor = kColor;
  });
  MaterialTable table;
  table.add(m, Affine{});
  const Surface& s = table.surface(table[0]);
  EXPECT_EQ(s.interior.ior, viaMemory(kIor));
  EXPECT_EQ(s.interior.fadeDistance, viaMemory(kFadeDistance));
  EXPECT_EQ(s.interior.fadePower, viaMemory(kFadePower));
  EXPECT_EQ(s.interior.fadeColor.g, viaMemory(kColor.g));
  EXPECT_EQ(s.finish.ambient.r, viaMemory(0.13));
  EXPECT_EQ(s.finish.diffuse, viaMemory(0.61));
  EXPECT_EQ(s.finish.phong, viaMemory(0.33));
  EXPECT_EQ(s.finish.reflection.max.b, viaMemory(0.03));
  EXPECT_EQ(table[0].color.rgb.r, viaMemory(kColor.r));
  EXPECT_EQ(table[0].color.filter, viaMemory(0.37));
  EXPECT_EQ(table[0].color.transmit, viaMemory(0.11));
}

TEST(Single, LightColourIsRounded) {
  LightDesc d;
  d.color = kColor;
  const Light l = buildLight(d);
  EXPECT_EQ(l.color.r, viaMemory(kColor.r));
  EXPECT_EQ(l.color.g, viaMemory(kColor.g));
  EXPECT_EQ(l.color.b, viaMemory(kColor.b));
}

}  // namespace
}  // namespace pvrt
