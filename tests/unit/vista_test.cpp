// The vista (render/vista.h): the pixels it calls clear meet nothing, and skipping them
// changes neither the image nor what any schedule counts.
#include "render/vista.h"

#include <gtest/gtest.h>

#include <random>
#include <string>

#include "render/camera_grid.h"
#include "test_scenes.h"

namespace pvrt {
namespace {

// Spheres and a box in a cluster, mostly sky around them, a floor plane when asked, seen
// from a camera placed at random around them.
std::string clusterScene(std::mt19937& rng, bool floor) {
  std::uniform_real_distribution<double> u(-1, 1);
  const auto num = [](double v) { return std::to_string(v); };
  std::string xml = "<scene>\n  <camera location=\"" + num(6 * u(rng)) + " " + num(3 + 3 * u(rng)) + " " +
                    num(-9 + 2 * u(rng)) + "\" look_at=\"" + num(u(rng)) + " " + num(1 + u(rng)) + " 0\" right=\"" +
                    num(1.2 + 0.5 * u(rng)) + " 0 0\"/>\n";
  xml += "  <light_source location=\"-5 8 -5\" color=\"1 1 1\"/>\n";
  if (floor) xml += "  <plane normal=\"0 1 0\" distance=\"0\"><pigment color=\"0.5 0.5 0.5\"/></plane>\n";
  for (int i = 0; i < 12; ++i)
    xml += "  <sphere center=\"" + num(3 * u(rng)) + " " + num(1.5 + u(rng)) + " " + num(3 * u(rng)) + "\" radius=\"" +
           num(0.15 + 0.3 * (u(rng) + 1)) + "\"><pigment color=\"0.8 0.3 0.2\"/></sphere>\n";
  xml +=
      "  <box corner1=\"-0.5 0 -0.5\" corner2=\"0.5 0.7 0.5\"><pigment color=\"0.2 0.6 0.3\"/>"
      "<rotate v=\"0 30 10\"/></box>\n";
  return xml + "</scene>";
}

// Every pixel that the mask of the whole image calls clear: each of its samples' rays meets nothing.
// Returns how many pixels were clear.
int checkClearPixelsMeetNothing(const Scene& scene, int w, int h, const std::vector<SubSample>& offsets,
                                const WorkItem& rect) {
  const VistaMask mask(scene.vista, scene.bvh, rect, w, h, offsets);
  int clear = 0;
  uint64_t tests = 0;
  for (int y = rect.y0; y < rect.y1; ++y)
    for (int x = rect.x0; x < rect.x1; ++x) {
      if (!mask.clear(x, y)) continue;
      ++clear;
      for (const SubSample& s : offsets) {
        const Ray ray = scene.camera.ray(x, y, s.dx, s.dy, w, h);
        EXPECT_FALSE(scene.bvh.closest(ray, scene.tol.primaryMinDepth, scene.tol.maxDistance, tests))
            << "pixel " << x << ", " << y;
      }
    }
  return clear;
}

std::vector<SubSample> povOffsets(int samples) {
  SamplerSettings s;
  s.kind = SamplerKind::Pov;
  s.samplesPerPixel = samples;
  std::vector<SubSample> offsets;
  PixelSampler(s).offsets(0, 0, offsets);
  return offsets;
}

TEST(Vista, ClearPixelsMeetNothing) {
  std::mt19937 rng(7);
  int clearSeen = 0, mayHitSeen = 0;
  for (int trial = 0; trial < 24; ++trial) {
    const bool floor = trial % 2 == 1;
    const Scene scene = buildScene(loadSceneString(clusterScene(rng, floor), "cluster.xml"));
    ASSERT_TRUE(scene.vista.usable()) << trial;
    const int w = 64, h = 40;
    for (int samples : {1, 9}) {
      const std::vector<SubSample> offsets = povOffsets(samples);
      // The whole image, a tile and a row: each pixel's answer is the same in any of them.
      const int whole = checkClearPixelsMeetNothing(scene, w, h, offsets, {0, 0, w, h});
      checkClearPixelsMeetNothing(scene, w, h, offsets, {8, 8, 24, 24});
      checkClearPixelsMeetNothing(scene, w, h, offsets, {0, 17, w, 18});
      clearSeen += whole;
      mayHitSeen += w * h - whole;
    }
  }
  // The property is not vacuous: many pixels are clear, and many are not.
  EXPECT_GT(clearSeen, 10000);
  EXPECT_GT(mayHitSeen, 10000);
}

TEST(Vista, APixelIsClearOrNotWhateverItsWorkItem) {
  std::mt19937 rng(11);
  const Scene scene = buildScene(loadSceneString(clusterScene(rng, true), "cluster.xml"));
  const int w = 80, h = 50;
  const std::vector<SubSample> offsets = povOffsets(9);
  const VistaMask whole(scene.vista, scene.bvh, {0, 0, w, h}, w, h, offsets);
  ASSERT_TRUE(whole.any());
  for (const WorkItem& item : {WorkItem{0, 0, 32, 32}, WorkItem{32, 32, 64, 50}, WorkItem{0, 13, w, 14},
                               WorkItem{7, 3, 21, 40}, WorkItem{79, 0, 80, 50}}) {
    const VistaMask part(scene.vista, scene.bvh, item, w, h, offsets);
    for (int y = item.y0; y < item.y1; ++y)
      for (int x = item.x0; x < item.x1; ++x) EXPECT_EQ(part.clear(x, y), whole.clear(x, y)) << x << ", " << y;
  }
}

TEST(Vista, NotUsedWhereABoxLiesAcrossTheCameraPlaneOrTheCameraIsOnAPlane) {
  const std::string light = "<light_source location=\"0 5 -5\" color=\"1 1 1\"/>";
  const Scene across = buildScene(loadSceneString(
      "<scene><camera location=\"0 1 0\" look_at=\"0 1 1\"/>" + light +
          "<sphere center=\"0 1 5\" radius=\"1\"/><sphere center=\"3 1 0\" radius=\"1\"/></scene>",
      "across.xml"));
  EXPECT_FALSE(across.vista.usable());
  // A sphere wholly behind the camera: no camera ray can meet it, so it leaves the vista on.
  const Scene behind = buildScene(loadSceneString(
      "<scene><camera location=\"0 1 0\" look_at=\"0 1 1\"/>" + light +
          "<sphere center=\"0 1 5\" radius=\"1\"/><sphere center=\"0 1 -5\" radius=\"1\"/></scene>",
      "behind.xml"));
  ASSERT_TRUE(behind.vista.usable());
  EXPECT_GT(checkClearPixelsMeetNothing(behind, 40, 30, povOffsets(9), {0, 0, 40, 30}), 600);
  const Scene onPlane = buildScene(
      loadSceneString("<scene><camera location=\"0 0 -5\" look_at=\"0 0 0\"/>" + light +
                          "<plane normal=\"0 1 0\" distance=\"0\"/><sphere center=\"0 1 5\" radius=\"1\"/></scene>",
                      "on_plane.xml"));
  EXPECT_FALSE(onPlane.vista.usable());
  const Scene inFront = buildScene(
      loadSceneString("<scene><camera location=\"0 1 -5\" look_at=\"0 1 0\"/>" + light +
                          "<plane normal=\"0 1 0\" distance=\"0\"/><sphere center=\"0 1 5\" radius=\"1\"/></scene>",
                      "in_front.xml"));
  EXPECT_TRUE(inFront.vista.usable());
}

// The image and the counts of rays and shading are those of a render without the vista
// (the intersection tests fewer); every schedule skips the same rays.
TEST(Vista, SkipsRaysWithoutChangingTheImage) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 4; ++trial) {
    const std::string xml = clusterScene(rng, trial % 2 == 0);
    const Scene with = buildScene(loadSceneString(xml, "cluster.xml"));
    Scene without = buildScene(loadSceneString(xml, "cluster.xml"));
    without.vista = Vista();
    for (int samples : {1, 4, 9, 16}) {
      RenderSettings s = test::settings(61, 37);
      s.sampler = {SamplerKind::Pov, samples, 0};
      const RenderResult a = render(with, s), b = render(without, s);
      EXPECT_EQ(a.image.data(), b.image.data()) << trial << " spp " << samples;
      EXPECT_GT(a.totals.vistaRays, 0u);
      EXPECT_EQ(b.totals.vistaRays, 0u);
      EXPECT_EQ(a.totals.primaryRays, b.totals.primaryRays);
      EXPECT_EQ(a.totals.shadowRays, b.totals.shadowRays);
      EXPECT_EQ(a.totals.shadingOps, b.totals.shadingOps);
      EXPECT_LE(a.totals.intersectionTests, b.totals.intersectionTests);
      for (const auto& [st, tile, threads] :
           {std::tuple{Strategy::Tiles, 7, 2}, std::tuple{Strategy::Cyclic, 8, 2}, std::tuple{Strategy::Block, 8, 3}}) {
        RenderSettings p = s;
        p.backend = Backend::OpenMP;
        p.threads = threads;
        p.schedule = {st, 0, tile};
        const RenderResult c = render(with, p);
        EXPECT_EQ(c.image.data(), a.image.data()) << strategyName(st);
        EXPECT_EQ(c.totals.vistaRays, a.totals.vistaRays) << strategyName(st);
        // A tile of 7 splits groups of pixels that share a packet, whose tests count otherwise.
        if (tile % 8 == 0) {
          EXPECT_EQ(c.totals.intersectionTests, a.totals.intersectionTests) << strategyName(st);
        }
      }
      RenderSettings m = s;
      m.loadMap = true;
      EXPECT_EQ(render(with, m).image.data(), a.image.data());
    }
  }
}

}  // namespace
}  // namespace pvrt
