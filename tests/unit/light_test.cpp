// Lights as built for the renderer (render/light.cpp) from the scene description.
#include <gtest/gtest.h>

#include "render/scene.h"
#include "scene/xml_loader.h"

namespace pvrt {
namespace {

Scene sceneWithLight(const char* light) {
  return buildScene(loadSceneString(std::string("<scene>") + light +
                                        "<plane normal=\"0 1 0\"><pigment color=\"1\"/></plane></scene>",
                                    "light.xml"));
}

// POV-Ray has no shadowless spotlight: `shadowless` and `spotlight` both set the light's
// type and the later wins, and the export writes `shadowless` last, so POV-Ray lights the
// whole floor with it as a point light (Attenuate_Light shapes only SPOT_SOURCE lights).
// Before, pvrt kept the cone: 97% of the channels of such a scene were off.
TEST(Light, AShadowlessSpotlightIsAShadowlessPointLightAsInPovRay) {
  const Scene s = sceneWithLight(
      "<light_source location=\"0 4 0\" shadowless=\"true\"><spotlight point_at=\"0 0 0\" radius=\"5\" "
      "falloff=\"10\" tightness=\"3\"/></light_source>");
  ASSERT_EQ(s.lights.size(), 1u);
  const Light& l = s.lights[0];
  EXPECT_TRUE(l.shadowless);
  EXPECT_FALSE(l.spot);
  // A point far outside the cone gets the light's full strength.
  EXPECT_EQ(l.attenuation(normalize(Vec3{0, 4, 0} - Vec3{3, 0, 0}), 5.0), 1.0);
}

TEST(Light, ASpotlightThatCastsShadowsKeepsItsCone) {
  const Scene s = sceneWithLight(
      "<light_source location=\"0 4 0\"><spotlight point_at=\"0 0 0\" radius=\"5\" falloff=\"10\"/></light_source>");
  const Light& l = s.lights[0];
  EXPECT_TRUE(l.spot);
  EXPECT_EQ(l.attenuation(normalize(Vec3{0, 4, 0} - Vec3{3, 0, 0}), 5.0), 0.0);
  EXPECT_EQ(l.attenuation(Vec3{0, 1, 0}, 4.0), 1.0);
}

// An area light's sample is its centre plus the sum of its two offsets, as
// ComputeOneWhiteLightRay forms it (Center + (axis1 u + axis2 v)), not the offsets added to
// the centre one by one: the two differ in the last bits, which decide a shadow segment that
// ends on a surface (a sample on a wall). Found by tools/difftest.py, seed 213.
TEST(Light, AnAreaLightSampleIsTheCentrePlusTheSumOfItsOffsets) {
  const Scene s = sceneWithLight(
      "<light_source location=\"0.1 0.7 0.3\"><area_light axis1=\"0.3 0.2 0.1\" axis2=\"0.1 0.6 0.7\" "
      "size1=\"3\" size2=\"5\"/></light_source>");
  const Light& l = s.lights[0];
  int apart = 0;
  for (int j = 0; j < 5; ++j)
    for (int i = 0; i < 3; ++i) {
      const double u = double(i) / 2 - 0.5, v = double(j) / 4 - 0.5;
      const Vec3 sum = l.location + (l.axis1 * u + l.axis2 * v);
      const Vec3 got = l.areaSample(i, j, Vec3(0.0));
      EXPECT_EQ(got.x, sum.x);
      EXPECT_EQ(got.y, sum.y);
      EXPECT_EQ(got.z, sum.z);
      const Vec3 oneByOne = l.location + l.axis1 * u + l.axis2 * v;
      apart += oneByOne.x != sum.x || oneByOne.y != sum.y || oneByOne.z != sum.z;
    }
  EXPECT_GT(apart, 0);  // the light tells the two apart
}

}  // namespace
}  // namespace pvrt
