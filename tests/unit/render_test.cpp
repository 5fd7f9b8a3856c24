// End-to-end renders through the library on small inline scenes with exact answers.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "generate/random_scene.h"
#include "parallel/threads.h"

#include "test_scenes.h"

namespace pvrt {
namespace {

using test::renderXml;
using test::settings;

// Camera at the centre of a closed sphere, lit by a point light at the same centre:
// every visible point faces the light head-on (N.L = 1) and nothing shadows it, so each
// pixel is ambient*C + diffuse*C*light exactly.
TEST(Render, CameraInsideLitSphereHasKnownBrightness) {
  const RenderResult r = renderXml(R"(<scene>
      <camera location="0 0 0" look_at="0 0 1"/>
      <light_source location="0 0 0" color="1 1 1"/>
      <sphere center="0 0 0" radius="10">
        <pigment color="0.5 0.25 1"/>
        <finish ambient="0.1" diffuse="0.6"/>
      </sphere></scene>)",
                                   settings(16, 12));
  for (int y = 0; y < 12; ++y)
    for (int x = 0; x < 16; ++x) {
      const float* p = r.image.row(y) + x * 3;
      EXPECT_NEAR(p[0], 0.5 * 0.7, 1e-6);
      EXPECT_NEAR(p[1], 0.25 * 0.7, 1e-6);
      EXPECT_NEAR(p[2], 1.0 * 0.7, 1e-6);
    }
  EXPECT_EQ(r.totals.primaryRays, 16u * 12u);
  EXPECT_EQ(r.totals.shadowRays, 16u * 12u);
  EXPECT_EQ(r.totals.reflectedRays, 0u);
}

TEST(Render, MissedRaysSeeTheBackground) {
  const RenderResult r = renderXml(R"(<scene><background color="0.2 0.4 0.6"/></scene>)", settings(4, 3));
  for (float v : {r.image.row(1)[0], r.image.row(1)[1], r.image.row(1)[2]}) EXPECT_GT(v, 0.0f);
  EXPECT_FLOAT_EQ(r.image.row(2)[9], 0.2f);
  EXPECT_FLOAT_EQ(r.image.row(2)[10], 0.4f);
  EXPECT_EQ(r.effects, 0u);
}

// A plane y=0 lit from straight above by a light at height h: the pixel looking straight
// down sees diffuse * 1 * colour (N.L = 1); the checker picks colour by cell.
// A sphere stretched 1e9 along x (legal since blind8's loader fix) fills the picture: its
// tolerances are those of its own space, where it has radius 1, not of its 2e9 world size
// (which made every ray miss it). The same with 1e8, which loaded before.
TEST(Render, SphereStretchedAlongOneAxisIsSeen) {
  for (const char* k : {"1e8", "1e9", "1e12"}) {
    const RenderResult r = renderXml(std::string(R"(<scene><camera location="0 0 -1.5"/>
      <sphere center="0 0 0" radius="1"><pigment color="1 1 1"/><finish ambient="1" diffuse="0"/>
      <scale v=")") + k + R"( 1 1"/></sphere></scene>)",
                                     settings(4, 3));
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < 4; ++x) EXPECT_FLOAT_EQ(r.image.row(y)[3 * x], 1.0f) << k << " at " << x << ", " << y;
  }
}

TEST(Render, PlaneUnderOverheadLightMatchesLambert) {
  const RenderResult r = renderXml(R"(<scene>
      <camera location="0.5 5 0.5" look_at="0.5 0 0.5" sky="0 0 1"/>
      <light_source location="0.5 10 0.5" color="1 1 1"/>
      <plane normal="0 1 0" distance="0">
        <pigment color="1 1 1"/>
        <finish ambient="0" diffuse="0.5"/>
      </plane></scene>)",
                                   settings(1, 1));
  EXPECT_NEAR(r.image.row(0)[0], 0.5, 1e-9);
}

// Two facing mirrors: the number of reflected rays per primary ray is bounded by the trace
// level: max_trace_level N allows the primary ray plus N-1 reflections.
TEST(Render, FacingMirrorsStopAtTheTraceLevel) {
  for (int level : {1, 3, 5}) {
    const RenderResult r = renderXml(R"(<scene>
        <global_settings max_trace_level=")" + std::to_string(level) + R"(" adc_bailout="0"/>
        <camera location="0 0 0" look_at="0 0 1"/>
        <plane normal="0 0 1" distance="5"><finish reflection="1" ambient="0" diffuse="0"/></plane>
        <plane normal="0 0 1" distance="-5"><finish reflection="1" ambient="0" diffuse="0"/></plane>
        </scene>)",
                                     settings(2, 2));
    EXPECT_EQ(r.totals.reflectedRays, 4u * uint64_t(level - 1)) << "max_trace_level " << level;
  }
}

TEST(Render, SceneWithoutMirrorsTracesNoReflectedRays) {
  const RenderResult r = renderXml(R"(<scene>
      <camera location="0 2 -5" look_at="0 0 0"/>
      <light_source location="5 5 -5"/>
      <plane normal="0 1 0" distance="-1"><pigment color="1 1 1"/></plane>
      <sphere center="0 0 0" radius="1"><pigment color="1 0 0"/><finish phong="0.5"/></sphere>
      </scene>)",
                                   settings(16, 12));
  EXPECT_EQ(r.totals.reflectedRays, 0u);
  EXPECT_EQ(r.totals.refractedRays, 0u);
  EXPECT_EQ(r.totals.transmittedRays, 0u);
  EXPECT_GT(r.totals.shadowRays, 0u);
  EXPECT_EQ(r.effects & kReflection, 0u);
  EXPECT_EQ(r.effects & kTransmission, 0u);
  EXPECT_NE(r.effects & kShadows, 0u);
  EXPECT_NE(r.effects & kHighlights, 0u);
}

TEST(Render, ShadowlessLightsTraceNoShadowRays) {
  const RenderResult r = renderXml(R"(<scene>
      <camera location="0 2 -5" look_at="0 0 0"/>
      <light_source location="5 5 -5" shadowless="true"/>
      <plane normal="0 1 0" distance="-1"><pigment color="1 1 1"/><finish reflection="0.3"/></plane>
      <sphere center="0 0 0" radius="1"><pigment color="1 0 0"/><finish phong="0.5"/></sphere>
      </scene>)",
                                   settings(16, 12));
  EXPECT_EQ(r.totals.shadowRays, 0u);
  EXPECT_EQ(r.effects & (kShadows | kHighlights), 0u);
  EXPECT_GT(r.totals.reflectedRays, 0u);
}

TEST(Render, GlassTracesRefractedRaysAndPlainTransmitDoesNot) {
  const char* glass = R"(<scene>
      <camera location="0 0 -5" look_at="0 0 0"/>
      <light_source location="5 5 -5"/>
      <sphere center="0 0 0" radius="1"><pigment color="1 1 1" filter="0.9"/>
        <interior ior="1.5"/></sphere></scene>)";
  const RenderResult g = renderXml(glass, settings(8, 8));
  EXPECT_GT(g.totals.refractedRays, 0u);
  EXPECT_EQ(g.totals.transmittedRays, 0u);
  const RenderResult t = renderXml(R"(<scene>
      <camera location="0 0 -5" look_at="0 0 0"/>
      <sphere center="0 0 0" radius="1"><pigment color="1 1 1" transmit="0.5"/></sphere></scene>)",
                                   settings(8, 8));
  EXPECT_EQ(t.totals.refractedRays, 0u);
  EXPECT_GT(t.totals.transmittedRays, 0u);
}

// A white filter-0.9 sphere between a light and a plane passes 0.9 * 0.9 of the light:
// one factor per surface crossing (POV-Ray's shadow rays are not bent).
TEST(Render, ShadowThroughFilterSphereMultipliesPerCrossing) {
  const RenderResult r = renderXml(R"(<scene>
      <camera location="0 5 0" look_at="0 0 0" sky="0 0 1"/>
      <light_source location="0 10 0"/>
      <plane normal="0 1 0" distance="0"><pigment color="1 1 1"/><finish ambient="0" diffuse="1"/></plane>
      <sphere center="0 7 0" radius="1" no_shadow="false"><pigment color="1 1 1" filter="0.9"/></sphere>
      </scene>)",
                                   settings(1, 1));
  EXPECT_NEAR(r.image.row(0)[0], 0.81, 1e-6);  // the film stores float
}

// buildScene of a description it may consume frees the objects' descriptions (a big scene
// must not hold them beside its BVH) and builds the same scene as from a kept description.
TEST(Render, SceneBuiltFromAConsumedDescriptionIsTheSame) {
  const SceneDesc desc = loadSceneString(R"(<scene>
      <camera location="0 2 -6" look_at="0 0 0"/>
      <light_source location="4 6 -4"/>
      <plane normal="0 1 0" distance="-1"><pigment><checker/></pigment><finish reflection="0.3"/></plane>
      <sphere center="0 0 0" radius="1"><pigment color="1 1 1" filter="0.8"/><interior ior="1.5"/></sphere>
      <box corner1="1 -1 0" corner2="2 0 1"><pigment color="0.8 0.2 0.1"/></box>
      </scene>)",
                                         "consumed.xml");
  SceneDesc consumed = desc;
  const Scene kept = buildScene(desc), fromConsumed = buildScene(std::move(consumed));
  // What buildScene left of the description it was handed, which is the point here.
  EXPECT_TRUE(consumed.objects.empty());  // NOLINT(bugprone-use-after-move)
  EXPECT_EQ(consumed.objects.capacity(), 0u);
  EXPECT_EQ(consumed.lights.size(), 1u);  // the rest is left as it was
  EXPECT_EQ(fromConsumed.effects, kept.effects);
  EXPECT_EQ(fromConsumed.bvh.size(), kept.bvh.size());
  const RenderSettings s = settings(24, 16);
  const RenderResult a = render(kept, s), b = render(fromConsumed, s);
  EXPECT_EQ(b.image.data(), a.image.data());
  EXPECT_EQ(b.totals.work(), a.totals.work());
  EXPECT_GT(a.totals.refractedRays, 0u);
}

// buildScene makes the same scene on any number of threads (it uses threadBudget()): the
// same primitives in the same order, materials, camera interiors, tolerances, tree and light
// buffers. 30,000 spheres make blocks of objects; a mesh and lone smooth triangles (one
// degenerate, a primitive never hit) give blocks other counts than their objects'; the
// camera sits inside two spheres and a transformed box.
TEST(Render, TheSceneDoesNotDependOnTheBuildThreads) {
  GenerateOptions options;
  options.spheres = 30000;
  options.lights = 3;
  options.seed = 9;
  options.radiusMin *= radiusScaleFor(options.spheres);
  options.radiusMax *= radiusScaleFor(options.spheres);
  SceneDesc desc = generateScene(options);
  const Vec3 eye = desc.camera.location;
  auto insert = [&](size_t at, ShapeDesc shape, bool transformed = false) {
    ObjectDesc o;
    o.shape = std::move(shape);
    o.material.finish.edit([&](FinishDesc& v) { v.phong = double(at % 3) * 0.3; });
    if (transformed) {  // turned about the origin, then moved to the camera
      o.transforms.steps.push_back({TransformStep::Kind::Rotate, {10, 20, 30}, {}, {}});
      o.transforms.steps.push_back({TransformStep::Kind::Translate, eye, {}, {}});
    }
    desc.objects.insert(desc.objects.begin() + std::ptrdiff_t(at), std::move(o));
  };
  MeshDesc mesh;
  for (int i = 0; i < 60; ++i) {
    const Vec3 p{0.1 * i, 1, 3};
    mesh.triangles.push_back({p, p + Vec3{0.1, 0, 0}, p + Vec3{0, 0.1, 0}, {}});
    mesh.smoothTriangles.push_back({p, {0, 0, 1}, p + Vec3{0.1, 0, 0.1}, {0, 1, 1}, p + Vec3{0, 0.1, 0}, {1, 0, 1}, {}});
  }
  insert(5000, mesh);
  insert(9000, SmoothTriangleDesc{{0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {0, 0, -1}, {0, 2, 0}, {0, 0, 1}, {}});  // degenerate
  insert(12000, SmoothTriangleDesc{{0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {0, 0.1, 1}, {0, 2, 0}, {0.1, 0, 1}, {}});
  insert(15000, SphereDesc{eye, 1});
  insert(21000, SphereDesc{eye + Vec3{0.1, 0, 0}, 2});
  insert(26000, BoxDesc{Vec3(-1), Vec3(1)}, true);
  auto build = [&](int threads) {
    setThreadBudget(threads);
    Scene scene = buildScene(desc);
    setThreadBudget(0);
    return scene;
  };
  const Scene one = build(1);
  ASSERT_EQ(one.cameraInteriors.count, 3);
  for (int threads : {2, 3, 8}) {
    const Scene many = build(threads);
    const auto all = [](const Bvh& bvh) {
      std::vector<Primitive> out;
      for (uint32_t i = 0; i < bvh.size(); ++i) out.push_back(bvh.primitive(i));
      return out;
    };
    const std::vector<Primitive> a = all(one.bvh), b = all(many.bvh);
    ASSERT_EQ(a.size(), b.size()) << threads << " threads";
    ASSERT_EQ(a.size(), desc.objects.size() - 1 + 120);  // the mesh's 120; the degenerate one is kept, never hit
    for (size_t i = 0; i < a.size(); ++i) {
      ASSERT_EQ(a[i].object, b[i].object) << "primitive " << i << ", " << threads << " threads";
      ASSERT_EQ(a[i].material, b[i].material) << "primitive " << i;
      ASSERT_EQ(a[i].opaque, b[i].opaque) << "primitive " << i;
      ASSERT_EQ(a[i].unit, b[i].unit) << "primitive " << i;
      ASSERT_EQ(a[i].shape.index(), b[i].shape.index()) << "primitive " << i;
      ASSERT_EQ(a[i].bounds().lo, b[i].bounds().lo) << "primitive " << i;
      ASSERT_EQ(a[i].bounds().hi, b[i].bounds().hi) << "primitive " << i;
    }
    ASSERT_EQ(one.materials.size(), many.materials.size());
    EXPECT_EQ(one.materials.surfaces(), many.materials.surfaces());
    for (size_t i = 0; i < one.materials.size(); ++i) {
      ASSERT_EQ(one.materials[i].surface, many.materials[i].surface) << "material " << i;
      ASSERT_EQ(one.materials[i].checker, many.materials[i].checker) << "material " << i;
      ASSERT_EQ(one.materials[i].color, many.materials[i].color) << "material " << i;
    }
    ASSERT_EQ(one.cameraInteriors.count, many.cameraInteriors.count);
    for (int k = 0; k < one.cameraInteriors.count; ++k)
      EXPECT_EQ(one.cameraInteriors.ids[k], many.cameraInteriors.ids[k]);
    EXPECT_EQ(one.tol.unit, many.tol.unit);
    EXPECT_EQ(one.effects, many.effects);
    ASSERT_EQ(one.bvh.nodes().size(), many.bvh.nodes().size());
    for (size_t i = 0; i < one.bvh.nodes().size(); ++i) {
      const BvhNode &x = one.bvh.nodes()[i], &y = many.bvh.nodes()[i];
      ASSERT_EQ(0, std::memcmp(x.quad, y.quad, sizeof x.quad)) << "node " << i;
      ASSERT_EQ(0, std::memcmp(x.child, y.child, sizeof x.child)) << "node " << i;
      ASSERT_EQ(0, std::memcmp(x.count, y.count, sizeof x.count)) << "node " << i;
    }
    ASSERT_EQ(one.lightBuffers.size(), many.lightBuffers.size());
    for (size_t l = 0; l < one.lightBuffers.size(); ++l) {
      const LightBuffer &x = one.lightBuffers[l], &y = many.lightBuffers[l];
      ASSERT_EQ(x.valid(), y.valid());
      ASSERT_EQ(x.entries(), y.entries());
      for (int c = 0; x.valid() && c < int(x.cells()); ++c)
        ASSERT_EQ(0, std::memcmp(x.list(c).data(), y.list(c).data(), x.list(c).size_bytes())) << "cell " << c;
    }
  }
}

}  // namespace
}  // namespace pvrt
