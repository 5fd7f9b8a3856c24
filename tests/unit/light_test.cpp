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

}  // namespace
}  // namespace pvrt
