// A render in passes (the sequence sampler under a time budget): its image is one go's bit
// for bit, and the passes stop when the budget is spent.
#include "render/passes.h"

#include <gtest/gtest.h>

#include "core/error.h"
#include "test_scenes.h"

namespace pvrt {
namespace {

// A thin opaque wall on a floor with the light behind it, seen close up (its crease is where
// the shadow cache decides pixels: scenes/fidelity_crease.xml), a mirror floor and a glass
// sphere: every kind of ray.
const char* kScene = R"(<scene>
  <camera location="0.004 0.012 -0.03" look_at="0 0 0" right="1.6 0 0" angle="40"/>
  <light_source location="-1 3 8" color="1 1 1"/>
  <light_source location="-3 5 -3" color="0.5 0.5 0.5"/>
  <plane normal="0 1 0" distance="0"><pigment color="0.8 0.8 0.8"/><finish reflection="0.3"/></plane>
  <box corner1="-3 0 0" corner2="3 1.5 0.0002"><pigment color="0.9 0.6 0.3"/></box>
  <sphere center="-0.006 0.003 -0.004" radius="0.003"><pigment color="1 1 1" filter="0.8"/><interior ior="1.5"/></sphere>
  <sphere center="0.007 0.002 -0.002" radius="0.002"><pigment color="1 0.2 0.1"/><finish phong="0.8"/></sphere>
</scene>)";

RenderSettings sequence(int samples, int width = 37, int height = 23) {
  RenderSettings s = test::settings(width, height);
  s.sampler.kind = SamplerKind::Sequence;
  s.sampler.samplesPerPixel = samples;
  s.sampler.seed = 7;
  return s;
}

// Passes ending at `ends`, one after the other.
std::function<int(const PassesSoFar&)> passesEndingAt(std::vector<int> ends) {
  return [ends](const PassesSoFar& so) { return so.passes.size() < ends.size() ? ends[so.passes.size()] : so.done; };
}

void expectSameImage(const Image& a, const Image& b) {
  ASSERT_EQ(a.width(), b.width());
  ASSERT_EQ(a.height(), b.height());
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width() * 3; ++x) ASSERT_EQ(a.row(y)[x], b.row(y)[x]) << x / 3 << "," << y;
}

TEST(Passes, AnImageInPassesIsOneGosBitForBit) {
  const Scene scene = buildScene(loadSceneString(kScene, "passes.xml"));
  const std::vector<int> ends{1, 3, 4, 8, 64, 67, 70};  // whole passes, and shorter ones anywhere
  const RenderResult whole = render(scene, sequence(70, 120, 75));
  for (Backend b : {Backend::Serial, Backend::OpenMP})
    for (Strategy st : {Strategy::Tiles, Strategy::Cyclic, Strategy::Dynamic}) {
      RenderSettings s = sequence(1 << 16, 120, 75);
      s.backend = b;
      s.threads = b == Backend::Serial ? 1 : 3;
      s.schedule.strategy = st;
      s.schedule.tileSize = 8;
      s.nextPass = passesEndingAt(ends);
      const RenderResult parts = render(scene, s);
      ASSERT_EQ(parts.passes.size(), ends.size());
      EXPECT_EQ(parts.passes.back().last, 70);
      EXPECT_EQ(parts.totals.primaryRays, whole.totals.primaryRays);
      expectSameImage(parts.image, whole.image);
    }
}

TEST(Passes, SmallPassesAndALoadMapGiveTheSameImage) {
  // Passes of 1, 1, 2 samples trace single rays and packets of several pixels; a load map
  // traces every pixel alone; a region only some pixels.
  const Scene scene = buildScene(loadSceneString(kScene, "passes.xml"));
  for (int c : {1, 3, 5, 12}) {
    const RenderResult whole = render(scene, sequence(c));
    std::vector<int> ends;
    for (int k = 1; k < c; k = wholePassEnd(k)) ends.push_back(k);
    ends.push_back(c);
    RenderSettings s = sequence(c);
    s.nextPass = passesEndingAt(ends);
    expectSameImage(render(scene, s).image, whole.image);
    s.loadMap = true;
    expectSameImage(render(scene, s).image, whole.image);
    RenderSettings region = sequence(c);
    region.region = WorkItem{5, 3, 30, 19};
    const Image part = render(scene, region).image;
    region.nextPass = passesEndingAt(ends);
    expectSameImage(render(scene, region).image, part);
  }
}

TEST(Passes, OnlyTheSequenceSamplerGoesInPasses) {
  const Scene scene = buildScene(loadSceneString(kScene, "passes.xml"));
  RenderSettings pov = test::settings(8, 8);
  pov.sampler.samplesPerPixel = 4;
  pov.nextPass = passesEndingAt({1, 4});  // pov's, grid's and jitter's samples depend on c
  EXPECT_THROW(render(scene, pov), Error);
}

PassesSoFar after(std::vector<PassRecord> passes, double seconds) {
  PassesSoFar so;
  so.passes = std::move(passes);
  so.done = so.passes.empty() ? 0 : so.passes.back().last;
  so.seconds = seconds;
  return so;
}

TEST(Passes, PredictionFollowsTheLatestPassesOfDifferentSizes) {
  EXPECT_EQ(predictPassSeconds({}, 8), 0);
  // One size: in proportion.
  EXPECT_DOUBLE_EQ(predictPassSeconds({{0, 1, 0.5}, {1, 2, 0.4}}, 4), 1.6);
  // 2 samples 1.0 s, 4 samples 1.6 s: 0.4 s + 0.3 s a sample.
  EXPECT_DOUBLE_EQ(predictPassSeconds({{0, 1, 0.6}, {1, 2, 0.55}, {2, 4, 1.0}, {4, 8, 1.6}}, 8), 2.8);
  // A flat pair: the slope is kept at half the latest pass's cost per sample (0.2 s).
  EXPECT_NEAR(predictPassSeconds({{2, 4, 0.8}, {4, 8, 0.8}}, 8), 0.8 + 0.1 * 4, 1e-12);
}

TEST(Passes, WholePassesDoubleTheSamplesUpTo64) {
  EXPECT_EQ(wholePassEnd(0), 1);
  EXPECT_EQ(wholePassEnd(1), 2);
  EXPECT_EQ(wholePassEnd(3), 4);
  EXPECT_EQ(wholePassEnd(5), 8);
  EXPECT_EQ(wholePassEnd(32), 64);
  EXPECT_EQ(wholePassEnd(64), 128);
  EXPECT_EQ(wholePassEnd(100), 128);
}

TEST(Passes, FirstOneSampleThenWholePassesWhileTheyFit) {
  const PassBudget b{10, 1, 0.1, 1 << 16};
  EXPECT_EQ(nextPassEnd(b, after({}, 0)), 1);
  EXPECT_EQ(nextPassEnd(b, after({{0, 1, 0.5}}, 0.5)), 2);
  EXPECT_EQ(nextPassEnd(b, after({{0, 1, 0.5}, {1, 2, 0.5}}, 1.0)), 4);
  EXPECT_EQ(nextPassEnd(b, after({{0, 1, 0.1}, {1, 2, 0.1}, {2, 4, 0.2}, {4, 8, 0.4}, {8, 16, 0.8}, {16, 32, 1.6},
                                  {32, 64, 3.2}},
                                 6.4)),
            64 + 25);  // 2.5 s left at 0.1 s a sample (and no fixed part): 64 samples would not fit
}

TEST(Passes, TheLastPassEndsNearestTheBudget) {
  const PassBudget b{2, 0.4, 0.05, 1 << 16};
  // 0.6 s a sample, 0.95 s left: 1 sample ends 0.35 s under, 2 samples 0.25 s over (more than 10%).
  EXPECT_EQ(nextPassEnd(b, after({{0, 1, 0.6}}, 0.6)), 2);   // a whole pass of 1 fits
  EXPECT_EQ(nextPassEnd(b, after({{0, 1, 0.6}, {1, 2, 0.6}}, 1.2)), 2);  // 0.35 s left: 1 more is 0.25 over
  // 0.55 s left and a sample of 0.6 s: 0.05 s over (2.5% of the budget) is nearer than 0.55 under.
  EXPECT_EQ(nextPassEnd({2, 0.4, 0.05, 1 << 16}, after({{0, 1, 0.6}, {1, 2, 0.6}}, 1.0)), 3);
  // After a shorter pass, another while a sample still fits: 0.35 s left, 0.3 s a sample.
  EXPECT_EQ(nextPassEnd({2, 0.4, 0.05, 1 << 16}, after({{0, 1, 0.3}, {1, 2, 0.3}, {2, 3, 0.3}}, 1.2)), 4);
  // ... and none when the end is nearest without it: 0.1 s left, 0.3 s a sample.
  EXPECT_EQ(nextPassEnd({2, 0.4, 0.05, 1 << 16}, after({{0, 1, 0.3}, {1, 2, 0.3}, {2, 3, 0.3}}, 1.45)), 3);
  // The most samples the caller allows.
  EXPECT_EQ(nextPassEnd({1000, 0, 0, 4}, after({{0, 1, 0.01}, {1, 2, 0.01}, {2, 4, 0.02}}, 0.04)), 4);
}

}  // namespace
}  // namespace pvrt
