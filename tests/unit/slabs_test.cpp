// The float slab test that single rays walk the BVH with must never lose a box that the
// double-precision test enters: otherwise a hit would go missing and the image change.
// Checked on random and on deliberately awkward rays: origins far from the boxes, on their
// faces and at every scale, directions with zero, negative-zero and tiny components, and
// rays that graze a box along an edge.
#include <gtest/gtest.h>

#include <cmath>

#include "accel/slabs.h"
#include "random_geometry.h"

namespace pvrt {
namespace {

class SlabCases : public test::RandomGeometry {
 public:
  using RandomGeometry::RandomGeometry;

  // A magnitude between 10^-3 and 10^8, with either sign.
  double scaled() { return (pick(2) ? 1 : -1) * std::pow(10.0, uniform(-3, 8)); }

  // A node with `used` children of random boxes around `center` of size about `size`.
  BvhNode node(const Vec3& center, double size, int used) {
    BvhNode n;
    for (int c = 0; c < used; ++c) {
      Vec3 lo, hi;
      for (int a = 0; a < 3; ++a) {
        const double mid = center[a] + uniform(-size, size), half = size * uniform(1e-6, 0.5);
        lo[a] = mid - half;
        hi[a] = mid + half;
      }
      n.setChild(c, {lo, hi}, uint32_t(c), 1);
    }
    return n;
  }

  // A direction from `from` to `to` (normalised); when `awkward`, with some components
  // replaced by zero, negative zero or a tiny number now and then.
  Vec3 direction(const Vec3& from, const Vec3& to, bool awkward = true) {
    Vec3 d = to - from;
    for (int a = 0; a < 3 && awkward; ++a) {
      switch (pick(12)) {
        case 0: d[a] = 0.0; break;
        case 1: d[a] = -0.0; break;
        case 2: d[a] = (pick(2) ? 1 : -1) * std::pow(10.0, uniform(-300, -30)); break;
        default: break;
      }
    }
    const double len = length(d);
    return len > 0 && std::isfinite(len) ? d / len : Vec3{0, 0, 1};
  }
};

// A point of child c's box (as the node stores it): a corner, a point on an edge or a face,
// or one inside.
Vec3 pointOf(const BvhNode& n, int c, SlabCases& r) {
  const Bounds b = n.childBounds(c);
  Vec3 p;
  for (int a = 0; a < 3; ++a) {
    switch (r.pick(3)) {
      case 0: p[a] = b.lo[a]; break;
      case 1: p[a] = b.hi[a]; break;
      default: p[a] = r.uniform(b.lo[a], b.hi[a]); break;
    }
  }
  return p;
}

void expectFloatEntersWhatDoubleEnters(const BvhNode& n, const Ray& ray, double tMin, double tMax) {
  double enterD[kBvhWidth];
  float enterF[kBvhWidth];
  const unsigned exact = hitsChildren(n, RaySlabs(ray), tMin, tMax, enterD) & ((1u << n.used) - 1);
  const unsigned fast = hitsNode(n, FloatRaySlabs(ray), float(tMin), float(tMax), enterF);
  ASSERT_EQ(exact & ~fast, 0u) << "origin " << ray.origin.x << " " << ray.origin.y << " " << ray.origin.z
                               << " dir " << ray.dir.x << " " << ray.dir.y << " " << ray.dir.z << " tMax " << tMax;
  // A box entered is not dropped later either: the walk drops stacked boxes whose float
  // entry lies beyond FloatRaySlabs::limit(tMax).
  for (unsigned m = exact; m != 0; m &= m - 1) {
    const int c = __builtin_ctz(m);
    ASSERT_LE(enterF[c], FloatRaySlabs::limit(float(tMax))) << "child " << c;
  }
}

TEST(Slabs, FloatTestEntersEveryBoxTheDoubleTestEnters) {
  SlabCases r(7);
  int entered = 0;
  for (int i = 0; i < 200000; ++i) {
    const double size = std::pow(10.0, r.uniform(-4, 4));
    const Vec3 center{r.scaled(), r.scaled(), r.scaled()};
    const BvhNode n = r.node(center, size, 1 + r.pick(kBvhWidth));
    // From near or far, aimed at a point of some child's box (so that most rays enter one).
    Vec3 origin = pointOf(n, r.pick(n.used), r);
    switch (r.pick(4)) {
      case 0: break;  // on a box's face, edge or corner, or inside it
      case 1: origin = origin + Vec3{r.scaled(), r.scaled(), r.scaled()} * 1e-3; break;
      default: origin = {r.scaled(), r.scaled(), r.scaled()}; break;
    }
    const Vec3 target = pointOf(n, r.pick(n.used), r);
    const Ray ray{origin, r.direction(origin, target)};
    const double tMin = r.pick(2) ? 0.0 : 1e-4;
    const double far = length(target - origin);
    double tMax = INFINITY;
    switch (r.pick(4)) {
      case 0: tMax = far; break;  // ends on the box, as a shadow segment ends at a light
      case 1: tMax = far * r.uniform(0.5, 2); break;
      case 2: tMax = 1e30; break;
      default: break;
    }
    expectFloatEntersWhatDoubleEnters(n, ray, tMin, tMax);
    double enter[kBvhWidth];
    entered += hitsChildren(n, RaySlabs(ray), tMin, tMax, enter) != 0;
  }
  // Most rays really enter a box, so the comparison is not a vacuous one.
  EXPECT_GT(entered, 100000);
}

// Rays along a box's edge or face, parallel to an axis: the double test enters the box (a
// NaN from 0 * infinity constrains nothing), and so must the float one.
TEST(Slabs, AxisParallelRaysOnAFaceStillEnter) {
  BvhNode n;
  n.setChild(0, {{1, 2, 3}, {1.5, 2.5, 3.5}}, 0, 1);
  n.setChild(1, {{100000.125, -7, 0.1}, {100001, -6.5, 0.3}}, 1, 1);
  for (int c = 0; c < 2; ++c) {
    const Bounds b = n.childBounds(c);
    for (const Vec3 dir : {Vec3{1, 0, 0}, Vec3{-1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, -0.0, 1}, Vec3{-0.0, 0, -1}}) {
      for (const Vec3 corner : {b.lo, b.hi, Vec3{b.lo.x, b.hi.y, b.lo.z}}) {
        const Ray ray{corner - dir * 10, dir};
        double enterD[kBvhWidth];
        ASSERT_NE(hitsChildren(n, RaySlabs(ray), 0, INFINITY, enterD) & (1u << c), 0u);
        expectFloatEntersWhatDoubleEnters(n, ray, 0, INFINITY);
      }
    }
  }
}

// An empty slot is never entered, whatever the ray, even one whose origin is beyond the
// float range (where the float test gives up on constraining the axis).
TEST(Slabs, EmptySlotsAreNeverEntered) {
  BvhNode n;
  n.setChild(0, {{0, 0, 0}, {1, 1, 1}}, 0, 1);
  float enter[kBvhWidth];
  for (const Vec3 origin : {Vec3{0.5, 0.5, -5}, Vec3{1e300, 0.5, 0.5}, Vec3{-1e39, 1e39, 0}}) {
    const Ray ray{origin, normalize(Vec3{0.5, 0.5, 0.5} - origin)};
    EXPECT_EQ(hitsNode(n, FloatRaySlabs(ray), 0, INFINITY, enter) & ~1u, 0u);
  }
}

// What the float test gives up: a few more boxes entered, never many. Over random rays
// the boxes it enters beyond the double test's are a tiny share.
TEST(Slabs, FloatTestEntersFewMoreBoxes) {
  SlabCases r(11);
  int exactCount = 0, fastCount = 0;
  for (int i = 0; i < 20000; ++i) {
    const BvhNode n = r.node({0, 0, 0}, 1, kBvhWidth);
    const Vec3 origin{r.uniform(-3, 3), r.uniform(-3, 3), r.uniform(-3, 3)};
    const Ray ray{origin, r.direction(origin, {r.uniform(-1, 1), r.uniform(-1, 1), r.uniform(-1, 1)}, false)};
    double enterD[kBvhWidth];
    float enterF[kBvhWidth];
    exactCount += __builtin_popcount(hitsChildren(n, RaySlabs(ray), 1e-4, 10, enterD));
    fastCount += __builtin_popcount(hitsNode(n, FloatRaySlabs(ray), 1e-4f, 10.0f, enterF));
  }
  EXPECT_GT(exactCount, 1000);
  EXPECT_LE(fastCount, exactCount + exactCount / 100);
}

}  // namespace
}  // namespace pvrt
