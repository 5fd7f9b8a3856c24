// POV-Ray's adaptive antialiasing through the renderer (render/adaptive_kernel.h): what a
// real scene's image must be, whatever the decisions were.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "test_scenes.h"

namespace pvrt {
namespace {

const char* kScene = R"(<scene>
  <camera location="0 2 -6" look_at="0 0.8 0" right="1.6 0 0"/>
  <light_source location="-4 6 -5" color="1 1 1"/>
  <plane normal="0 1 0" distance="0"><pigment><checker color1="1 1 1" color2="0.1 0.1 0.1"/></pigment></plane>
  <sphere center="0 1 0" radius="1"><pigment color="0.8 0.3 0.1"/><finish phong="0.6"/></sphere>
</scene>)";

RenderResult renderWith(SamplerSettings sampler) {
  RenderSettings s = test::settings(80, 50, Backend::OpenMP, 2);
  s.sampler = sampler;
  return test::renderXml(kScene, s);
}

// A method 1 pixel is either its centre ray alone (POV-Ray's -A) or the centre plus the
// grid (+A0.0), bit for bit: the same rays, summed the same way.
TEST(AdaptiveRender, Method1PixelsAreEitherTheCentreOrTheFullSupersample) {
  const RenderResult centre = renderWith({SamplerKind::Pov, 1, 0});
  const RenderResult full = renderWith({SamplerKind::Pov, 9, 0});
  const RenderResult adaptive = renderWith({SamplerKind::Pov, 9, 0, {0.3, 1, 32}});
  long fromCentre = 0, fromFull = 0, neither = 0;
  for (int y = 0; y < 50; ++y)
    for (int x = 0; x < 80; ++x) {
      const float *a = adaptive.image.row(y) + 3 * x, *c = centre.image.row(y) + 3 * x, *f = full.image.row(y) + 3 * x;
      const bool isCentre = a[0] == c[0] && a[1] == c[1] && a[2] == c[2];
      const bool isFull = a[0] == f[0] && a[1] == f[1] && a[2] == f[2];
      fromCentre += isCentre && !isFull;
      fromFull += isFull && !isCentre;
      neither += !isCentre && !isFull;
    }
  EXPECT_EQ(neither, 0);
  EXPECT_GT(fromCentre, 0);  // the flat parts were left alone
  EXPECT_GT(fromFull, 0);    // the edges were supersampled
  // The camera rays: every pixel's centre, each block's frame (row above, column left),
  // and 9 more for each supersampled pixel.
  const uint64_t frames = 2 * 80 + 3 * 50;  // 2 block rows, 3 block columns of 32 pixels
  EXPECT_EQ((adaptive.totals.primaryRays - 80 * 50 - frames) % 9, 0u);
  EXPECT_GE((adaptive.totals.primaryRays - 80 * 50 - frames) / 9, uint64_t(fromFull));
}

// Threshold 0 makes method 1 the plain pov sampler (every pixel supersampled once); a higher
// threshold supersamples fewer pixels.
TEST(AdaptiveRender, ThresholdsAtTheEndsOfTheRange) {
  const RenderResult full = renderWith({SamplerKind::Pov, 9, 0});
  EXPECT_EQ(renderWith({SamplerKind::Pov, 9, 0, {0.0, 1, 32}}).image.data(), full.image.data());
  const RenderResult lax = renderWith({SamplerKind::Pov, 9, 0, {1.0, 1, 32}});
  const RenderResult strict = renderWith({SamplerKind::Pov, 9, 0, {0.05, 1, 32}});
  EXPECT_LT(lax.totals.primaryRays, strict.totals.primaryRays);
}

// --pov-blocks: threshold 0 traced through the method-1 kernel, so every pixel is the full
// supersample, found block by block: the frames' centre rays are traced besides, and the image
// does not depend on the threads (this scene has no crease where the shadow cache decides).
TEST(AdaptiveRender, PovBlocksTracesEveryPixelFullyInBlocks) {
  SamplerSettings blocks{SamplerKind::Pov, 9, 0, {0.0, 1, 32}};
  blocks.adaptive.blocks = true;
  const RenderResult r = renderWith(blocks);
  const uint64_t frames = 2 * 80 + 3 * 50;
  EXPECT_EQ(r.totals.primaryRays, 80 * 50 * 10 + frames);
  EXPECT_EQ(r.image.data(), renderWith({SamplerKind::Pov, 9, 0}).image.data());
  RenderSettings one = test::settings(80, 50, Backend::Serial, 1);
  one.sampler = blocks;
  EXPECT_EQ(test::renderXml(kScene, one).image.data(), r.image.data());
}

// --pov-blocks at one ray a pixel (POV-Ray's -A): whole blocks to a work item, each traced in
// POV-Ray's order with the shadow cache kept from pixel to pixel; one ray a pixel still, and
// the same bits on one thread and on two threads with rows dealt as bands. In this scene no
// shadow rests on the cache's smaller depths, so the image is the plain -A's too.
TEST(AdaptiveRender, PovBlocksAtOneRayAPixelKeepsTheCacheWithinBlocks) {
  SamplerSettings blocks{SamplerKind::Pov, 1, 0, {0.0, 1, 32}};
  blocks.adaptive.blocks = true;
  const PixelSampler sampler(blocks);
  EXPECT_FALSE(sampler.adaptive());
  EXPECT_TRUE(sampler.blockCache());
  EXPECT_EQ(sampler.blockGranule(), 32);
  EXPECT_FALSE(PixelSampler(SamplerSettings{SamplerKind::Pov, 1, 0}).blockCache());
  const RenderResult r = renderWith(blocks);
  EXPECT_EQ(r.totals.primaryRays, 80u * 50u);
  EXPECT_EQ(r.image.data(), renderWith({SamplerKind::Pov, 1, 0}).image.data());
  RenderSettings one = test::settings(80, 50, Backend::Serial, 1);
  one.sampler = blocks;
  RenderSettings cyclic = test::settings(80, 50, Backend::OpenMP, 2);
  cyclic.sampler = blocks;
  cyclic.schedule.strategy = Strategy::Cyclic;
  EXPECT_EQ(test::renderXml(kScene, one).image.data(), r.image.data());
  EXPECT_EQ(test::renderXml(kScene, cyclic).image.data(), r.image.data());
}

// A negative light on the floor, reflected with exponent 2 by the sphere: blue below 0
// raised to 1/2, so NaN in POV-Ray as in pvrt (blind8's scene 09f).
const char* kNaNScene = R"(<scene>
  <camera location="0 2 -6" look_at="0 1 0" angle="55" right="1.6 0 0"/>
  <light_source location="-3 6 -4" color="1 0.95 0.9"/>
  <light_source location="3 3 -4" color="-0.2 -0.1 -0.3"/>
  <sphere center="1.6 1 0" radius="0.9"><pigment color="0.2 0.4 0.9"/>
    <finish ambient="0" diffuse="0.4"><reflection min="0.8" exponent="2"/></finish></sphere>
  <plane normal="0 1 0"><pigment color="0.9"/></plane>
</scene>)";

bool sameBits(const Image& a, const Image& b) {
  return a.data().size() == b.data().size() &&
         std::memcmp(a.data().data(), b.data().data(), a.data().size() * sizeof(float)) == 0;
}

// POV-Ray's +A0.0 supersamples a pixel when its colour differs from its left or top
// neighbour's by at least 0, and a NaN colour fails that comparison: such a pixel keeps its
// centre ray. The plain pov sampler, which supersamples every pixel, traced it with all ten
// (09f: 52 channels over POV-Ray's by up to 47 levels); a render that meets a NaN sample is
// now traced again as --pov-blocks, which makes POV-Ray's decisions (09f: 0 channels differ).
TEST(AdaptiveRender, APixelWhoseColourIsNaNKeepsItsCentreRay) {
  RenderSettings s = test::settings(160, 100, Backend::OpenMP, 2);
  s.sampler = {SamplerKind::Pov, 9, 0};
  const RenderResult plain = test::renderXml(kNaNScene, s);
  ASSERT_GT(plain.totals.nonFiniteSamples, 0u);
  s.sampler.adaptive.blocks = true;
  const RenderResult blocks = test::renderXml(kNaNScene, s);
  EXPECT_TRUE(sameBits(plain.image, blocks.image));
  // Fewer camera rays than every pixel supersampled: the centre, the 9 more of each pixel
  // supersampled, and the frames of its 32-pixel blocks (a row above and a column left each:
  // 4 block rows of 160, 5 block columns of 100).
  const uint64_t everyPixel = 160 * 100 * 10 + 4 * 160 + 5 * 100;
  EXPECT_LT(plain.totals.primaryRays, everyPixel);
  EXPECT_EQ((everyPixel - plain.totals.primaryRays) % 9, 0u);
  // Every sample finite: the plain sampler stays as it was, a single render.
  RenderSettings f = test::settings(80, 50, Backend::OpenMP, 2);
  f.sampler = {SamplerKind::Pov, 9, 0};
  EXPECT_EQ(test::renderXml(kScene, f).totals.primaryRays, 80u * 50u * 10u);
}

// Method 2 at +A0.0 subdivides every pixel fully: POV-Ray's +R3 is a 5 x 5 lattice from
// corner to corner, its points weighted 1, 2, 2, 2, 1 along each axis (the trapezoid rule).
TEST(AdaptiveRender, Method2AtThresholdZeroTracesTheWholeLattice) {
  const RenderResult r = renderWith({SamplerKind::Pov, 9, 0, {0.0, 2, 32}});
  // Corners of each 32-pixel block (its pixels' and one row and column more), then 21 more
  // lattice points a pixel.
  const uint64_t corners = (32 + 1) * (32 + 1) * 2 + (16 + 1) * (32 + 1) + (32 + 1) * (18 + 1) * 2 + (16 + 1) * (18 + 1);
  EXPECT_EQ(r.totals.primaryRays, corners + 80 * 50 * 21);
}

}  // namespace
}  // namespace pvrt
