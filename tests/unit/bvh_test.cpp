// The BVH must be an invisible speed-up: for any ray it finds exactly the hit a loop over
// every primitive finds, while testing only a handful of primitives per ray.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "accel/bvh.h"
#include "random_geometry.h"

namespace pvrt {
namespace {

// A primitive of shape `s` that came from object `object`.
Primitive make(const Shape& s, uint32_t object) {
  Primitive p;
  p.shape = s;
  p.object = object;
  return p;
}

// Random scenes with a fixed seed so failures reproduce.
class SceneMaker : public test::RandomGeometry {
 public:
  using RandomGeometry::RandomGeometry;
  // `n` spheres in the cube [-half, half]^3, each primitive's object index its position.
  std::vector<Primitive> spheres(size_t n, double half, double rMin, double rMax) {
    std::vector<Primitive> prims;
    prims.reserve(n);
    for (size_t i = 0; i < n; ++i) {
      const Vec3 c = point(half);
      prims.push_back(make(SphereShape{c, uniform(rMin, rMax)}, uint32_t(i)));
    }
    return prims;
  }
  Ray ray(double half) { return {point(half), direction()}; }
  // `n` primitives of every bounded shape in [-10, 10]^3, some transformed, each with its
  // own material and object, plus a plane under everything.
  std::vector<Primitive> mixed(uint32_t n) {
    std::vector<Primitive> prims;
    for (uint32_t i = 0; i < n; ++i) {
      const Vec3 c = point(10);
      const double r = uniform(0.1, 0.8);
      Shape s;
      std::optional<PovConePlacement> placed;  // cylinders, cones and discs carry POV-Ray's transform
      std::optional<PovDiscPlacement> disc;
      std::optional<PovTransform> mesh;
      switch (i % 7) {
        case 0: s = SphereShape{c, r}; break;
        case 1: s = BoxShape{c - Vec3(r), c + Vec3{r, 2 * r, r}}; break;
        case 2: placed = placeCylinder(c, c + direction() * (2 * r), r / 2, i % 2 == 0); break;
        case 3: placed = placeCone(c, r, c + direction() * (2 * r), r / 3, false); break;
        case 4: disc = placeDisc(c, direction(), r, r / 2); break;
        case 5: {
          const Vec3 b = c + direction() * r, d = c + direction() * r;
          s = PovMeshBuilder().triangle(c, b, d);
          break;
        }
        default: {  // a mesh's smooth triangle, in a turned mesh's own space
          const Vec3 n1 = direction(), b = c + direction() * r, n2 = direction(), d = c + direction() * r;
          bool smooth = false;
          s = PovMeshBuilder().smoothTriangle(c, n1, b, n2, d, direction(), smooth);
          mesh = PovTransform::rotation({10, 20, 30});
        }
      }
      if (placed) s = placed->shape;
      if (disc) s = disc->shape;
      Primitive p = make(s, i);
      if (placed) p.transform = share(placed->transform.toTransform());
      if (disc) p.transform = share(disc->transform.toTransform());
      if (mesh) p.transform = share(mesh->toTransform());
      p.material = n - i;
      if (i % 5 == 0) {  // a sphere at the origin, scaled, rotated and moved to c
        p.shape = SphereShape{{0, 0, 0}, r};
        p.transform = share(Transform::from(
            Affine::scale({1, 0.5, 2}).then(Affine::rotate({10, 20, 30})).then(Affine::translate(c))));
      }
      prims.push_back(p);
    }
    prims.push_back(make(PlaneShape{{0, 1, 0}, -11}, n));
    return prims;
  }
};

struct Found {
  bool hit = false;
  double t = 0;
  uint32_t object = 0;
};

// The reference answer: every primitive tested, nearest kept.
Found bruteForce(const std::vector<Primitive>& prims, const Ray& r, double tMin, double tMax,
                 bool skipNoShadow = false) {
  Found f;
  double best = tMax;
  for (const Primitive& p : prims) {
    if (skipNoShadow && p.noShadow) continue;
    if (auto h = p.intersect(r, tMin, best)) {
      best = h->t;
      f = {true, h->t, p.object};
    }
  }
  return f;
}

Found viaBvh(const Bvh& bvh, const Ray& r, double tMin, double tMax, uint64_t& tests,
             bool skipNoShadow = false) {
  const auto h = bvh.closest(r, tMin, tMax, tests, skipNoShadow);
  if (!h) return {};
  return {true, h->hit.t, bvh.primitive(h->primitive).object};
}

// Compares BVH and brute force on `rays` random rays; returns how many hit something.
int compareOnRandomRays(const std::vector<Primitive>& prims, SceneMaker& gen, int rays, double half,
                        uint32_t leafSize = kBvhLeafSize) {
  const Bvh bvh(prims, 0, leafSize);
  EXPECT_EQ(bvh.stats().leafSize, leafSize);
  int hits = 0;
  uint64_t tests = 0;
  for (int i = 0; i < rays; ++i) {
    const Ray r = gen.ray(half);
    const Found want = bruteForce(prims, r, kMinIsectDepth, kMaxDistance);
    const Found got = viaBvh(bvh, r, kMinIsectDepth, kMaxDistance, tests);
    EXPECT_EQ(got.hit, want.hit) << "ray " << i;
    if (got.hit && want.hit) {
      // Same primitive, same arithmetic: the distance must agree to the last bit.
      EXPECT_EQ(got.object, want.object) << "ray " << i;
      EXPECT_EQ(got.t, want.t) << "ray " << i;
    }
    hits += want.hit;
  }
  return hits;
}

// 2,000 spheres in a 20-unit cube, 5,000 rays starting anywhere (inside spheres too).
TEST(Bvh, ClosestMatchesBruteForceOnRandomSpheres) {
  SceneMaker gen(0x5eed'0001);
  const auto prims = gen.spheres(2000, 10, 0.05, 0.6);
  const int hits = compareOnRandomRays(prims, gen, 5000, 12);
  // The test means something only if many rays hit and some miss.
  EXPECT_GT(hits, 1000);
  EXPECT_LT(hits, 5000);
}

// The cheaper trees (leaves of up to 16, 64, 255 primitives: a memory limit) answer every
// ray as the SAH's tree does, with fewer nodes and bytes.
TEST(Bvh, CheaperTreesAnswerTheSame) {
  SceneMaker gen(0x5eed'0011);
  const auto prims = gen.spheres(3000, 10, 0.05, 0.5);
  uint64_t nodes = Bvh(prims).stats().nodes, bytes = Bvh(prims).stats().bytes;
  for (uint32_t leaf : {16u, 64u, 255u}) {
    SceneMaker rays(0x5eed'0012);
    EXPECT_GT(compareOnRandomRays(prims, rays, 2000, 12, leaf), 300) << leaf;
    const Bvh cheap(prims, 0, leaf);
    EXPECT_LT(cheap.stats().nodes, nodes) << leaf;
    EXPECT_LT(cheap.stats().bytes, bytes) << leaf;
    nodes = cheap.stats().nodes;
    bytes = cheap.stats().bytes;
  }
  // The same tree whatever the number of threads.
  const Bvh one(prims, 1, 64), two(prims, 2, 64);
  ASSERT_EQ(one.nodes().size(), two.nodes().size());
  for (uint32_t i = 0; i < one.size(); ++i) EXPECT_EQ(one.primitive(i).object, two.primitive(i).object);
}

// Sizes around the leaf size and tiny scenes exercise the build's edge cases.
TEST(Bvh, ClosestMatchesBruteForceForSmallScenes) {
  SceneMaker gen(0x5eed'0002);
  for (size_t n : {1u, 2u, 3u, 4u, 5u, 7u, 16u, 33u}) {
    SCOPED_TRACE(n);
    const auto prims = gen.spheres(n, 3, 0.3, 1.5);
    const int hits = compareOnRandomRays(prims, gen, 500, 4);
    EXPECT_GT(hits, 0);
  }
}

// A mixture of every bounded shape, some transformed, plus a plane under everything.
TEST(Bvh, ClosestMatchesBruteForceOnMixedShapesAndAPlane) {
  SceneMaker gen(0x5eed'0003);
  const std::vector<Primitive> prims = gen.mixed(600);
  const int hits = compareOnRandomRays(prims, gen, 5000, 10);
  EXPECT_GT(hits, 2000);  // roughly half of the rays point down at the floor
}

// What shading asks of a hit primitive through the BVH (read from its compact leaf record
// where it can be) is exactly what the Primitive itself answers, bit for bit.
TEST(Bvh, ShadingQueriesMatchThePrimitives) {
  SceneMaker gen(0x5eed'0010);
  auto prims = gen.mixed(700);
  // Planes, which the leaf records answer for too, some of them tilted.
  prims.push_back(make(PlaneShape{normalize(Vec3{0.3, 1, 0.2}), -15}, 901));
  prims.push_back(make(PlaneShape{{0, 0, 1}, 40}, 902));
  prims.push_back(make(PlaneShape{normalize(Vec3{-1, 0.1, 0.4}), 30}, 903));
  const Bvh bvh(std::move(prims));
  const auto same = [](const Vec3& a, const Vec3& b) { return std::memcmp(&a, &b, sizeof(Vec3)) == 0; };
  int hits = 0, planeHits = 0;
  for (int k = 0; k < 4000; ++k) {
    const Ray r = gen.ray(12);
    uint64_t tests = 0;
    const auto found = bvh.closest(r, 1e-6, 1e7, tests);
    if (!found) continue;
    ++hits;
    const uint32_t i = found->primitive;
    const Primitive& p = bvh.primitive(i);
    planeHits += std::holds_alternative<PlaneShape>(p.shape);
    EXPECT_EQ(bvh.material(i), p.material);
    EXPECT_EQ(bvh.object(i), p.object);
    const SurfacePoint a = bvh.surfacePoint(i, r, found->hit), b = p.surfacePoint(r, found->hit);
    EXPECT_TRUE(same(a.p, b.p) && same(a.error, b.error)) << "primitive " << i;
    EXPECT_TRUE(same(bvh.normal(i, r, found->hit), p.normal(r, found->hit))) << "primitive " << i;
    const auto again = bvh.intersect(i, r, 1e-6, 1e7), direct = p.intersect(r, 1e-6, 1e7);
    ASSERT_EQ(again.has_value(), direct.has_value());
    EXPECT_EQ(again->t, direct->t);
  }
  EXPECT_GT(hits, 1000);
  EXPECT_GT(planeHits, 100);
}

// Planes have no bounds: they live outside the tree and are tested on every ray. A ray
// that misses every sphere still finds the plane y=-20, 20 units below the origin.
TEST(Bvh, UnboundedPlanesAreStillFound) {
  SceneMaker gen(0x5eed'0004);
  auto prims = gen.spheres(100, 5, 0.1, 0.5);
  prims.push_back(make(PlaneShape{{0, 1, 0}, -20}, 777));
  const Bvh bvh(prims);
  EXPECT_EQ(bvh.size(), 101u);
  uint64_t tests = 0;
  const Found f = viaBvh(bvh, {{50, 0, 50}, {0, -1, 0}}, kMinIsectDepth, kMaxDistance, tests);
  ASSERT_TRUE(f.hit);
  EXPECT_EQ(f.object, 777u);
  EXPECT_DOUBLE_EQ(f.t, 20.0);

  // A scene of planes only: no tree at all, still found, the nearer one first.
  const Bvh planes(std::vector<Primitive>{make(PlaneShape{{0, 0, 1}, 5}, 0), make(PlaneShape{{0, 0, 1}, 3}, 1)});
  EXPECT_EQ(planes.stats().nodes, 0u);
  const Found g = viaBvh(planes, {{0, 0, 0}, {0, 0, 1}}, kMinIsectDepth, kMaxDistance, tests);
  ASSERT_TRUE(g.hit);
  EXPECT_EQ(g.object, 1u);
  EXPECT_DOUBLE_EQ(g.t, 3.0);
}

// Two spheres on the z axis; the nearer (z=5) is no_shadow. Shadow queries pass through
// it to the farther one (z=10), ordinary queries stop at it.
TEST(Bvh, SkipNoShadowIgnoresNoShadowPrimitives) {
  Primitive nearSphere = make(SphereShape{{0, 0, 5}, 1}, 0);
  nearSphere.noShadow = true;
  const Primitive farSphere = make(SphereShape{{0, 0, 10}, 1}, 1);
  Primitive plane = make(PlaneShape{{0, 0, -1}, -20}, 2);  // z = 20, also no_shadow
  plane.noShadow = true;
  const Bvh bvh(std::vector<Primitive>{nearSphere, farSphere, plane});
  const Ray r{{0, 0, 0}, {0, 0, 1}};
  uint64_t tests = 0;
  const Found normal = viaBvh(bvh, r, kMinIsectDepth, kMaxDistance, tests);
  ASSERT_TRUE(normal.hit);
  EXPECT_EQ(normal.object, 0u);
  EXPECT_DOUBLE_EQ(normal.t, 4.0);
  const Found shadow = viaBvh(bvh, r, kMinIsectDepth, kMaxDistance, tests, true);
  ASSERT_TRUE(shadow.hit);
  EXPECT_EQ(shadow.object, 1u);
  EXPECT_DOUBLE_EQ(shadow.t, 9.0);
  // Beyond the far sphere only no_shadow things remain.
  EXPECT_FALSE(viaBvh(bvh, {{0, 0, 12}, {0, 0, 1}}, kMinIsectDepth, kMaxDistance, tests, true).hit);
  EXPECT_TRUE(viaBvh(bvh, {{0, 0, 12}, {0, 0, 1}}, kMinIsectDepth, kMaxDistance, tests).hit);

  // And on a random scene with every third sphere no_shadow, against brute force.
  SceneMaker gen(0x5eed'0005);
  auto prims = gen.spheres(1500, 10, 0.1, 0.7);
  for (size_t i = 0; i < prims.size(); i += 3) prims[i].noShadow = true;
  const Bvh big(prims);
  for (int i = 0; i < 3000; ++i) {
    const Ray q = gen.ray(12);
    const Found want = bruteForce(prims, q, kMinIsectDepth, kMaxDistance, true);
    const Found got = viaBvh(big, q, kMinIsectDepth, kMaxDistance, tests, true);
    ASSERT_EQ(got.hit, want.hit) << "ray " << i;
    if (want.hit) {
      EXPECT_EQ(got.object, want.object) << "ray " << i;
      EXPECT_EQ(got.t, want.t) << "ray " << i;
      EXPECT_NE(got.object % 3, 0u) << "a no_shadow sphere was returned";
    }
  }
}

// tMax limits the search (a shadow ray stops at its light): the sphere at t=4 is found
// with tMax 4.5 but not with tMax 3.5; tMin above it finds the plane behind instead.
TEST(Bvh, RespectsTMinAndTMax) {
  const Bvh bvh(std::vector<Primitive>{make(SphereShape{{0, 0, 5}, 1}, 0), make(PlaneShape{{0, 0, 1}, 8}, 1)});
  const Ray r{{0, 0, 0}, {0, 0, 1}};
  uint64_t tests = 0;
  EXPECT_TRUE(viaBvh(bvh, r, kMinIsectDepth, 4.5, tests).hit);
  EXPECT_FALSE(viaBvh(bvh, r, kMinIsectDepth, 3.5, tests).hit);
  const Found behind = viaBvh(bvh, r, 6.5, kMaxDistance, tests);
  ASSERT_TRUE(behind.hit);
  EXPECT_EQ(behind.object, 1u);
  EXPECT_DOUBLE_EQ(behind.t, 8.0);
}

TEST(Bvh, EmptyBvhFindsNothing) {
  const Ray r{{0, 0, 0}, {0, 0, 1}};
  uint64_t tests = 0;
  const Bvh defaulted;
  EXPECT_FALSE(defaulted.closest(r, kMinIsectDepth, kMaxDistance, tests));
  const Bvh built{std::vector<Primitive>{}};
  EXPECT_FALSE(built.closest(r, kMinIsectDepth, kMaxDistance, tests));
  EXPECT_EQ(tests, 0u);
  EXPECT_EQ(built.stats().nodes, 0u);
  EXPECT_EQ(built.stats().leaves, 0u);
  EXPECT_TRUE(built.empty());
}

// Building reorders the primitives, but keeps every one of them exactly once.
TEST(Bvh, ReorderingKeepsEveryPrimitive) {
  SceneMaker gen(0x5eed'0006);
  auto prims = gen.spheres(1000, 10, 0.1, 0.5);
  prims.push_back(make(PlaneShape{{0, 1, 0}, 0}, 1000));
  const Bvh bvh(prims);
  std::vector<uint32_t> objects;
  for (uint32_t i = 0; i < bvh.size(); ++i) objects.push_back(bvh.primitive(i).object);
  // The bounded ones come first, the plane last.
  EXPECT_EQ(objects.back(), 1000u);
  std::sort(objects.begin(), objects.end());
  for (uint32_t i = 0; i < objects.size(); ++i) ASSERT_EQ(objects[i], i);
}

// The whole point: with 100,000 spheres a ray costs on the order of log(N) primitive
// tests, not N. The spheres are dense enough that most rays hit one (so rays do not just
// skim past the root box). We demand an average below 1% of N (1,000 tests) and, more
// tellingly, below 3 log2(N) (about 50); and the answers must agree with brute force.
TEST(Bvh, IntersectionTestsGrowFarSlowerThanThePrimitiveCount) {
  SceneMaker gen(0x5eed'0007);
  constexpr size_t kN = 100000;
  const auto prims = gen.spheres(kN, 50, 0.2, 1.5);
  const Bvh bvh(prims);
  constexpr int kRays = 2000;
  uint64_t tests = 0;
  int hits = 0;
  for (int i = 0; i < kRays; ++i) {
    const Ray r = gen.ray(60);
    const Found got = viaBvh(bvh, r, kMinIsectDepth, kMaxDistance, tests);
    hits += got.hit;
    if (i % 20 == 0) {  // brute force on 100 of the rays (each costs N tests)
      const Found want = bruteForce(prims, r, kMinIsectDepth, kMaxDistance);
      ASSERT_EQ(got.hit, want.hit) << "ray " << i;
      if (want.hit) {
        EXPECT_EQ(got.object, want.object) << "ray " << i;
      }
    }
  }
  const double perRay = double(tests) / kRays;
  EXPECT_LT(perRay, 0.01 * kN) << "average tests per ray";
  EXPECT_LT(perRay, 3 * std::log2(double(kN))) << "average tests per ray";
  EXPECT_GT(perRay, 0.0);
  EXPECT_GT(hits, kRays / 2);
  // At the same density, 1,000 spheres cost about as much per ray as 100,000: 100x the
  // primitives must not multiply the cost by anything like 100.
  SceneMaker small(0x5eed'0008);
  const double smallHalf = 50 / std::cbrt(100.0);
  const Bvh few(small.spheres(1000, smallHalf, 0.2, 1.5));
  uint64_t fewTests = 0;
  for (int i = 0; i < kRays; ++i)
    viaBvh(few, small.ray(1.2 * smallHalf), kMinIsectDepth, kMaxDistance, fewTests);
  const double fewPerRay = double(fewTests) / kRays;
  EXPECT_GT(fewPerRay, 0.0);
  EXPECT_LT(perRay, 10 * fewPerRay) << "100x the primitives, " << perRay / fewPerRay << "x the tests";
}

// A tree of width W with L leaves has between (L-1)/(W-1) and L-1 nodes (every node but
// the root of a one-leaf tree has 2 to W children); with at most a few primitives per
// leaf there are at least N/4 leaves, and the tree is at least logW(N/4) deep but
// nowhere near N deep.
TEST(Bvh, StatsDescribeTheTree) {
  SceneMaker gen(0x5eed'0009);
  constexpr size_t kN = 10000;
  const Bvh bvh(gen.spheres(kN, 20, 0.05, 0.3));
  const BvhStats& s = bvh.stats();
  EXPECT_GE((kBvhWidth - 1) * s.nodes, s.leaves - 1);
  EXPECT_LE(s.nodes, s.leaves - 1);
  EXPECT_GE(s.leaves, kN / 4);
  EXPECT_LE(s.leaves, kN);
  EXPECT_GE(s.maxDepth, int(std::log(double(kN) / 4) / std::log(double(kBvhWidth))));
  EXPECT_LE(s.maxDepth, 64);
  EXPECT_EQ(s.bytes, s.nodes * sizeof(BvhNode) + kN * sizeof(PrimitiveRecord));  // spheres: records alone
  EXPECT_GE(s.buildSeconds, 0.0);

  // One primitive: a root with a single leaf, depth 1.
  const Bvh one(gen.spheres(1, 1, 0.5, 0.5));
  EXPECT_EQ(one.stats().nodes, 1u);
  EXPECT_EQ(one.stats().leaves, 1u);
  EXPECT_EQ(one.stats().maxDepth, 1);
}

// 5,000 identical spheres share one centroid, so no SAH split exists; the build must
// still split them (not one 5,000-primitive leaf, not a 5,000-deep chain) and find them.
TEST(Bvh, CoincidentCentroidsStillBuildABalancedTree) {
  std::vector<Primitive> prims;
  for (uint32_t i = 0; i < 5000; ++i) {
    prims.push_back(make(SphereShape{{1, 2, 3}, 0.5 + 0.0001 * i}, i));
  }
  const Bvh bvh(prims);
  EXPECT_LE(bvh.stats().maxDepth, 20);  // halving 5,000 down to leaves of <= 4: ~11 levels
  EXPECT_GE(bvh.stats().leaves, 5000u / 4);
  uint64_t tests = 0;
  // From the centre every sphere is hit from inside; the smallest (object 0) is nearest.
  const Found f = viaBvh(bvh, {{1, 2, 3}, {1, 0, 0}}, kMinIsectDepth, kMaxDistance, tests);
  ASSERT_TRUE(f.hit);
  EXPECT_EQ(f.object, 0u);
  EXPECT_DOUBLE_EQ(f.t, 0.5);
  // From outside, the largest (object 4999, radius 0.9999) is hit first: 10 - 0.9999.
  const Found g = viaBvh(bvh, {{-9, 2, 3}, {1, 0, 0}}, kMinIsectDepth, kMaxDistance, tests);
  ASSERT_TRUE(g.hit);
  EXPECT_EQ(g.object, 4999u);
  EXPECT_NEAR(g.t, 10 - 0.9999, 1e-12);
}

// Building on several threads gives the very tree one thread builds: the same nodes, in
// the same order, over the same primitive order. 300,000 primitives take every parallel
// path (nodes binned and partitioned by several threads, subtrees built and collapsed at the
// same time, the primitives gathered in blocks): spheres, boxes, a slab of flat ones, a
// heap with one centroid (no SAH split), and planes (unbounded) among them.
TEST(Bvh, TheTreeDoesNotDependOnTheBuildThreads) {
  SceneMaker gen(35);
  auto prims = gen.spheres(250000, 50, 0.01, 0.3);
  for (uint32_t i = 0; i < 40000; ++i) {
    const Vec3 c = gen.point(50);
    prims.push_back(make(BoxShape{{c.x, 0.5, c.z}, {c.x + 0.2, 0.5, c.z + 0.1}}, uint32_t(prims.size())));
  }
  for (uint32_t i = 0; i < 10000; ++i) prims.push_back(make(SphereShape{{1, 2, 3}, 0.1 + 1e-5 * i}, uint32_t(prims.size())));
  for (uint32_t i = 0; i < 3; ++i) {
    const auto at = prims.begin() + std::ptrdiff_t(i * 100000);
    prims.insert(at, make(PlaneShape{{0, 1, 0}, double(i)}, uint32_t(prims.size())));
  }
  const Bvh one(prims, 1);
  EXPECT_GT(one.stats().maxDepth, 6);
  for (unsigned threads : {2u, 3u, 8u}) {
    const Bvh many(prims, threads);
    ASSERT_EQ(one.nodes().size(), many.nodes().size()) << threads << " threads";
    for (size_t i = 0; i < one.nodes().size(); ++i) {
      const BvhNode &a = one.nodes()[i], &b = many.nodes()[i];
      ASSERT_EQ(0, std::memcmp(a.quad, b.quad, sizeof a.quad)) << "node " << i << ", " << threads << " threads";
      ASSERT_EQ(0, std::memcmp(a.child, b.child, sizeof a.child)) << "node " << i << ", " << threads << " threads";
      ASSERT_EQ(0, std::memcmp(a.count, b.count, sizeof a.count)) << "node " << i << ", " << threads << " threads";
      ASSERT_EQ(a.used, b.used) << "node " << i << ", " << threads << " threads";
    }
    ASSERT_EQ(one.size(), many.size());
    for (size_t i = 0; i < one.size(); ++i)
      ASSERT_EQ(one.primitive(i).object, many.primitive(i).object) << "primitive " << i << ", " << threads;
    EXPECT_EQ(one.stats().leaves, many.stats().leaves);
    EXPECT_EQ(one.stats().maxDepth, many.stats().maxDepth);
    EXPECT_EQ(one.stats().bytes, many.stats().bytes);
  }
}

// Boxes standing on y = 0, written as -0 and +0 by turns: every node's box has its min y at
// zero, with the sign of whichever zero met it first, unless the build makes every -0 a +0.
// The threads build the top nodes and the subtrees below them in different orders.
TEST(Bvh, SignedZerosGiveTheSameTreeWhateverTheThreads) {
  SceneMaker gen(36);
  std::vector<Primitive> prims;
  for (uint32_t i = 0; i < 200000; ++i) {
    const Vec3 c = gen.point(50);
    prims.push_back(make(BoxShape{{c.x, i % 3 ? -0.0 : 0.0, c.z}, {c.x + 0.1, 0.2, c.z + 0.1}}, i));
  }
  const Bvh one(prims, 1);
  for (unsigned threads : {2u, 8u}) {
    const Bvh many(prims, threads);
    ASSERT_EQ(one.nodes().size(), many.nodes().size());
    for (size_t i = 0; i < one.nodes().size(); ++i)
      ASSERT_EQ(0, std::memcmp(one.nodes()[i].quad, many.nodes()[i].quad, sizeof one.nodes()[i].quad))
          << "node " << i << ", " << threads << " threads";
  }
}

// Packets must give every ray exactly the answer the single-ray queries give, for
// narrow packets (a pixel's samples) and wide ones (rays in every direction).
TEST(BvhPacket, ClosestMatchesSingleRays) {
  SceneMaker gen(31);
  auto prims = gen.spheres(500, 8, 0.05, 0.8);
  prims.push_back(make(PlaneShape{normalize(Vec3{0.1, 1, 0}), -9}, 9999));
  const Bvh bvh(prims);
  for (int packet = 0; packet < 300; ++packet) {
    const Vec3 origin = gen.point(12);
    const Vec3 axis = gen.direction();
    const double spread = packet % 3 == 0 ? 2.0 : packet % 3 == 1 ? 0.01 : 1e-6;
    const int count = 1 + packet % kMaxPacket;
    std::vector<Ray> rays;
    for (int k = 0; k < count; ++k) rays.push_back({origin, normalize(axis + gen.direction() * spread)});
    std::vector<std::optional<ClosestHit>> got(static_cast<size_t>(count));
    uint64_t tests = 0;
    bvh.closestPacket(rays.data(), count, 1e-4, 1e7, got.data(), tests);
    for (int k = 0; k < count; ++k) {
      const auto want = bvh.closest(rays[size_t(k)], 1e-4, 1e7, tests);
      ASSERT_EQ(want.has_value(), got[size_t(k)].has_value()) << "packet " << packet << " ray " << k;
      if (want) {
        EXPECT_EQ(want->hit.t, got[size_t(k)]->hit.t);
        EXPECT_EQ(want->primitive, got[size_t(k)]->primitive);
      }
    }
  }
}

// Rays from their own origins (a packet's reflected rays) get every live ray exactly the
// answer closest() gives it alone, among spheres, boxes (tested ray by ray) and a plane,
// whether the rays are nearly parallel or scattered; the lanes left out are not touched.
TEST(BvhPacket, SpreadClosestMatchesSingleRays) {
  SceneMaker gen(37);
  auto prims = gen.spheres(400, 8, 0.05, 0.8);
  for (uint32_t i = 0; i < 60; ++i) {
    const Vec3 c = gen.point(8);
    prims.push_back(make(BoxShape{c, c + Vec3(0.3, 0.5, 0.2)}, 5000 + i));
  }
  prims.push_back(make(PlaneShape{normalize(Vec3{0.1, 1, 0}), -9}, 9999));
  const Bvh bvh(prims);
  int hits = 0, misses = 0;
  for (int packet = 0; packet < 300; ++packet) {
    const Vec3 centre = gen.point(10), axis = gen.direction();
    const double spread = packet % 3 == 0 ? 2.0 : packet % 3 == 1 ? 0.01 : 1e-6;
    const double apart = packet % 2 == 0 ? 0.05 : 3.0;  // how far apart the origins are
    const int count = 1 + packet % kMaxPacket;
    const uint64_t all = count == 64 ? ~uint64_t(0) : (uint64_t(1) << count) - 1;
    const uint64_t live = packet % 4 == 0 ? all & 0x5555555555555555u : all;
    PacketRays rays;
    for (int k = 0; k < count; ++k)
      rays.set(k, centre + gen.direction() * apart, normalize(axis + gen.direction() * spread));
    rays.finish(count);
    std::vector<std::optional<ClosestHit>> got(kMaxPacket, ClosestHit{ShapeHit{-1, 0, 0, 0}, 12345});
    uint64_t tests = 0;
    bvh.closestSpread(rays, live, 1e-4, 1e7, got.data(), tests);
    for (int k = 0; k < count; ++k) {
      if (!(live >> k & 1u)) {
        ASSERT_TRUE(got[size_t(k)] && got[size_t(k)]->primitive == 12345) << "lane " << k << " was written";
        continue;
      }
      const auto want = bvh.closest(rays.ray(k), 1e-4, 1e7, tests);
      ASSERT_EQ(want.has_value(), got[size_t(k)].has_value()) << "packet " << packet << " ray " << k;
      if (want) {
        EXPECT_EQ(want->hit.t, got[size_t(k)]->hit.t);
        EXPECT_EQ(want->hit.part, got[size_t(k)]->hit.part);
        EXPECT_EQ(want->primitive, got[size_t(k)]->primitive);
      }
      (want ? hits : misses)++;
    }
  }
  EXPECT_GT(hits, 1000);  // both answers are well exercised
  EXPECT_GT(misses, 1000);
}

// How many segments of the packets checked below got each answer.
struct Answers {
  int blocked = 0, clear = 0, transparent = 0;
};

// occlusionPacket over `segments` (which all end at `apex`, tMin 1e-3) gives each segment
// the answer occlusion() gives it alone; the answers are counted in `answers`.
void expectPacketMatchesSingles(const Bvh& bvh, const Vec3& apex, const std::vector<Ray>& segments,
                                const std::vector<double>& tMax, int packet, Answers& answers) {
  const int count = int(segments.size());
  std::vector<Occlusion> got(static_cast<size_t>(count));
  std::vector<uint32_t> blocker(static_cast<size_t>(count));
  uint64_t tests = 0;
  bvh.occlusionPacket(apex, segments.data(), tMax.data(), count, 1e-3, got.data(), blocker.data(), tests);
  for (int k = 0; k < count; ++k) {
    uint32_t b = 0;
    const Occlusion want = bvh.occlusion(segments[size_t(k)], 1e-3, tMax[size_t(k)], tests, b);
    ASSERT_EQ(int(want), int(got[size_t(k)])) << "packet " << packet << " segment " << k;
    answers.blocked += want == Occlusion::Blocked;
    answers.clear += want == Occlusion::Clear;
    answers.transparent += want == Occlusion::Transparent;
  }
}

TEST(BvhPacket, OcclusionMatchesSingleSegments) {
  SceneMaker gen(32);
  auto prims = gen.spheres(400, 8, 0.05, 0.8);
  prims.push_back(make(PlaneShape{Vec3{0, 1, 0}, -9}, 9999));
  for (size_t i = 0; i < prims.size(); i += 7) prims[i].opaque = false;  // some see-through
  const Bvh bvh(prims);
  Answers answers;
  for (int packet = 0; packet < 300; ++packet) {
    const Vec3 apex = gen.point(12);
    const Vec3 centre = gen.point(9);
    const double spread = packet % 3 == 0 ? 6.0 : packet % 3 == 1 ? 0.05 : 1e-7;
    const int count = 1 + packet % kMaxPacket;
    std::vector<Ray> segments;
    std::vector<double> tMax;
    for (int k = 0; k < count; ++k) {
      const Vec3 start = centre + gen.point(spread);
      const Vec3 to = apex - start;
      const double dist = length(to);
      segments.push_back({start, to / dist});
      tMax.push_back(dist - 1e-3);
    }
    ASSERT_NO_FATAL_FAILURE(expectPacketMatchesSingles(bvh, apex, segments, tMax, packet, answers));
  }
  // The cases were all exercised.
  EXPECT_GT(answers.blocked, 100);
  EXPECT_GT(answers.clear, 100);
  EXPECT_GT(answers.transparent, 10);
}

// Segments from one point toward the samples of an area light (different ends), some of
// them left out of `live`: every live one gets the answer occlusion() gives it alone, and
// the others come out Clear.
TEST(BvhPacket, OcclusionFromAPointMatchesSingleSegments) {
  SceneMaker gen(36);
  auto prims = gen.spheres(400, 8, 0.05, 0.8);
  prims.push_back(make(PlaneShape{Vec3{0, 1, 0}, -9}, 9999));
  for (size_t i = 0; i < prims.size(); i += 7) prims[i].opaque = false;  // some see-through
  const Bvh bvh(prims);
  Answers answers;
  for (int packet = 0; packet < 300; ++packet) {
    const Vec3 origin = gen.point(9);
    const Vec3 light = gen.point(12);
    // A patch of light the size of a lamp, of the scene, or of a few ulps.
    const double spread = packet % 3 == 0 ? 6.0 : packet % 3 == 1 ? 0.3 : 1e-12;
    const int count = 1 + packet % 16;
    PacketRays lanes;
    alignas(32) double tMax[kMaxPacket];
    uint64_t live = 0;
    std::vector<Ray> segments;
    for (int k = 0; k < count; ++k) {
      const Vec3 to = light + gen.point(spread) - origin;
      const double dist = length(to);
      segments.push_back({origin, to / dist});
      tMax[k] = dist - 1e-3;
      live |= uint64_t((k + packet) % 5 != 0) << k;
      lanes.set(k, origin, segments.back().dir);
    }
    lanes.finish(count);
    for (int k = count; k < lanes.groups * 4; ++k) tMax[k] = -INFINITY;
    Occlusion got[kMaxPacket];
    uint32_t blocker[kMaxPacket];
    uint64_t tests = 0;
    bvh.occlusionPacketFromPoint(lanes, tMax, 1e-3, live, got, blocker, tests);
    for (int k = 0; k < count; ++k) {
      uint32_t b = 0;
      const Occlusion want =
          (live >> k & 1) ? bvh.occlusion(segments[size_t(k)], 1e-3, tMax[k], tests, b) : Occlusion::Clear;
      ASSERT_EQ(int(want), int(got[k])) << "packet " << packet << " segment " << k;
      if (want == Occlusion::Blocked) {
        // The blocker it names is opaque and really blocks the segment.
        ASSERT_TRUE(bvh.intersect(blocker[k], segments[size_t(k)], 1e-3, tMax[k]).has_value());
      }
      answers.blocked += want == Occlusion::Blocked;
      answers.clear += want == Occlusion::Clear;
      answers.transparent += want == Occlusion::Transparent;
    }
  }
  EXPECT_GT(answers.blocked, 100);
  EXPECT_GT(answers.clear, 100);
  EXPECT_GT(answers.transparent, 10);
}

// A packet query's note of a Transparent segment's nearest see-through hit is the first
// step of its see-through walk: closest(..., skipNoShadow) over the same interval, the same
// primitive at the same distance. Segments from one point (area-light samples) and toward
// one light (a packet's shadows), among see-through spheres and a see-through plane that
// the segments cross (a tie between the plane and a sphere goes to the plane).
TEST(BvhPacket, TransparentSegmentsNoteTheFirstStepOfTheirWalk) {
  SceneMaker gen(38);
  auto prims = gen.spheres(300, 8, 0.05, 0.8);
  prims.push_back(make(PlaneShape{Vec3{0, 1, 0}, 0.5}, 9998));
  prims.back().opaque = false;
  prims.push_back(make(PlaneShape{Vec3{0, 1, 0}, -9}, 9999));
  for (size_t i = 0; i < prims.size(); i += 3) prims[i].opaque = false;  // a third see-through
  const Bvh bvh(prims);
  int transparent = 0, onPlane = 0;
  for (int packet = 0; packet < 400; ++packet) {
    const bool fromPoint = packet % 2 == 0;
    const Vec3 fixed = gen.point(fromPoint ? 9 : 12);
    const int count = 1 + packet % (fromPoint ? 16 : kMaxPacket);
    PacketRays lanes;
    alignas(32) double tMax[kMaxPacket];
    std::vector<Ray> segments;
    for (int k = 0; k < count; ++k) {
      const Vec3 other = (fromPoint ? gen.point(12) : fixed + gen.point(packet % 4 == 1 ? 0.5 : 6.0));
      const Vec3 start = fromPoint ? fixed : other, end = fromPoint ? other : fixed;
      const double dist = length(end - start);
      segments.push_back({start, (end - start) / dist});
      tMax[k] = dist - 1e-3;
      lanes.set(k, start, segments.back().dir);
    }
    lanes.finish(count);
    for (int k = count; k < lanes.groups * 4; ++k) tMax[k] = -INFINITY;
    const uint64_t live = count == 64 ? ~uint64_t(0) : (uint64_t(1) << count) - 1;
    Occlusion got[kMaxPacket];
    uint32_t blocker[kMaxPacket];
    PacketNearest nearest;
    uint64_t tests = 0;
    if (fromPoint)
      bvh.occlusionPacketFromPoint(lanes, tMax, 1e-3, live, got, blocker, tests, &nearest);
    else
      bvh.occlusionPacket(fixed, lanes, tMax, 1e-3, live, got, blocker, tests, &nearest);
    for (int k = 0; k < count; ++k) {
      if (got[k] != Occlusion::Transparent) continue;
      ++transparent;
      const auto want = bvh.closest(segments[size_t(k)], 1e-3, tMax[k], tests, /*skipNoShadow=*/true);
      ASSERT_TRUE(want.has_value()) << "packet " << packet << " segment " << k;
      EXPECT_EQ(want->primitive, nearest.hit[k].primitive) << "packet " << packet << " segment " << k;
      EXPECT_EQ(want->hit.t, nearest.hit[k].hit.t) << "packet " << packet << " segment " << k;
      EXPECT_EQ(want->hit.part, nearest.hit[k].hit.part);
      onPlane += bvh.plane(want->primitive) != nullptr;
    }
  }
  EXPECT_GT(transparent, 200);
  EXPECT_GT(onPlane, 20);
}

// Segments left out of `live` (as the tracer leaves out its unlit rays, in place) are
// reported Clear, and the others get the answers they get alone.
TEST(BvhPacket, OcclusionTestsOnlyTheLiveSegments) {
  SceneMaker gen(34);
  const Bvh bvh(gen.spheres(400, 8, 0.05, 0.8));
  int blocked = 0;
  for (int packet = 0; packet < 200; ++packet) {
    const Vec3 apex = gen.point(12);
    const Vec3 centre = gen.point(9);
    const int count = 1 + packet % kMaxPacket;
    PacketRays lanes;
    alignas(32) double tMax[kMaxPacket];
    uint64_t live = 0;
    std::vector<Ray> segments;
    for (int k = 0; k < count; ++k) {
      const Vec3 start = centre + gen.point(packet % 2 == 0 ? 2.0 : 0.05);
      const double dist = length(apex - start);
      segments.push_back({start, (apex - start) / dist});
      const bool in = (k + packet) % 3 != 0;
      live |= uint64_t(in) << k;
      lanes.set(k, in ? start : Vec3(NAN), segments.back().dir);
      tMax[k] = in ? dist - 1e-3 : -INFINITY;
    }
    lanes.finish(count);
    for (int k = count; k < lanes.groups * 4; ++k) tMax[k] = -INFINITY;
    std::vector<Occlusion> got(static_cast<size_t>(count), Occlusion::Transparent);
    std::vector<uint32_t> blocker(static_cast<size_t>(count));
    uint64_t tests = 0;
    bvh.occlusionPacket(apex, lanes, tMax, 1e-3, live, got.data(), blocker.data(), tests);
    for (int k = 0; k < count; ++k) {
      uint32_t b = 0;
      const Occlusion want = (live >> k & 1u) != 0 ? bvh.occlusion(segments[size_t(k)], 1e-3, tMax[k], tests, b)
                                                   : Occlusion::Clear;
      ASSERT_EQ(int(want), int(got[size_t(k)])) << "packet " << packet << " segment " << k;
      blocked += want == Occlusion::Blocked;
    }
  }
  EXPECT_GT(blocked, 100);
}

// Packets that mix segments starting exactly on a plane (as a floor's shadow segments do),
// on the light's side of it, and on the far side, with the light above, below and on the
// plane, tilted or not: each segment gets the answer it gets alone.
TEST(BvhPacket, OcclusionMatchesSingleSegmentsStartingOnAPlane) {
  SceneMaker gen(35);
  Answers answers;
  int onPlane = 0, grazing = 0;
  for (const Vec3& normal : {Vec3{0, 1, 0}, normalize(Vec3{0.2, 1, -0.3})}) {
    const double distance = -2;
    auto prims = gen.spheres(60, 8, 0.05, 0.6);
    prims.push_back(make(PlaneShape{normal, distance}, 9999));
    const Bvh bvh(prims);
    for (int packet = 0; packet < 300; ++packet) {
      // The light 5 above the plane, 5 below it, on it, or a hair above it (where segments
      // from just below the plane graze it and cross it far from their start).
      const double heights[] = {5.0, -5.0, 0.0, 0.01};
      const double height = heights[packet % 4];
      Vec3 apex = gen.point(6);
      apex = apex + normal * (distance + height - dot(normal, apex));
      const Vec3 centre = gen.point(6);
      const int count = 1 + packet % kMaxPacket;
      std::vector<Ray> segments;
      std::vector<double> tMax;
      for (int k = 0; k < count; ++k) {
        Vec3 start = centre + gen.point(packet % 2 == 0 ? 3.0 : 0.01);
        // On the plane as nearly as rounding lets it be, 0.5 to one side or the other, or
        // a hair below it.
        const double offsets[] = {0.0, 0.5, -0.5, -1e-4};
        const double to = offsets[k % 4];
        start = start + normal * (distance + to - dot(normal, start));
        if (normal.x == 0) start.y = distance + to;  // exactly, for the level plane
        onPlane += dot(normal, start) == distance;
        grazing += to == -1e-4 && height == 0.01;
        const double dist = length(apex - start);
        if (dist < 0.01) continue;
        segments.push_back({start, (apex - start) / dist});
        tMax.push_back(dist - 1e-3);
      }
      if (segments.empty()) continue;
      ASSERT_NO_FATAL_FAILURE(expectPacketMatchesSingles(bvh, apex, segments, tMax, packet, answers));
    }
  }
  EXPECT_GT(answers.blocked, 1000);
  EXPECT_GT(answers.clear, 1000);
  EXPECT_GT(onPlane, 1000);
  EXPECT_GT(grazing, 500);
}

// The cone test is conservative: whenever one of its rays enters a box, it says so.
TEST(BvhPacket, ConeNeverMissesABoxARayHits) {
  SceneMaker gen(33);
  int hits = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const Vec3 apex = gen.point(5);
    const Vec3 axis = gen.direction();
    std::vector<Vec3> dirs;
    for (int k = 0; k < 8; ++k) dirs.push_back(normalize(axis + gen.direction() * 0.2));
    const PacketCone cone(apex, [&](int k) { return dirs[size_t(k)]; }, 8, 0.0);
    Bounds box;
    box.extend(gen.point(6));
    box.extend(gen.point(6));
    bool any = false;
    for (const Vec3& d : dirs) {  // exact enough: a dense march along each ray
      for (double t = 0; t < 30 && !any; t += 0.01) {
        const Vec3 p = apex + d * t;
        any = p.x >= box.lo.x && p.x <= box.hi.x && p.y >= box.lo.y && p.y <= box.hi.y && p.z >= box.lo.z &&
              p.z <= box.hi.z;
      }
    }
    if (any) {
      ++hits;
      ASSERT_LT(cone.entry(box, 30), INFINITY) << "trial " << trial;
    }
    // The four-box form the traversal uses answers as entry() does, box by box: the box
    // sits in slot trial % kBvhWidth of a node whose other slots hold unrelated boxes.
    BvhNode node;
    const int slot = trial % kBvhWidth;
    for (int c = 0; c < kBvhWidth; ++c) {
      Bounds other;
      other.extend(gen.point(6));
      other.extend(gen.point(6));
      node.setChild(c, c == slot ? box : other, 0, 1);
    }
    unsigned mask = 0;
    double enter[kBvhWidth];
    for (int q = 0; q < kBvhQuads; ++q)
      mask |= cone.entries(node.quad[q].lo, node.quad[q].hi, 30, enter + 4 * q) << (4 * q);
    for (int c = 0; c < kBvhWidth; ++c) {
      const double one = cone.entry(node.childBounds(c), 30);
      ASSERT_EQ((mask >> c & 1u) != 0, one < INFINITY) << "trial " << trial << " slot " << c;
      if (one < INFINITY) {
        ASSERT_EQ(enter[c], one) << "trial " << trial << " slot " << c;
      }
    }
    if (any) {
      ASSERT_TRUE(mask >> slot & 1u) << "trial " << trial;
    }
  }
  EXPECT_GT(hits, 1000);
}

}  // namespace
}  // namespace pvrt
