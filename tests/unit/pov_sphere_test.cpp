// Spheres as POV-Ray 3.7 intersects and shades them (geometry/primitive.h: hitUnitSphere,
// sphereNormal, sphereHitPoint) and where spawned rays then start (render/spawn.h):
// POV-Ray's operations to the bit where they are sound, pvrt's careful ones where not.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "geometry/primitive.h"
#include "render/spawn.h"

namespace pvrt {
namespace {

// Sphere::Intersect written out as POV-Ray writes it, step by step.
struct PovRoots {
  bool hit;
  double depth1, depth2;
};
PovRoots povSphereIntersect(const Vec3& center, double radius2, const Ray& ray) {
  const double ocx = center.x - ray.origin.x, ocy = center.y - ray.origin.y, ocz = center.z - ray.origin.z;
  const double ocSquared = ocx * ocx + ocy * ocy + ocz * ocz;
  const double closest = ocx * ray.dir.x + ocy * ray.dir.y + ocz * ray.dir.z;
  if (ocSquared >= radius2 && closest < 1e-10) return {false, 0, 0};
  const double halfChord2 = radius2 - ocSquared + closest * closest;
  if (!(halfChord2 > 1e-10)) return {false, 0, 0};
  const double halfChord = std::sqrt(halfChord2);
  return {true, closest - halfChord, closest + halfChord};
}

Vec3 unitDirection(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  const Vec3 v{g(rng), g(rng), g(rng)};
  return v * (1.0 / length(v));
}

// A ray from the origin along +z meets the sphere of radius 1 around (0, 0, 5) at 4 and
// 6: |oc|^2 = 25, oc.d = 5, half chord^2 = 1 - 25 + 25 = 1, all exact.
TEST(PovSphere, HeadOnDepthsWorkedOutByHand) {
  const auto h = detail::hitUnitSphere({0, 0, 5}, 1, {0, 0, 0}, {0, 0, 1}, 1e-4, 1e7, 1);
  ASSERT_TRUE(h);
  EXPECT_EQ(h->t, 4.0);
  const auto inside = detail::hitUnitSphere({0, 0, 5}, 1, {0, 0, 5}, {0, 0, 1}, 1e-4, 1e7, 1);
  ASSERT_TRUE(inside);
  EXPECT_EQ(inside->t, 1.0);  // from the centre: the far root only
}

// Over random rays toward random spheres within POV-Ray's reach, the depth is exactly
// POV-Ray's nearer root above the minimum depth; and the careful arithmetic it replaced
// (the roots q and c / q) gives other bits for some of them, so this could fail.
TEST(PovSphere, DepthsArePovRaysToTheBit) {
  std::mt19937_64 rng(26);
  std::uniform_real_distribution<double> coord(-20, 20), size(0.05, 5);
  int compared = 0, otherwise = 0;
  for (int i = 0; i < 20000; ++i) {
    const Vec3 center{coord(rng), coord(rng), coord(rng)};
    const double r = size(rng);
    const Vec3 origin{coord(rng), coord(rng), coord(rng)};
    // Aim near the sphere so that most rays hit.
    const Vec3 target = center + unitDirection(rng) * (r * 1.1);
    Vec3 dir = target - origin;
    dir = dir * (1.0 / length(dir));
    const Ray ray{origin, dir};
    const PovRoots pov = povSphereIntersect(center, r * r, ray);
    const auto got = detail::hitUnitSphere(center, r * r, origin, dir, 1e-4, 1e7, 1);
    double want = 0;
    bool wantHit = false;
    if (pov.hit) {
      if (pov.depth1 > 1e-4 && pov.depth1 < 1e7) wantHit = true, want = pov.depth1;
      else if (pov.depth2 > 1e-4 && pov.depth2 < 1e7) wantHit = true, want = pov.depth2;
    }
    ASSERT_EQ(bool(got), wantHit) << i;
    if (!got) continue;
    ++compared;
    ASSERT_EQ(got->t, want) << i;
    // Haines et al.'s roots, as pvrt had them.
    const Vec3 oc = center - origin;
    const double closest = dot(oc, dir);
    const Vec3 perp = oc - dir * closest;
    const double q = closest + std::copysign(std::sqrt(r * r - dot(perp, perp)), closest);
    const double c = (dot(oc, oc) - r * r) / q;
    const double careful = std::min(q, c) > 1e-4 ? std::min(q, c) : std::max(q, c);
    otherwise += careful != want;
  }
  EXPECT_GT(compared, 10000);
  EXPECT_GT(otherwise, 100) << "the two arithmetics should differ in the last bits for some rays";
}

// A small sphere far beyond POV-Ray's reach (10^7 radii): POV-Ray's half chord would be
// rounding noise; pvrt's is accurate, hits where the ray passes 0.9 r from the centre
// at the right depth, and misses at 1.1 r.
TEST(PovSphere, FarSpheresKeepTheCarefulArithmetic) {
  const double r = 1e-3;
  const Vec3 center{0, 0, 1e4};
  for (const double offset : {0.0, 0.5, 0.9}) {
    const Vec3 origin{offset * r, 0, 0};
    const auto h = detail::hitUnitSphere(center, r * r, origin, {0, 0, 1}, 1e-4, 1e7, 1);
    ASSERT_TRUE(h) << offset;
    const double exact = 1e4 - r * std::sqrt(1 - offset * offset);
    EXPECT_NEAR(h->t, exact, 1e-12 * 1e4) << offset;
  }
  EXPECT_FALSE(detail::hitUnitSphere(center, r * r, {1.1 * r, 0, 0}, {0, 0, 1}, 1e-4, 1e7, 1));
}

// Sphere::Normal: (P - C) times the reciprocal of the radius, which for a radius of 3 is
// not always the quotient; POV-Ray's product it is.
TEST(PovSphere, NormalTimesTheReciprocalRadius) {
  const SphereShape s{{0.5, -1, 2}, 3};
  std::mt19937_64 rng(3);
  int differ = 0;
  for (int i = 0; i < 1000; ++i) {
    const Vec3 p = s.center + unitDirection(rng) * 3;
    const Vec3 n = sphereNormal(s, p);
    const double inv = 1.0 / 3;
    EXPECT_EQ(n, Vec3((p.x - 0.5) * inv, (p.y + 1) * inv, (p.z - 2) * inv));
    differ += n != (p - s.center) / 3;
  }
  EXPECT_GT(differ, 0) << "the product and the quotient should differ somewhere";
}

// The shading point is POV-Ray's origin + t * dir, unmoved, and its bound covers its
// distance from the surface.
TEST(PovSphere, HitPointIsTheRaysOwnWithABound) {
  const SphereShape s{{1, 2, 3}, 1.5};
  std::mt19937_64 rng(7);
  for (int i = 0; i < 1000; ++i) {
    const Vec3 origin = s.center + unitDirection(rng) * 10;
    const Vec3 dir = (s.center + unitDirection(rng) * 0.7 - origin) * (1.0 / length(s.center - origin));
    const Ray ray{origin, dir * (1.0 / length(dir))};
    const auto h = intersectWorldSphere(s, 1, ray, 1e-4, 1e7);
    ASSERT_TRUE(h);
    const Vec3 at = ray.at(h->t);
    const SurfacePoint sp = sphereHitPoint(s, at);
    EXPECT_EQ(sp.p, at);
    const long double d = std::sqrt((long double)(at.x - 1) * (at.x - 1) + (long double)(at.y - 2) * (at.y - 2) +
                                    (long double)(at.z - 3) * (at.z - 3)) - 1.5L;
    EXPECT_LE(std::fabs(double(d)), length(sp.error) * 1.0000001) << i;
    EXPECT_LT(length(sp.error), 1e-13);
  }
}

// Spawned rays start at the hit point, as POV-Ray's do, when they leave its error slab
// within half the minimum depth; a grazing ray or a point far from the origin (a slab
// thicker than that) starts at the error-bounded origin instead.
TEST(PovSphere, SpawnedRaysStartAtTheHitPointWhereThatIsSafe) {
  const Vec3 n{0, 1, 0};
  const SurfacePoint thin{{0.25, 1e-17, 0.5}, {1e-16, 1e-16, 1e-16}};
  EXPECT_EQ(spawnOrigin(thin, n, {0.6, 0.8, 0}, 1e-4), thin.p);
  EXPECT_EQ(spawnOrigin(thin, n, {0.6, -0.8, 0}, 1e-4), thin.p);
  const Vec3 grazing{1, 1e-13, 0};
  const Vec3 o = spawnOrigin(thin, n, grazing, 1e-4);
  EXPECT_GT(o.y, thin.p.y + 1e-16);  // moved out of the slab on the side the ray leaves to
  const SurfacePoint thick{{1e12, 0, 0}, {1e-4, 1e-4, 1e-4}};
  EXPECT_NE(spawnOrigin(thick, n, {0, 1, 0}, 1e-4), thick.p);
  // Shadow segments: one origin for every light, the hit point when the slab is thin.
  RayTolerances tol;
  const double limit = shadowSlabLimit(tol);
  EXPECT_EQ(shadowSegmentOrigin(thin, n, limit), thin.p);
  EXPECT_GT(shadowSegmentOrigin(thick, n, limit).y, 0);
}

}  // namespace
}  // namespace pvrt
