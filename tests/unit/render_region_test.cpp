// The render region (POV-Ray's +SC/+EC/+SR/+ER): how its bounds are read, and that its pixels
// are those of the whole image.
#include "render/render_region.h"

#include <gtest/gtest.h>

#include "core/error.h"
#include "test_scenes.h"

namespace pvrt {
namespace {

void expectRect(const WorkItem& r, int x0, int y0, int x1, int y1) {
  EXPECT_EQ(r.x0, x0);
  EXPECT_EQ(r.y0, y0);
  EXPECT_EQ(r.x1, x1);
  EXPECT_EQ(r.y1, y1);
}

TEST(RenderRegion, PixelNumbersCountFromOneAndIncludeTheEnd) {
  expectRect(parseRegion({"3", "10", "11", "20"}, 64, 40), 2, 10, 10, 20);
  expectRect(parseRegion({"1", "64", "1", "40"}, 64, 40), 0, 0, 64, 40);
}

TEST(RenderRegion, SharesAreReadAsPovRay37ReadsThem) {
  // povray +W64 +H40 +SC0.25 +EC0.5 renders columns 16 to 31 (counted from 0).
  expectRect(parseRegion({"0.25", "0.5", "", ""}, 64, 40), 16, 0, 32, 40);
  expectRect(parseRegion({"0.0", "1.0", "0.5", "1.0"}, 64, 40), 0, 20, 64, 40);
}

TEST(RenderRegion, MissingBoundsAreTheImagesEdges) {
  expectRect(parseRegion({"", "", "5", ""}, 64, 40), 0, 4, 64, 40);
  EXPECT_FALSE(RegionBounds{}.any());
}

TEST(RenderRegion, RefusesWhatIsNotARegionOfTheImage) {
  const std::vector<std::pair<RegionBounds, std::string>> bad = {
      {{"0", "", "", ""}, "--start-col 0: pixel numbers run from 1 to 64"},
      {{"", "65", "", ""}, "--end-col 65: pixel numbers run from 1 to 64"},
      {{"", "", "1.5", ""}, "--start-row 1.5: a share of the image must lie from 0.0 to 1.0"},
      {{"", "", "", "ten"}, "--end-row ten: expected a pixel number"},
      {{"", "", "", "3x"}, "--end-row 3x: expected a pixel number"},
      // Decimal digits only, as every number pvrt reads (strtol took " 2" and "+2" as 2).
      {{" 2", "", "", ""}, "--start-col  2: expected a pixel number"},
      {{"+2", "", "", ""}, "--start-col +2: expected a pixel number"},
      {{"", "", "0x0.8p0", ""}, "--start-row 0x0.8p0: expected a pixel number"},
      {{"", "", " 0.5", ""}, "--start-row  0.5: expected a pixel number"},
      {{"10", "5", "", ""}, "columns 10 to 5 hold no pixel"},
      {{"", "", "0.5", "0.5"}, "rows 21 to 20 hold no pixel"},
  };
  for (const auto& [bounds, message] : bad) {
    try {
      parseRegion(bounds, 64, 40);
      ADD_FAILURE() << "accepted " << message;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ExitCode::Usage);
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  }
}

// A scene with every kind of ray, so that a region whose pixels differed anywhere would show.
const char* kScene = R"(<scene>
  <camera location="0 1 -4" look_at="0 0.5 0"/>
  <light_source location="-3 5 -3" color="1 1 1"/>
  <plane normal="0 1 0" distance="0"><pigment color="0.8 0.8 0.8"/><finish reflection="0.3"/></plane>
  <sphere center="0 0.7 0" radius="0.7"><pigment color="1 1 1" filter="0.8"/><interior ior="1.5"/></sphere>
  <sphere center="1.2 0.4 0.5" radius="0.4"><pigment color="1 0.2 0.1"/><finish phong="0.8"/></sphere>
</scene>)";

TEST(RenderRegion, PixelsAreTheWholeImagesOnEveryBackend) {
  const Scene scene = buildScene(loadSceneString(kScene, "region.xml"));
  RenderSettings whole = test::settings(45, 30);
  whole.sampler.samplesPerPixel = 4;
  const Image full = render(scene, whole).image;
  const WorkItem r{7, 5, 38, 23};
  for (Backend b : {Backend::Serial, Backend::OpenMP})
    for (Strategy st : {Strategy::Tiles, Strategy::Cyclic, Strategy::Block, Strategy::Dynamic}) {
      RenderSettings s = whole;
      s.backend = b;
      s.threads = 3;
      s.schedule.strategy = st;
      s.schedule.tileSize = 8;
      s.region = r;
      const RenderResult part = render(scene, s);
      ASSERT_EQ(part.image.width(), r.x1 - r.x0);
      ASSERT_EQ(part.image.height(), r.y1 - r.y0);
      long pixels = 0;
      for (const WorkerStats& w : part.workers) pixels += w.pixels;
      EXPECT_EQ(pixels, r.pixels());
      for (int y = r.y0; y < r.y1; ++y)
        for (int x = r.x0; x < r.x1; ++x)
          for (int c = 0; c < 3; ++c)
            ASSERT_EQ(part.image.row(y - r.y0)[(x - r.x0) * 3 + c], full.row(y)[x * 3 + c]) << x << "," << y;
    }
}

TEST(RenderRegion, LoadMapIsCutToTheRegion) {
  const Scene scene = buildScene(loadSceneString(kScene, "region.xml"));
  RenderSettings s = test::settings(20, 10);
  s.loadMap = true;
  const RenderResult full = render(scene, s);
  s.region = WorkItem{3, 2, 9, 7};
  const RenderResult part = render(scene, s);
  ASSERT_EQ(part.load.size(), size_t(6 * 5));
  for (int y = 2; y < 7; ++y)
    for (int x = 3; x < 9; ++x) EXPECT_EQ(part.load[size_t((y - 2) * 6 + x - 3)], full.load[size_t(y * 20 + x)]);
}

TEST(RenderRegion, ARegionOutsideTheImageIsRefused) {
  const Scene scene = buildScene(loadSceneString(kScene, "region.xml"));
  RenderSettings s = test::settings(20, 10);
  s.region = WorkItem{3, 2, 21, 7};
  EXPECT_THROW(render(scene, s), Error);
}

}  // namespace
}  // namespace pvrt
