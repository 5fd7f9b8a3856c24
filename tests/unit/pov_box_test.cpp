// Boxes placed as POV-Ray 3.7's parser places them (Parse_Box, Box::Translate, Box::Scale,
// Box::Transform) and intersected as Box::Intersect does: a turned box's depths to the bit,
// so that its faces tie with a plane as POV-Ray's do (blind9's `checker_ft_transformed`: a
// sheared and turned glass box standing on the floor, 113 channels over 1 level before).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "core/pov_transform.h"
#include "render/scene.h"
#include "scene/xml_loader.h"

namespace pvrt {
namespace {

using Matrix = PovTransform::Matrix;

Vec3 invTransPoint(const Matrix& m, const Vec3& v) {  // MInvTransPoint
  Vec3 r;
  for (int i = 0; i < 3; ++i) r[i] = v.x * m[0][i] + v.y * m[1][i] + v.z * m[2][i] + m[3][i];
  return r;
}
Vec3 invTransDirection(const Matrix& m, const Vec3& v) {  // MInvTransDirection
  Vec3 r;
  for (int i = 0; i < 3; ++i) r[i] = v.x * m[0][i] + v.y * m[1][i] + v.z * m[2][i];
  return r;
}

// Box::Intersect's depths (the side choices left out: they never move a depth), then
// All_Intersections' choice: the entry depth when above DEPTH_TOLERANCE, else the exit.
std::optional<double> povBoxDepth(const Vec3& lo, const Vec3& hi, const Matrix* inverse, const Ray& ray) {
  const Vec3 p = inverse ? invTransPoint(*inverse, ray.origin) : ray.origin;
  const Vec3 d = inverse ? invTransDirection(*inverse, ray.dir) : ray.dir;
  double tmin = 0, tmax = 1e30;
  for (int a = 0; a < 3; ++a) {
    const double close = a == 0 ? 0 : 1e-6;
    if (d[a] < -1e-10 || d[a] > 1e-10) {
      const double far = ((d[a] < 0 ? lo[a] : hi[a]) - p[a]) / d[a];
      const double near = ((d[a] < 0 ? hi[a] : lo[a]) - p[a]) / d[a];
      if (far < tmin) return std::nullopt;
      if (far <= tmax - close) tmax = far;
      if (near >= tmin + close) {
        if (near > tmax) return std::nullopt;
        tmin = near;
      }
    } else if (p[a] < lo[a] || p[a] > hi[a]) {
      return std::nullopt;
    }
  }
  if (tmax < 1e-6) return std::nullopt;
  return tmin > 1e-4 ? tmin : tmax;
}

TEST(PovBox, TurnedBoxDepthsArePovRaysToTheBit) {
  // Scales and translations before the first rotate or matrix move the corners; every step
  // from it on is composed into the box's transform.
  const std::string xml =
      "<scene><box corner1=\"0.8 0.8 0.8\" corner2=\"-0.8 -0.8 -0.8\">"
      "<translate v=\"0.1 0.2 0.3\"/><scale v=\"1.5 -0.7 1.1\"/>"
      "<matrix v=\"1 0 0  0.4 1 0  0 0 1  0 0 0\"/><rotate v=\"0 35 0\"/><scale v=\"1.3\"/>"
      "<translate v=\"1.5 0.8 0.5\"/></box></scene>";
  const Scene scene = buildScene(loadSceneString(xml, "t.xml"));
  ASSERT_EQ(scene.bvh.size(), 1u);
  const Primitive& prim = scene.bvh.primitive(0);
  ASSERT_TRUE(std::holds_alternative<BoxShape>(prim.shape));
  ASSERT_TRUE(prim.transform);

  // POV-Ray's placement, step by step.
  Vec3 lo{-0.8, -0.8, -0.8}, hi{0.8, 0.8, 0.8};
  lo = lo + Vec3{0.1, 0.2, 0.3};
  hi = hi + Vec3{0.1, 0.2, 0.3};
  const Vec3 s{1.5, -0.7, 1.1};
  const Vec3 a = mul(lo, s), b = mul(hi, s);
  lo = vmin(a, b);
  hi = vmax(a, b);
  PovTransform t = PovTransform::identity();
  t.then(PovTransform::matrixOf(Affine::povMatrix({1, 0, 0, 0.4, 1, 0, 0, 0, 1, 0, 0, 0})));
  t.then(PovTransform::rotation({0, 35, 0}));
  t.then(PovTransform::scaling({1.3, 1.3, 1.3}));
  t.then(PovTransform::translation({1.5, 0.8, 0.5}));
  const BoxShape& box = std::get<BoxShape>(prim.shape);
  EXPECT_EQ(box.lo, lo);
  EXPECT_EQ(box.hi, hi);

  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> coord(-6, 6), unit(-1, 1);
  int hits = 0;
  for (int i = 0; i < 5000; ++i) {
    const Vec3 origin{coord(rng), coord(rng), coord(rng)};
    const Vec3 target = t.toTransform().toWorld.applyPoint({(lo.x + hi.x) / 2 + unit(rng) * (hi.x - lo.x) * 0.6,
                                                            (lo.y + hi.y) / 2 + unit(rng) * (hi.y - lo.y) * 0.6,
                                                            (lo.z + hi.z) / 2 + unit(rng) * (hi.z - lo.z) * 0.6});
    Vec3 dir = target - origin;
    dir = dir * (1.0 / length(dir));
    const Ray ray{origin, dir};
    const auto pov = povBoxDepth(lo, hi, &t.inverse, ray);
    const auto ours = prim.intersect(ray, 1e-4, 1e7);
    ASSERT_EQ(bool(pov), bool(ours)) << i;
    if (!pov) continue;
    ++hits;
    ASSERT_EQ(ours->t, *pov) << i;
  }
  EXPECT_GT(hits, 2000);
}

// A box only moved and scaled keeps no transform: its corners move one step at a time,
// (corner + d) * s, as Box::Translate and Box::Scale move them (not by the composed map).
TEST(PovBox, MovedAndScaledCornersStepByStep) {
  const Scene scene =
      buildScene(loadSceneString("<scene><box corner1=\"0.1 0.2 0.3\" corner2=\"1 1 1\"><translate v=\"0.7 0.7 0.7\"/>"
                                 "<scale v=\"0.3 -3 1.7\"/></box></scene>",
                                 "t.xml"));
  const Primitive& prim = scene.bvh.primitive(0);
  EXPECT_FALSE(prim.transform);
  const BoxShape& box = std::get<BoxShape>(prim.shape);
  const Vec3 a = mul(Vec3{0.1, 0.2, 0.3} + Vec3{0.7, 0.7, 0.7}, Vec3{0.3, -3, 1.7});
  const Vec3 b = mul(Vec3{1, 1, 1} + Vec3{0.7, 0.7, 0.7}, Vec3{0.3, -3, 1.7});
  EXPECT_EQ(box.lo, vmin(a, b));
  EXPECT_EQ(box.hi, vmax(a, b));
}

}  // namespace
}  // namespace pvrt
