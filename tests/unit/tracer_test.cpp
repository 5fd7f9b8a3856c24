// The tracer's packet path (tracePacket: hits and shadows found a packet at a time, plain
// surfaces shaded four rays at a time) against its ray-by-ray path (trace).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "render/tracer.h"
#include "scene/xml_loader.h"

namespace pvrt {
namespace {

// Plain surfaces of several finishes (diffuse only, phong, specular, both, no diffuse),
// a checker, a mirror, glass, a light that casts no shadows and one too dark to count,
// planes seen from above, from below (a ceiling above the lights) and tilted: every branch
// of the four-lane set-up and shading and of their fallbacks.
const char* kScene = R"(<scene>
  <camera location="0 3 -8" look_at="0 1 0" right="1.6 0 0"/>
  <light_source location="-5 8 -5" color="0.7 0.7 0.7"/>
  <light_source location="4 6 -4" color="0.3 0.25 0.2"/>
  <light_source location="0 9 2" color="0.2 0.2 0.2" shadowless="true"/>
  <light_source location="2 5 -6" color="1e-11 1e-11 1e-11"/>
  <plane normal="0 1 0" distance="0">
    <pigment><checker color1="0.9 0.9 0.9" color2="0.2 0.3 0.6"/></pigment>
  </plane>
  <plane normal="0 1 0" distance="12"><pigment color="0.5 0.5 0.6"/><finish phong="0.4"/></plane>
  <plane normal="0.3 0.2 -0.93" distance="-5.2"><pigment color="0.6 0.5 0.4"/></plane>
  <sphere center="-2 1 0" radius="1"><pigment color="0.8 0.2 0.1"/><finish phong="0.8" phong_size="60"/></sphere>
  <sphere center="0 0.7 -1" radius="0.7"><pigment color="0.2 0.8 0.1"/><finish specular="0.6" roughness="0.02"/></sphere>
  <sphere center="2 1 0.5" radius="1"><pigment color="0.3 0.3 0.9"/><finish phong="0.5" specular="0.3" diffuse="0"/></sphere>
  <sphere center="-0.5 2.3 1" radius="0.6"><pigment color="0.9 0.9 0.9"/><finish reflection="0.6"/></sphere>
  <sphere center="1 0.5 -2.5" radius="0.5"><pigment color="1 1 1" filter="0.9"/><interior ior="1.5"/></sphere>
  <box corner1="-3.5 0 1.5" corner2="-2.5 1.2 2.5"><pigment color="0.7 0.6 0.2"/><finish diffuse="0.9"/></box>
</scene>)";

constexpr EffectSet kEffects = kShadows | kReflection | kTransmission | kHighlights | kTextures;

bool sameBits(const Color& a, const Color& b) {
  return std::memcmp(&a.r, &b.r, sizeof(double)) == 0 && std::memcmp(&a.g, &b.g, sizeof(double)) == 0 &&
         std::memcmp(&a.b, &b.b, sizeof(double)) == 0;
}

// Mirrors and glass over a checkered floor under three lights, one of them inside the
// glass: most packet rays spawn mirror and refracted rays whose hits (found and given their
// shadows ahead, Tracer::shadowsAhead) lie in the shadows of spheres, boxes and each other,
// so that POV-Ray's shadow cache, which shading applies to them, decides many tests.
const char* kMirrorScene = R"(<scene>
  <camera location="0 4 -9" look_at="0 1 0" right="1.6 0 0"/>
  <light_source location="-4 9 -6" color="0.8 0.8 0.8"/>
  <light_source location="5 5 -3" color="0.4 0.35 0.3"/>
  <light_source location="0.5 1 0" color="0.3 0.3 0.3"/>
  <plane normal="0 1 0" distance="0">
    <pigment><checker color1="0.9 0.9 0.9" color2="0.1 0.2 0.5"/></pigment><finish reflection="0.3"/>
  </plane>
  <plane normal="0 0 -1" distance="-6"><pigment color="0.6 0.6 0.5"/><finish reflection="0.5"/></plane>
  <sphere center="-1.5 1 0" radius="1"><pigment color="0.9 0.9 0.9"/><finish reflection="0.8" phong="0.5"/></sphere>
  <sphere center="0.5 1 0" radius="0.9"><pigment color="1 1 1" filter="0.8"/><interior ior="1.5"/></sphere>
  <sphere center="2.2 0.6 -1" radius="0.6"><pigment color="0.8 1 0.8" transmit="0.9"/><interior ior="1"/></sphere>
  <sphere center="-0.3 2.6 1.5" radius="0.5"><pigment color="0.8 0.3 0.2"/></sphere>
  <box corner1="1.5 0 1" corner2="3 2.5 2.5"><pigment color="0.7 0.7 0.8"/><finish reflection="0.6"/></box>
  <box corner1="-3.5 0 -2" corner2="-2.5 0.8 -1"><pigment color="0.7 0.6 0.2" filter="0.5"/></box>
</scene>)";

// Packets of every size, their rays in a cone about random directions toward the scene,
// each ray's colour and the counters held to trace()'s, bit for bit.
void expectPacketsMatchTraces(const char* xml, const Vec3& origin, int rounds) {
  const Scene scene = buildScene(loadSceneString(xml, "tracer.xml"));
  ASSERT_EQ(scene.effects & ~kEffects, 0u) << "the scene calls for effects the tracer below leaves out";
  RenderStats packetStats, aloneStats;
  Tracer<kEffects> packet(scene, packetStats), alone(scene, aloneStats);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> spread(-0.35, 0.35);
  std::vector<Ray> rays(kMaxPacket);
  std::vector<Color> colours(kMaxPacket);
  long rays4 = 0;
  for (int round = 0; round < rounds; ++round) {
    const int count = 1 + round % kMaxPacket;
    const Vec3 axis = normalize(Vec3{spread(rng) * 3, -0.35 + 3 * spread(rng), 1});
    const double width = round % 3 == 0 ? 0.002 : 0.05;
    for (int k = 0; k < count; ++k)
      rays[k] = Ray{origin, normalize(axis + Vec3{spread(rng) * width, spread(rng) * width, spread(rng) * width})};
    packet.beginPixel();
    packet.tracePacket(rays.data(), count, scene.cameraInteriors, colours.data());
    for (int k = 0; k < count; ++k) {
      alone.beginPixel();
      const Color c = alone.trace(rays[k], 0, 1.0, scene.cameraInteriors);
      ASSERT_TRUE(sameBits(colours[k], c)) << "round " << round << " ray " << k << ": " << colours[k].r << " "
                                           << colours[k].g << " " << colours[k].b << " against " << c.r << " "
                                           << c.g << " " << c.b;
    }
    rays4 += count / 4 * 4;
  }
  EXPECT_GT(rays4, 10000);
  EXPECT_EQ(packetStats.shadingOps, aloneStats.shadingOps);
  EXPECT_EQ(packetStats.shadowRays, aloneStats.shadowRays);
  EXPECT_EQ(packetStats.reflectedRays, aloneStats.reflectedRays);
  EXPECT_EQ(packetStats.refractedRays, aloneStats.refractedRays);
  EXPECT_GT(aloneStats.reflectedRays, 0u);
  EXPECT_GT(aloneStats.refractedRays, 0u);
}

TEST(Tracer, PacketShadingGivesEveryRayTheColourOfItsOwnTrace) {
  expectPacketsMatchTraces(kScene, {0, 3, -8}, 600);
}

TEST(Tracer, SpawnedHitsShadowedAheadGiveTheColourOfTheirOwnTrace) {
  expectPacketsMatchTraces(kMirrorScene, {0, 4, -9}, 600);
}

}  // namespace
}  // namespace pvrt
