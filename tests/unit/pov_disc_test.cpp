// Discs as POV-Ray 3.7 intersects them (geometry/pov_disc.h): the canonical disc through
// POV-Ray's own transform, its depth and its world normal to the bit.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "geometry/pov_disc.h"
#include "geometry/primitive.h"

namespace pvrt {
namespace {

using Matrix = PovTransform::Matrix;

// MInvTransPoint and MInvTransDirection (matrices.cpp) written out from the inverse matrix.
Vec3 invTransPoint(const Matrix& m, const Vec3& v) {
  Vec3 r;
  for (int i = 0; i < 3; ++i) r[i] = v.x * m[0][i] + v.y * m[1][i] + v.z * m[2][i] + m[3][i];
  return r;
}
Vec3 invTransDirection(const Matrix& m, const Vec3& v) {
  Vec3 r;
  for (int i = 0; i < 3; ++i) r[i] = v.x * m[0][i] + v.y * m[1][i] + v.z * m[2][i];
  return r;
}

// Disc::Intersect step by step, as discs.cpp writes it (depths above DEPTH_TOLERANCE).
std::optional<double> povDiscIntersect(const PovDiscPlacement& d, const Ray& ray) {
  const Vec3 p = invTransPoint(d.transform.inverse, ray.origin);
  Vec3 dir = invTransDirection(d.transform.inverse, ray.dir);
  const double len = std::sqrt(dir.x * dir.x + dir.y * dir.y + dir.z * dir.z);
  const double inv = 1.0 / len;
  dir = {dir.x * inv, dir.y * inv, dir.z * inv};
  if (!(std::fabs(dir.z) > 1e-10)) return std::nullopt;
  const double t = -p.z / dir.z;
  if (!(t >= 0.0)) return std::nullopt;
  const double u = p.x + t * dir.x, v = p.y + t * dir.y;
  const double r2 = u * u + v * v;
  if (!(r2 >= d.shape.inner2 && r2 <= d.shape.outer2)) return std::nullopt;
  const double depth = t / len;
  if (!(depth > 1e-6 && depth < 1e7)) return std::nullopt;
  return depth;
}

Primitive primitiveOf(const PovDiscPlacement& placed) {
  Primitive p;
  p.shape = placed.shape;
  p.transform = share(placed.transform.toTransform());
  return p;
}

// A ring in y = 0 of radius 2 around a hole of radius 1, seen from 5 above: exact depths.
TEST(PovDisc, RingWorkedOutByHand) {
  const Primitive d = primitiveOf(placeDisc({0, 0, 0}, {0, 1, 0}, 2, 1));
  const Ray down{{1.5, 5, 0}, {0, -1, 0}};
  const auto h = d.intersect(down, 0, 1e7);
  ASSERT_TRUE(h);
  EXPECT_EQ(h->t, 5.0);
  EXPECT_FALSE(d.intersect({{0.5, 5, 0}, {0, -1, 0}}, 0, 1e7));   // through the hole
  EXPECT_FALSE(d.intersect({{2.5, 5, 0}, {0, -1, 0}}, 0, 1e7));   // beyond the rim
  EXPECT_FALSE(d.intersect({{1.5, 5, 0}, {1, 0, 0}}, 0, 1e7));    // parallel
  EXPECT_FALSE(d.intersect(down, 5.0, 1e7));                      // not beyond lo
  EXPECT_TRUE(d.inside({0, -5e-4, 0}));  // behind it and within its box (below)
  EXPECT_FALSE(d.inside({0, -1, 0}));    // behind it, beyond its box
  EXPECT_FALSE(d.inside({0, 1, 0}));
}

// Random discs, each moved by a rotation, a scale and a translation written after it, and
// random rays toward them: every depth is POV-Ray's, bit for bit.
TEST(PovDisc, DepthsArePovRaysToTheBit) {
  std::mt19937_64 rng(26);
  std::uniform_real_distribution<double> coord(-10, 10), unit(-1, 1), size(0.2, 3);
  int hits = 0;
  for (int i = 0; i < 5000; ++i) {
    const Vec3 center{coord(rng), coord(rng), coord(rng)}, normal{unit(rng), unit(rng), unit(rng)};
    const double r = size(rng);
    PovDiscPlacement d = placeDisc(center, normal, r, i % 3 == 0 ? r / 3 : 0);
    if (i % 2) {
      d.then(PovTransform::rotation({coord(rng) * 9, coord(rng) * 9, coord(rng) * 9}));
      d.then(PovTransform::scaling({size(rng), size(rng), size(rng)}));
      d.then(PovTransform::translation({coord(rng), coord(rng), coord(rng)}));
    }
    const Primitive p = primitiveOf(d);
    const Vec3 origin{coord(rng) * 3, coord(rng) * 3, coord(rng) * 3};
    const Vec3 target = p.transform->toWorld.applyPoint({unit(rng) * r, unit(rng) * r, 0});
    Vec3 dir = target - origin;
    dir = dir * (1.0 / length(dir));
    const Ray ray{origin, dir};
    const auto pov = povDiscIntersect(d, ray);
    const auto ours = p.intersect(ray, 0, 1e7);
    ASSERT_EQ(bool(pov), bool(ours)) << i;
    if (!pov) continue;
    ++hits;
    ASSERT_EQ(ours->t, *pov) << i;
  }
  EXPECT_GT(hits, 2000);
}

// The normal is the written one made unit, then carried by each transform and made unit
// again (MTransNormal, VNormalize), as Disc::Transform does.
TEST(PovDisc, NormalFollowsEachTransformWritten) {
  PovDiscPlacement d = placeDisc({1, 2, 3}, {0, 2, 0}, 1, 0);
  EXPECT_EQ(d.shape.normal, (Vec3{0, 1, 0}));
  const PovTransform scale = PovTransform::scaling({1, 0.5, 4}), turn = PovTransform::rotation({30, 0, 40});
  d.then(scale);
  d.then(turn);
  Vec3 n{0, 1, 0};
  for (const PovTransform* t : {&scale, &turn}) {
    const Matrix& m = t->inverse;
    Vec3 w;
    for (int i = 0; i < 3; ++i) w[i] = n.x * m[i][0] + n.y * m[i][1] + n.z * m[i][2];
    n = w * (1.0 / std::sqrt(w.x * w.x + w.y * w.y + w.z * w.z));
  }
  EXPECT_EQ(d.shape.normal, n);
  const Primitive p = primitiveOf(d);
  const Vec3 middle = p.transform->toWorld.applyPoint({0, 0, 0});
  const Ray toward{middle + n * 5.0, -n};
  const auto h = p.intersect(toward, 0, 1e7);
  ASSERT_TRUE(h);
  EXPECT_EQ(p.normal(toward, *h), n);
}

// A disc lying on the plane y = 0 meets rays at the plane's distance only in exact
// arithmetic: its rounding puts it nearer for some rays and not for others, which is how
// POV-Ray's image of such a disc comes out speckled, and why pvrt must round as it does.
TEST(PovDisc, OnAPlaneTheRoundingDecides) {
  const Primitive d = primitiveOf(placeDisc({0.3, 0, 0.1}, {0, 1, 0}, 2, 0));
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> spot(-1, 1);
  int nearer = 0, notNearer = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 origin{0.3, 3.1, -7.2}, target{spot(rng), 0, spot(rng)};
    Vec3 dir = target - origin;
    dir = dir * (1.0 / length(dir));
    const auto h = d.intersect({origin, dir}, 0, 1e7);
    ASSERT_TRUE(h);
    const double plane = -(origin.y) / dir.y;  // Plane::Intersect for y = 0
    (h->t < plane ? nearer : notNearer)++;
  }
  EXPECT_GT(nearer, 0);
  EXPECT_GT(notNearer, 0);
}

// TracePixel::InitRayContainerState starts a camera ray inside an object only when the camera
// is inside the object's bounding box as well as its inside test. A disc's inside is the
// half-space below it, but its box (Disc::Compute_BBox) is a slab SMALL_TOLERANCE (1e-3) above
// and below it: a camera below a glass disc's plane and away from it is in no disc (a glass's
// rim or bottom seen from a camera below or above them, blind10's glass of water).
TEST(PovDisc, HoldsACameraOnlyWithinItsBoundingBox) {
  const Primitive rim = primitiveOf(placeDisc({0, 1.8, 0}, {0, 1, 0}, 0.6, 0.56));
  EXPECT_FALSE(rim.inside({0, 1.6, -4}));            // below its plane, far from its box
  EXPECT_FALSE(rim.inside({0.1, 1.79, 0.2}));        // below its plane, beneath its box
  EXPECT_TRUE(rim.inside({0.1, 1.8 - 5e-4, 0.2}));   // below its plane, within its box
  EXPECT_FALSE(rim.inside({0.1, 1.8 + 5e-4, 0.2}));  // within its box, above its plane
  EXPECT_FALSE(rim.inside({0.7, 1.8 - 5e-4, 0}));    // beside its box
  // A turned disc's box is the world box of its turned slab (Recompute_BBox): it holds
  // points below the disc's plane that the slab itself does not.
  const Primitive turned = primitiveOf(placeDisc({0, 0, 0}, {1, 1, 0}, 1, 0));
  EXPECT_TRUE(turned.inside({-0.3, -0.3, 0}));
  EXPECT_FALSE(turned.inside({-0.3, 0.35, 0}));      // above its plane
  EXPECT_FALSE(turned.inside({-3, -3, 0}));
}

}  // namespace
}  // namespace pvrt
