// The same scene and settings give the same image bit for bit, whatever the backend,
// thread count or work decomposition.
#include <gtest/gtest.h>

#include <tuple>
#include <utility>

#include "test_scenes.h"

namespace pvrt {
namespace {

const char* kScene = R"(<scene>
  <camera location="0 3 -8" look_at="0 1 0" right="1.6 0 0"/>
  <light_source location="-5 8 -5" color="0.8 0.8 0.8"/>
  <light_source location="5 6 -3" color="0.4 0.4 0.5">
    <area_light axis1="1 0 0" axis2="0 0 1" size1="3" size2="3"/>
  </light_source>
  <plane normal="0 1 0" distance="0">
    <pigment><checker color1="0.9 0.9 0.9" color2="0.2 0.3 0.6"/></pigment>
    <finish reflection="0.2"/>
  </plane>
  <sphere center="-1.5 1 0" radius="1"><pigment color="0.8 0.2 0.1"/><finish phong="0.8"/></sphere>
  <sphere center="1.2 0.8 -1" radius="0.8"><pigment color="1 1 1" filter="0.9"/>
    <finish reflection="0.1" ambient="0" diffuse="0.1"/><interior ior="1.5"/></sphere>
</scene>)";

RenderResult renderWith(Backend b, int threads, Strategy st, int chunk = 0, int tile = 8) {
  RenderSettings s = test::settings(48, 30, b, threads);
  s.sampler = {SamplerKind::Jitter, 4, 3};
  s.schedule = {st, chunk, tile};
  return test::renderXml(kScene, s);
}

TEST(Determinism, EveryBackendThreadCountAndStrategyGivesTheSameImage) {
  const RenderResult ref = renderWith(Backend::Serial, 1, Strategy::Tiles);
  ASSERT_GT(ref.totals.refractedRays, 0u);
  for (int threads : {1, 2, 3}) {
    for (Strategy st : {Strategy::Block, Strategy::Cyclic, Strategy::Static, Strategy::Dynamic,
                        Strategy::Guided, Strategy::Tiles}) {
      const RenderResult r = renderWith(Backend::OpenMP, threads, st, st == Strategy::Dynamic ? 3 : 0);
      EXPECT_EQ(r.image.data(), ref.image.data()) << strategyName(st) << " with " << threads << " threads";
      EXPECT_EQ(r.totals.totalRays(), ref.totals.totalRays());
      EXPECT_EQ(r.totals.intersectionTests, ref.totals.intersectionTests);
    }
  }
}

TEST(Determinism, LoadMapIsTheSameOnEveryBackend) {
  RenderSettings a = test::settings(32, 20, Backend::Serial, 1);
  a.loadMap = true;
  RenderSettings b = a;
  b.backend = Backend::OpenMP;
  b.threads = 2;
  b.schedule.strategy = Strategy::Cyclic;
  const RenderResult ra = test::renderXml(kScene, a), rb = test::renderXml(kScene, b);
  EXPECT_EQ(ra.load, rb.load);
  double sum = 0;
  for (float v : ra.load) sum += v;
  EXPECT_EQ(uint64_t(sum), ra.totals.work());
}

// Neighbouring pixels of a row share a packet unless a load map asks for each pixel's own
// work, or the work item splits their group (tiles of an odd size): the image must not tell.
TEST(Determinism, PixelsSharingAPacketGiveTheImageOfPixelsTracedAlone) {
  auto renderWithSampler = [](SamplerKind kind, int samples, Strategy st, int tile, bool loadMap) {
    RenderSettings s = test::settings(37, 23, Backend::OpenMP, 2);
    s.sampler = {kind, samples, 5};
    s.schedule = {st, 0, tile};
    s.loadMap = loadMap;
    return test::renderXml(kScene, s);
  };
  // 4 to 37 rays a pixel: groups of 8, 4 and 2 pixels, and pixels that no group fits.
  for (const auto& [kind, samples] : {std::pair{SamplerKind::Pov, 4}, std::pair{SamplerKind::Pov, 9},
                                      std::pair{SamplerKind::Pov, 16}, std::pair{SamplerKind::Pov, 36},
                                      std::pair{SamplerKind::Jitter, 4}}) {
    const RenderResult alone = renderWithSampler(kind, samples, Strategy::Tiles, 8, true);
    ASSERT_GT(alone.totals.refractedRays, 0u);
    for (const auto& [st, tile] : {std::pair{Strategy::Tiles, 8}, std::pair{Strategy::Tiles, 7},
                                   std::pair{Strategy::Cyclic, 8}}) {
      const RenderResult r = renderWithSampler(kind, samples, st, tile, false);
      EXPECT_EQ(r.image.data(), alone.image.data()) << "c=" << samples << " " << strategyName(st) << " " << tile;
      EXPECT_EQ(r.totals.totalRays(), alone.totals.totalRays());
      EXPECT_EQ(r.totals.shadingOps, alone.totals.shadingOps);
    }
  }
}

// POV-Ray's adaptive antialiasing decides per block in a fixed order, so blocks may go to
// any thread in any grouping: rows become bands of blocks, tiles are rounded up to whole
// blocks, and image and ray counts stay the same.
TEST(Determinism, AdaptiveAntialiasingGivesTheSameImageWhateverTheSchedule) {
  for (int method : {1, 2}) {
    auto renderAdaptive = [&](Backend b, int threads, Strategy st, int chunk, int tile) {
      RenderSettings s = test::settings(70, 45, b, threads);  // 16-pixel blocks, the last ones partial
      s.sampler = {SamplerKind::Pov, 9, 0, {0.3, method, 16}};
      s.schedule = {st, chunk, tile};
      return test::renderXml(kScene, s);
    };
    const RenderResult ref = renderAdaptive(Backend::Serial, 1, Strategy::Tiles, 0, 16);
    const RenderResult full = test::renderXml(kScene, [] {
      RenderSettings s = test::settings(70, 45);
      s.sampler = {SamplerKind::Pov, 9, 0};
      return s;
    }());
    ASSERT_GT(ref.totals.refractedRays, 0u);
    // Fewer camera rays than supersampling everything (method 1: 10 a pixel; method 2 at
    // +A0.0: 25 lattice points), yet some pixels were supersampled.
    EXPECT_LT(ref.totals.primaryRays, uint64_t(70 * 45 * (method == 1 ? 10 : 25)));
    EXPECT_GT(ref.totals.primaryRays, uint64_t(71 * 46));
    EXPECT_NE(ref.image.data(), full.image.data());
    for (int threads : {1, 2, 3})
      for (const auto& [st, chunk, tile] :
           {std::tuple{Strategy::Block, 0, 16}, std::tuple{Strategy::Cyclic, 0, 16},
            std::tuple{Strategy::Static, 0, 16}, std::tuple{Strategy::Dynamic, 2, 16},
            std::tuple{Strategy::Guided, 0, 16}, std::tuple{Strategy::Tiles, 0, 7},
            std::tuple{Strategy::Tiles, 0, 40}}) {
        const RenderResult r = renderAdaptive(Backend::OpenMP, threads, st, chunk, tile);
        EXPECT_EQ(r.image.data(), ref.image.data())
            << "method " << method << " " << strategyName(st) << " tile " << tile << " with " << threads << " threads";
        EXPECT_EQ(r.totals.totalRays(), ref.totals.totalRays());
      }
  }
}

}  // namespace
}  // namespace pvrt
