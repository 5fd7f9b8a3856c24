// A light buffer must be an invisible speed-up too: for every shadow segment that ends at
// its light, it gives the answer the BVH's occlusion query gives (blocked, see-through or
// clear), and the nearest primitive that casts shadows that its closest query gives,
// whatever the light's place: outside the scene, among the primitives, inside one.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include <filesystem>

#include "accel/bvh.h"
#include "accel/light_buffer.h"
#include "accel/packet_rays.h"
#include "generate/random_scene.h"
#include "geometry/primitive.h"
#include "random_geometry.h"
#include "render/renderer.h"
#include "render/scene.h"
#include "scene/xml_loader.h"

namespace pvrt {
namespace {

constexpr double kTol = 1e-3;  // the shadow tolerance kept from both ends of a segment

class Maker : public test::RandomGeometry {
 public:
  using RandomGeometry::RandomGeometry;

  // `n` spheres in [-half, half]^3: every seventh see-through, every eleventh no_shadow,
  // and a floor plane.
  std::vector<Primitive> scene(size_t n, double half, double rMin, double rMax) {
    std::vector<Primitive> prims;
    for (size_t i = 0; i < n; ++i) {
      Primitive p;
      p.shape = SphereShape{point(half), uniform(rMin, rMax)};
      p.object = uint32_t(i);
      p.opaque = i % 7 != 0;
      p.noShadow = i % 11 == 0;
      prims.push_back(p);
    }
    Primitive floor;
    floor.shape = PlaneShape{{0, 1, 0}, -half};
    floor.object = uint32_t(n);
    prims.push_back(floor);
    return prims;
  }
};

struct Answer {
  Occlusion viaTree, viaBuffer;
  Occlusion viaCell;  // from the cell of the direction from the light to the surface point (and walkViaCell)
  // The crossings of a walk along the segment, each step starting at the last crossing
  // (as the tracer walks see-through shadows): by the tree's closest query, and among the
  // buffer's candidates for the walk.
  std::vector<ClosestHit> walkViaTree, walkViaBuffer, walkViaCell;
  // viaCell again, noting the nearest see-through hit (meaningful when Transparent).
  Occlusion viaCellNoting;
  ClosestHit noted;
  // viaCellNoting again, listing the walk's candidates as it goes, and shadowCandidates'
  // list from the cell (meaningful when Transparent).
  Occlusion viaCellListing;
  ClosestHit listingNoted;
  std::vector<uint32_t> listed, fromCell;
};

// Up to 8 steps of such a walk from `segment` toward a light `dist` away; `nearest` answers
// a step.
template <class Nearest>
std::vector<ClosestHit> walk(Ray segment, double dist, Nearest&& nearest) {
  std::vector<ClosestHit> crossings;
  for (int k = 0; k < 8; ++k) {
    const std::optional<ClosestHit> hit = nearest(segment, dist);
    if (!hit) break;
    crossings.push_back(*hit);
    segment.origin = segment.origin + segment.dir * hit->hit.t;
    dist -= hit->hit.t;
  }
  return crossings;
}

// The segment from a point on the surface of primitive `i` (a sphere) toward the light,
// started a hair off the surface, as the tracer starts it; both queries' answers.
Answer shadowOf(const Bvh& bvh, const LightBuffer& buffer, uint32_t i, const Vec3& onSphere, double shift) {
  const SphereShape s = std::get<SphereShape>(bvh.primitive(i).shape);
  const Vec3 normal = normalize(onSphere - s.center);
  const Vec3 toLight = buffer.light() - onSphere;
  const double dist = length(toLight);
  const Vec3 l = toLight / dist;
  const Ray segment{onSphere + normal * shift, l};
  uint64_t tests = 0;
  uint32_t blocker = 0;
  Answer a;
  a.viaTree = bvh.occlusion(segment, kTol, dist - kTol, tests, blocker);
  a.viaBuffer = bvh.occlusionToLight(buffer, segment, kTol, dist - kTol, (dist + shift) * (1 + 1e-9), tests, blocker);
  // As the tracer asks it: from the cell of the direction from the light to the surface
  // point, found before the segment's direction was.
  const int cell = buffer.cellIndexOf(onSphere - buffer.light());
  EXPECT_GE(cell, 0);
  a.viaCell = bvh.occlusionToLight(buffer, cell, segment, kTol, dist - kTol, (dist + shift) * (1 + 1e-9), tests,
                                   blocker);
  a.viaCellNoting = bvh.occlusionToLight(buffer, cell, segment, kTol, dist - kTol, (dist + shift) * (1 + 1e-9),
                                         tests, blocker, a.noted);
  a.walkViaTree = walk(segment, dist, [&](const Ray& step, double left) {
    return bvh.closest(step, kTol, left - kTol, tests, /*skipNoShadow=*/true);
  });
  std::vector<uint32_t> candidates;
  const double drift = LightBuffer::kMargin * kTol;  // the tracer's bound (Tracer::orderedTransmittance)
  EXPECT_TRUE(bvh.shadowCandidates(buffer, segment, dist, (dist + shift) * (1 + 1e-9), drift, candidates));
  a.walkViaBuffer = walk(segment, dist, [&](const Ray& step, double left) {
    return bvh.closestAmong(candidates, step, kTol, left - kTol, tests);
  });
  std::vector<uint32_t>& fromCell = a.fromCell;
  bvh.shadowCandidates(buffer, cell, segment, dist, (dist + shift) * (1 + 1e-9), drift, fromCell);
  a.walkViaCell = walk(segment, dist, [&](const Ray& step, double left) {
    return bvh.closestAmong(fromCell, step, kTol, left - kTol, tests);
  });
  a.viaCellListing = bvh.occlusionToLight(buffer, cell, segment, kTol, dist - kTol, (dist + shift) * (1 + 1e-9), tests,
                                          blocker, a.listingNoted, dist, drift, a.listed);
  return a;
}

void expectBufferAgrees(const std::vector<Primitive>& prims, const Vec3& light, Maker& gen, int segments,
                        int* blocked = nullptr, size_t* crossed = nullptr, int* seeThrough = nullptr) {
  const Bvh bvh(prims);
  const LightBuffer buffer(light, bvh.occluders());
  int count = 0;
  size_t crossings = 0;
  for (int k = 0; k < segments; ++k) {
    const uint32_t i = uint32_t(gen.uniform(0, double(prims.size() - 1)));  // a sphere, not the floor
    const SphereShape s = std::get<SphereShape>(bvh.primitive(i).shape);
    const Vec3 onSphere = s.center + gen.direction() * s.radius;
    if (length(buffer.light() - onSphere) <= 2 * kTol) continue;
    const Answer a = shadowOf(bvh, buffer, i, onSphere, 1e-12);
    ASSERT_EQ(int(a.viaBuffer), int(a.viaTree)) << "segment " << k << " from sphere " << i;
    ASSERT_EQ(int(a.viaCell), int(a.viaTree)) << "segment " << k << " from sphere " << i;
    ASSERT_EQ(a.walkViaBuffer.size(), a.walkViaTree.size()) << "segment " << k;
    ASSERT_EQ(a.walkViaCell.size(), a.walkViaTree.size()) << "segment " << k;
    for (size_t c = 0; c < a.walkViaTree.size(); ++c) {
      EXPECT_EQ(a.walkViaBuffer[c].primitive, a.walkViaTree[c].primitive) << "segment " << k << " crossing " << c;
      EXPECT_EQ(a.walkViaBuffer[c].hit.t, a.walkViaTree[c].hit.t) << "segment " << k << " crossing " << c;
      EXPECT_EQ(a.walkViaCell[c].primitive, a.walkViaTree[c].primitive) << "segment " << k << " crossing " << c;
      EXPECT_EQ(a.walkViaCell[c].hit.t, a.walkViaTree[c].hit.t) << "segment " << k << " crossing " << c;
    }
    // A see-through answer notes the walk's first crossing, as its first step finds it.
    ASSERT_EQ(int(a.viaCellNoting), int(a.viaCell)) << "segment " << k;
    if (a.viaCell == Occlusion::Transparent) {
      if (seeThrough) ++*seeThrough;
      ASSERT_FALSE(a.walkViaCell.empty()) << "segment " << k;
      EXPECT_EQ(a.noted.primitive, a.walkViaCell[0].primitive) << "segment " << k;
      EXPECT_EQ(a.noted.hit.t, a.walkViaCell[0].hit.t) << "segment " << k;
    }
    // Listing the walk's candidates on the way changes neither the answer nor the note, and
    // a see-through answer lists exactly what shadowCandidates lists from the cell.
    ASSERT_EQ(int(a.viaCellListing), int(a.viaCell)) << "segment " << k;
    if (a.viaCell == Occlusion::Transparent) {
      EXPECT_EQ(a.listingNoted.primitive, a.noted.primitive) << "segment " << k;
      EXPECT_EQ(a.listingNoted.hit.t, a.noted.hit.t) << "segment " << k;
      EXPECT_EQ(a.listed, a.fromCell) << "segment " << k;
    }
    crossings += a.walkViaTree.size();
    count += a.viaTree == Occlusion::Blocked;
  }
  if (blocked) *blocked = count;
  if (crossed) *crossed = crossings;
}

// A dense cloud lit from outside: most segments are blocked, some see-through.
TEST(LightBuffer, AgreesWithTheTreeForALightOutsideTheScene) {
  Maker gen(3);
  const auto prims = gen.scene(3000, 10, 0.1, 0.6);
  int blocked = 0;
  size_t crossed = 0;
  int seeThrough = 0;
  expectBufferAgrees(prims, {3, 40, -7}, gen, 20000, &blocked, &crossed, &seeThrough);
  EXPECT_GT(seeThrough, 500);  // answers that note their walk's first crossing
  EXPECT_GT(blocked, 2000);
  EXPECT_LT(blocked, 19000);
  EXPECT_GT(crossed, 40000u);  // walks of several steps, as through glass
}

// A light among the spheres sees them on every face of its cube, and close.
TEST(LightBuffer, AgreesWithTheTreeForALightAmongThePrimitives) {
  Maker gen(5);
  const auto prims = gen.scene(2000, 10, 0.1, 0.8);
  for (const Vec3 light : {Vec3{0.5, 0.25, -0.125}, Vec3{9.5, -9.5, 0}, Vec3{0, 0, 0}})
    expectBufferAgrees(prims, light, gen, 8000);
}

// A light inside a sphere (and so inside its box): that sphere is tested for every
// segment, and blocks every one from outside it.
TEST(LightBuffer, APrimitiveAroundTheLightIsTestedEverywhere) {
  Maker gen(9);
  auto prims = gen.scene(500, 10, 0.1, 0.5);
  Primitive shell;
  shell.shape = SphereShape{{1, 2, 3}, 2};
  shell.object = 999;
  prims.push_back(shell);
  const Bvh bvh(prims);
  const LightBuffer buffer({1.5, 2, 3}, bvh.occluders());
  ASSERT_EQ(buffer.everywhere().size(), 1u);
  expectBufferAgrees(prims, {1.5, 2, 3}, gen, 4000);
}

// A light with more primitives around it than LightBuffer::kMaxEverywhere gets no buffer,
// wherever in the list they come (here after a primitive the cells list).
TEST(LightBuffer, TooManyPrimitivesAroundTheLightLeaveItToTheTree) {
  std::vector<LightBuffer::Occluder> boxes{{{{1, 1, 1}, {2, 2, 2}}}};
  for (size_t k = 0; k < LightBuffer::kMaxEverywhere; ++k) boxes.push_back({{{-1, -1, -1}, {1, 1, 1}}});
  EXPECT_TRUE(LightBuffer({0, 0, 0}, boxes).valid());  // at the limit
  boxes.push_back({{{-2, -2, -2}, {2, 2, 2}}});
  const LightBuffer over({0, 0, 0}, boxes);
  EXPECT_FALSE(over.valid());
  EXPECT_TRUE(over.everywhere().empty());
}

// Cells are sized for the typical primitive; when many primitives are far bigger, their
// lists would outgrow LightBuffer::kEntriesPerPrimitive entries a primitive (and a fixed
// allowance), and the light gets no buffer.
TEST(LightBuffer, PrimitivesSpanningManyCellsLeaveItToTheTree) {
  const auto scene = [](int big) {
    std::vector<LightBuffer::Occluder> boxes;
    test::RandomGeometry random(17);
    for (int k = 0; k < 2 * big + 1; ++k) {
      // In front of the light along +z, 10 away: tiny ones (which set the cells' size), and
      // big ones 11 to 13 cells across (fewer than LightBuffer::kCrowded cells in all).
      const double half = k % 2 == 0 ? 0.001 : 0.4;
      const Vec3 c{random.uniform(-2, 2), random.uniform(-2, 2), 10};
      boxes.push_back({{c - Vec3(half), c + Vec3(half)}});
    }
    return boxes;
  };
  const LightBuffer few({0, 0, 0}, scene(100)), many({0, 0, 0}, scene(800));
  EXPECT_EQ(few.resolution(), 256);
  EXPECT_TRUE(few.everywhere().empty());
  EXPECT_TRUE(few.valid());
  EXPECT_GT(few.entries(), 100u * 100u);  // the big ones are listed in a hundred cells or more
  EXPECT_FALSE(many.valid());
}

// A box the buffer cannot place (a NaN bound) is tested for every segment, as the BVH's
// box test lets it through too.
TEST(LightBuffer, ABoxWithANanBoundIsTestedEverywhere) {
  const std::vector<LightBuffer::Occluder> boxes{
      {{{1, 1, 1}, {2, 2, 2}}}, {{{NAN, 1, 1}, {2, 2, 2}}}, {{{-3, -3, 5}, {-2, -2, NAN}}}};
  const LightBuffer buffer({0, 0, 0}, boxes);
  ASSERT_TRUE(buffer.valid());
  ASSERT_EQ(buffer.everywhere().size(), 2u);
  EXPECT_EQ(buffer.everywhere()[0], 1u);
  EXPECT_EQ(buffer.everywhere()[1], 2u);
}

// Segments whose direction lies on the edges and corners between the cube's faces.
TEST(LightBuffer, AgreesOnTheEdgesBetweenFaces) {
  std::vector<Primitive> prims;
  const Vec3 light{0, 0, 0};
  uint32_t id = 0;
  for (const Vec3 d : {Vec3{1, 1, 0}, Vec3{1, -1, 0}, Vec3{0, 1, 1}, Vec3{-1, 0, 1}, Vec3{1, 1, 1}, Vec3{-1, -1, -1},
                       Vec3{1, 0, 0}, Vec3{0, 0, -1}}) {
    Primitive p;
    p.shape = SphereShape{normalize(d) * 5, 0.5};
    p.object = id++;
    prims.push_back(p);
    Primitive behind;  // the surface point that a segment along d leaves from
    behind.shape = SphereShape{normalize(d) * 9, 0.5};
    behind.object = id++;
    prims.push_back(behind);
  }
  const Bvh bvh(prims);
  const LightBuffer buffer(light, bvh.occluders());
  for (uint32_t i = 0; i < bvh.size(); ++i) {
    const SphereShape s = std::get<SphereShape>(bvh.primitive(i).shape);
    if (length(s.center) < 7) continue;
    // The point of the far sphere that faces the light exactly: its segment runs along
    // the edge or corner direction, through the near sphere.
    const Vec3 onSphere = s.center - normalize(s.center) * s.radius;
    const Answer a = shadowOf(bvh, buffer, i, onSphere, 1e-12);
    EXPECT_EQ(a.viaTree, Occlusion::Blocked);
    EXPECT_EQ(a.viaBuffer, Occlusion::Blocked);
  }
}

// Segments that pass just inside or just outside a sphere's silhouette as the light sees
// it: the cells a sphere is listed in (its cone of directions, not only its box's
// footprint) must hold every direction that meets it. Narrowing the cones by 2% fails this.
TEST(LightBuffer, AgreesOnSegmentsThatGrazeSpheres) {
  Maker gen(17);
  const Vec3 light{0.3, 12, -0.2};
  const auto prims = gen.scene(400, 10, 0.2, 1.2);
  const Bvh bvh(prims);
  const LightBuffer buffer(light, bvh.occluders());
  ASSERT_TRUE(buffer.valid());
  int blocked = 0, clear = 0;
  for (int k = 0; k < 40000; ++k) {
    const uint32_t i = uint32_t(gen.uniform(0, double(prims.size() - 1)));
    const SphereShape s = std::get<SphereShape>(bvh.primitive(i).shape);
    const Vec3 c = s.center - light;
    const double d = length(c);
    if (d <= 2 * s.radius) continue;
    // A direction from the light at angle theta from the centre's: inside the silhouette
    // by up to 1e-3 of its angle, or outside by as much.
    const Vec3 axis = c / d;
    const Vec3 side = normalize(cross(axis, gen.direction()));
    const double theta = std::asin(s.radius / d) * (1 + gen.uniform(-1e-3, 1e-3));
    const Vec3 dir = axis * std::cos(theta) + side * std::sin(theta);
    const Vec3 from = light + dir * (d + 2 * s.radius);  // beyond the sphere
    const double dist = length(light - from);
    const Ray segment{from, (light - from) / dist};
    uint64_t tests = 0;
    uint32_t blocker = 0;
    const Occlusion viaTree = bvh.occlusion(segment, kTol, dist - kTol, tests, blocker);
    const Occlusion viaBuffer =
        bvh.occlusionToLight(buffer, segment, kTol, dist - kTol, dist * (1 + 1e-9), tests, blocker);
    ASSERT_EQ(int(viaBuffer), int(viaTree)) << "segment " << k << " grazing sphere " << i;
    (viaTree == Occlusion::Clear ? clear : blocked)++;
  }
  EXPECT_GT(blocked, 10000);
  EXPECT_GT(clear, 1000);
}

// A walk's candidates leave a sphere out only where the bound on its chord does, found with a
// square root for each sphere (as shadowCandidates once did): spheres that the line passes by
// on either side of that bound, by up to 2% of it, some of them also within the cheaper bound
// that shadowCandidates tries first.
TEST(LightBuffer, ShadowCandidatesLeaveOutWhatTheChordBoundLeavesOut) {
  Maker gen(23);
  const Vec3 light{0.25, 100, -0.5};
  const Vec3 from{0, 0, 0};
  const double dist = length(light - from);
  const Ray line{from, (light - from) / dist};
  const double drift = LightBuffer::kMargin * kTol, reach = dist * (1 + 1e-9);
  // The bound for a sphere whose centre is oc from the line's origin (shadowCandidates').
  auto bound = [&](const Vec3& oc, double r) {
    const double x = length(oc) + dist;
    return -(1e-9 * (x * x + r * r) + 4 * x * drift);
  };
  std::vector<Primitive> prims;
  for (int i = 0; i < 600; ++i) {
    const double r = gen.uniform(0.05, 2), along = gen.uniform(5, 80);
    const Vec3 foot = from + line.dir * along;
    const Vec3 side = normalize(cross(line.dir, gen.direction()));
    // The chord r^2 - d^2 at a distance d = r + delta from the line is about -2 r delta.
    const double threshold = -bound(foot + side * r - from, r) / (2 * r);
    Primitive p;
    // Every tenth crosses the line, so that the segment's query answers see-through.
    const double off = i % 10 == 0 ? 0.5 * r : r + threshold * (1 + gen.uniform(-0.02, 0.02));
    p.shape = SphereShape{foot + side * off, r};
    p.object = uint32_t(i);
    p.opaque = false;
    prims.push_back(p);
  }
  const Bvh bvh(prims);
  const LightBuffer buffer(light, bvh.occluders());
  ASSERT_TRUE(buffer.valid());
  const int cell = buffer.cellIndexOf(from - light);
  ASSERT_GE(cell, 0);
  std::vector<uint32_t> expected;
  int left = 0;
  for (const LightBuffer::Entry& e : buffer.list(cell)) {
    if (e.near > reach) break;
    const SphereShape s = std::get<SphereShape>(bvh.primitive(e.primitive).shape);
    const Vec3 oc = s.center - from;
    const Vec3 perp = oc - line.dir * dot(oc, line.dir);
    if (s.radius * s.radius - dot(perp, perp) < bound(oc, s.radius)) {
      ++left;
      continue;
    }
    expected.push_back(e.primitive);
  }
  for (uint32_t i : buffer.everywhere()) expected.push_back(i);
  EXPECT_GT(left, 100);
  EXPECT_GT(expected.size(), 100u);
  std::vector<uint32_t> listed;
  bvh.shadowCandidates(buffer, cell, line, dist, reach, drift, listed);
  EXPECT_EQ(listed, expected);
  // And as the segment's query lists them on the way (every sphere is see-through).
  uint64_t tests = 0;
  uint32_t blocker = 0;
  ClosestHit nearest;
  std::vector<uint32_t> onTheWay;
  const Occlusion found = bvh.occlusionToLight(buffer, cell, line, kTol, dist - kTol, reach, tests, blocker, nearest,
                                               dist, drift, onTheWay);
  ASSERT_EQ(int(found), int(Occlusion::Transparent));
  EXPECT_EQ(onTheWay, expected);
}

// The cones cut the lists: fewer entries than the boxes' footprints alone give.
TEST(LightBuffer, SpheresAreListedByTheirCones) {
  Maker gen(19);
  const Bvh bvh(gen.scene(2000, 10, 0.1, 0.5));
  const Vec3 light{1, 25, 2};
  std::vector<LightBuffer::Occluder> boxesOnly = bvh.occluders();
  for (LightBuffer::Occluder& o : boxesOnly) o.radius = INFINITY;
  const LightBuffer withCones(light, bvh.occluders()), withBoxes(light, boxesOnly);
  EXPECT_LT(double(withCones.entries()), 0.95 * double(withBoxes.entries()));
}

// The buffer's lists: nearest first, and each primitive listed in the cell of the
// direction to its centre (or tested everywhere).
TEST(LightBuffer, ListsAreSortedAndHoldEveryPrimitive) {
  Maker gen(13);
  const auto prims = gen.scene(1000, 10, 0.1, 0.6);
  const Bvh bvh(prims);
  const std::vector<LightBuffer::Occluder> occluders = bvh.occluders();
  const Vec3 light{2, 30, 1};
  const LightBuffer buffer(light, occluders);
  EXPECT_GT(buffer.resolution(), 8);
  for (uint32_t i = 0; i < occluders.size(); ++i) {
    std::span<const LightBuffer::Entry> cell;
    ASSERT_TRUE(buffer.cell(occluders[i].box.centroid() - light, cell));
    bool found = false;
    for (size_t e = 0; e < cell.size(); ++e) {
      found |= cell[e].primitive == i;
      if (e > 0) {
        ASSERT_LE(cell[e - 1].near, cell[e].near);
        if (cell[e - 1].near == cell[e].near) {
          ASSERT_LT(cell[e - 1].primitive, cell[e].primitive);  // ties by index
        }
      }
    }
    for (uint32_t j : buffer.everywhere()) found |= j == i;
    EXPECT_TRUE(found) << "primitive " << i;
  }
  std::span<const LightBuffer::Entry> none;
  EXPECT_FALSE(buffer.cell({0, 0, 0}, none));
  EXPECT_FALSE(buffer.cell({NAN, 1, 0}, none));
}

// Whether two buffers list the same primitives in the same order in every cell.
void expectSameBuffer(const LightBuffer& a, const LightBuffer& b, const std::string& what) {
  ASSERT_EQ(a.valid(), b.valid()) << what;
  ASSERT_EQ(a.resolution(), b.resolution()) << what;
  ASSERT_EQ(a.entries(), b.entries()) << what;
  ASSERT_EQ(a.cells(), b.cells()) << what;
  for (int c = 0; a.valid() && c < int(a.cells()); ++c) {
    const auto x = a.list(c), y = b.list(c);
    ASSERT_EQ(x.size(), y.size()) << "cell " << c << ", " << what;
    for (size_t e = 0; e < x.size(); ++e) {
      ASSERT_EQ(x[e].primitive, y[e].primitive) << "cell " << c << ", " << what;
      ASSERT_EQ(x[e].near, y[e].near) << "cell " << c << ", " << what;
    }
  }
  EXPECT_EQ(std::vector<uint32_t>(a.everywhere().begin(), a.everywhere().end()),
            std::vector<uint32_t>(b.everywhere().begin(), b.everywhere().end()))
      << what;
}

// Building on several threads, and several lights together, gives the very buffers one
// thread builds a light at a time: every cell's list, and the primitives tested everywhere.
// 200,000 spheres, and boxes big enough to be tested everywhere, take every parallel path
// (blocks of primitives listed at the same time, cells filled and sorted at the same time);
// the third light, among the spheres, gets no buffer.
TEST(LightBuffer, TheBufferDoesNotDependOnTheBuildThreads) {
  Maker gen(71);
  auto prims = gen.scene(200000, 20, 0.01, 0.1);
  for (int i = 0; i < 8; ++i) {
    Primitive big;
    const Vec3 c = gen.point(20);
    big.shape = BoxShape{c - Vec3(4), c + Vec3(4)};
    big.object = uint32_t(prims.size());
    prims.insert(prims.begin() + 1000 * i, big);
  }
  const Bvh bvh(prims, 1);
  const std::vector<LightBuffer::Occluder> occluders = bvh.occluders();
  const std::vector<Vec3> lights{{2, 30, 1}, {24, 5, -3}, {0.5, 0.2, -0.3}};
  std::vector<LightBuffer> one;
  for (const Vec3& light : lights) one.emplace_back(light, occluders, 1);
  ASSERT_TRUE(one[0].valid() && one[1].valid());
  ASSERT_FALSE(one[2].valid());
  ASSERT_GT(one[0].entries(), occluders.size());
  ASSERT_FALSE(one[1].everywhere().empty());
  for (int threads : {1, 2, 3, 8}) {
    const std::vector<LightBuffer> many = LightBuffer::build(lights, occluders, threads);
    ASSERT_EQ(many.size(), lights.size());
    for (size_t k = 0; k < lights.size(); ++k)
      expectSameBuffer(one[k], many[k], "light " + std::to_string(k) + ", " + std::to_string(threads) + " threads");
  }
}

// commonCell names a cell only when every direction of the box has it, and names the
// cell of a box that is one direction.
TEST(LightBuffer, CommonCellHoldsEveryDirectionOfTheBox) {
  Maker gen(61);
  const Bvh bvh(gen.scene(300, 5, 0.05, 0.5));
  const LightBuffer buffer({0.3, 0.2, -0.1}, bvh.occluders());
  ASSERT_TRUE(buffer.valid());
  int answered = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    // Around a random direction, or around an edge or a corner between faces.
    Vec3 centre = trial % 4 == 0 ? Vec3{1.0, trial % 8 == 0 ? -1.0 : 1.0, gen.uniform(-1, 1)} : gen.direction();
    if (trial % 16 == 1) centre = {-1, 1, 1};
    centre = centre * gen.uniform(0.01, 100);
    const double spread = length(centre) * std::pow(10.0, -double(gen.pick(9)));
    const Vec3 a = centre + gen.point(spread), b = centre + gen.point(spread);
    const Vec3 lo = vmin(a, b), hi = vmax(a, b);
    EXPECT_EQ(buffer.commonCell(a, a), buffer.cellIndexOf(a)) << "trial " << trial;
    const int cell = buffer.commonCell(lo, hi);
    if (cell < 0) continue;
    ++answered;
    for (int corner = 0; corner < 8; ++corner) {
      const Vec3 d{corner & 1 ? hi.x : lo.x, corner & 2 ? hi.y : lo.y, corner & 4 ? hi.z : lo.z};
      ASSERT_EQ(buffer.cellIndexOf(d), cell) << "trial " << trial << " corner " << corner;
    }
    for (int k = 0; k < 8; ++k) {
      const Vec3 d{gen.uniform(lo.x, hi.x), gen.uniform(lo.y, hi.y), gen.uniform(lo.z, hi.z)};
      ASSERT_EQ(buffer.cellIndexOf(d), cell) << "trial " << trial << " point " << k;
    }
  }
  EXPECT_GT(answered, 5000);
  EXPECT_LT(answered, 19000);  // boxes across cells and faces were tried too
  EXPECT_EQ(buffer.commonCell(Vec3(0.0), Vec3(0.0)), -1);
  EXPECT_EQ(buffer.commonCell(Vec3{1, 0, 0}, Vec3{1, NAN, 0}), -1);
}

// A packet of segments toward the light that share a cell, answered from the cell's list,
// gets for each segment the tree's answer, the floor's points (exactly on it) included.
TEST(LightBuffer, PacketsInOneCellAgreeWithTheTree) {
  Maker gen(62);
  const std::vector<Primitive> prims = gen.scene(300, 5, 0.05, 0.5);
  const Bvh bvh(prims);
  const Vec3 light{1.5, 9, -2};
  const LightBuffer buffer(light, bvh.occluders());
  ASSERT_TRUE(buffer.valid());
  int answered = 0, blocked = 0, transparent = 0;
  for (int packet = 0; packet < 3000; ++packet) {
    Vec3 centre = gen.point(5);
    if (packet % 2 == 0) centre.y = -5;  // on the floor
    const int count = 1 + packet % kMaxPacket;
    PacketRays lanes;
    alignas(32) double tMax[kMaxPacket];
    Vec3 lo(INFINITY), hi(-INFINITY);
    double reach = 0;
    for (int k = 0; k < count; ++k) {
      Vec3 start = centre + gen.point(packet % 3 == 0 ? 0.1 : 0.002);
      if (packet % 2 == 0) start.y = -5;
      const double dist = length(light - start);
      const Vec3 dir = (light - start) / dist;
      lanes.set(k, start, dir);
      tMax[k] = dist - kTol;
      lo = vmin(lo, -dir);
      hi = vmax(hi, -dir);
      reach = std::max(reach, dist * (1 + 1e-9));
    }
    lanes.finish(count);
    for (int k = count; k < lanes.groups * 4; ++k) tMax[k] = -INFINITY;
    const int cell = buffer.commonCell(lo, hi);
    if (cell < 0) continue;
    ++answered;
    const uint64_t live = count == 64 ? ~uint64_t(0) : (uint64_t(1) << count) - 1;
    std::vector<Occlusion> got(static_cast<size_t>(count));
    std::vector<uint32_t> blocker(static_cast<size_t>(count));
    uint64_t tests = 0;
    bvh.occlusionPacketInCell(buffer, cell, reach, lanes, tMax, kTol, live, got.data(), blocker.data(), tests);
    for (int k = 0; k < count; ++k) {
      uint32_t b = 0;
      const Occlusion want = bvh.occlusion(lanes.ray(k), kTol, tMax[k], tests, b);
      ASSERT_EQ(int(want), int(got[size_t(k)])) << "packet " << packet << " segment " << k;
      blocked += want == Occlusion::Blocked;
      transparent += want == Occlusion::Transparent;
    }
  }
  EXPECT_GT(answered, 1500);
  EXPECT_GT(blocked, 1000);
  EXPECT_GT(transparent, 50);
}

// Every scene of the repository renders the same with its light buffers as without them,
// bit for bit: one ray a pixel, and packets of 9 whose shadow segments are answered from the
// buffers too, and shading answering its segments from the cells it prefetched (in these
// small scenes only when asked for).
TEST(LightBuffer, EveryRepositorySceneRendersTheSameWithoutBuffers) {
  int scenes = 0, buffered = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(PVRT_SOURCE_DIR "/scenes")) {
    if (entry.path().extension() != ".xml") continue;
    // Packets' segments answered from the buffers one by one (as in big scenes), or together
    // from one cell where they can (as in small ones), against no buffers at all.
    Scene with = buildScene(loadSceneFile(entry.path().string()));
    with.packetShadowsFromBuffers = true;
    Scene cells = with;
    cells.packetShadowsFromBuffers = false;
    Scene without = with;
    without.lightBuffers.clear();
    // And as in big scenes, where shading prefetches each light's cell for the point and its
    // segments are answered from those cells.
    Scene prefetched = with;
    prefetched.prefetchLightBuffers = true;
    RenderSettings s;
    s.width = 64;
    s.height = 40;
    for (int spp : {1, 9}) {
      s.sampler.samplesPerPixel = spp;
      const RenderResult a = render(with, s), b = render(without, s), c = render(cells, s);
      EXPECT_EQ(a.image.data(), b.image.data()) << entry.path() << " spp " << spp;
      EXPECT_EQ(a.totals.shadowRays, b.totals.shadowRays) << entry.path() << " spp " << spp;
      EXPECT_EQ(c.image.data(), b.image.data()) << entry.path() << " spp " << spp << ", packets in cells";
      EXPECT_EQ(c.totals.shadowRays, b.totals.shadowRays) << entry.path() << " spp " << spp << ", packets in cells";
      const RenderResult d = render(prefetched, s);
      EXPECT_EQ(d.image.data(), b.image.data()) << entry.path() << " spp " << spp << ", cells prefetched";
      EXPECT_EQ(d.totals.shadowRays, b.totals.shadowRays) << entry.path() << " spp " << spp << ", cells prefetched";
    }
    ++scenes;
    for (const LightBuffer& lb : with.lightBuffers) buffered += lb.valid();
  }
  EXPECT_GT(scenes, 40);
  EXPECT_GT(buffered, 40);
}

// A memory limit below the BVH's bytes gets a cheaper tree (bigger leaves, far fewer nodes)
// that fits when the primitives' records leave room for any nodes, and the same image.
TEST(LightBuffer, AMemoryLimitBelowTheTreeBuildsACheaperOne) {
  GenerateOptions g;
  g.spheres = 3000;
  g.lights = 3;
  const SceneDesc desc = generateScene(g);
  const Scene full = buildScene(desc, {SIZE_MAX, true});
  ASSERT_EQ(full.bvh.stats().leafSize, kBvhLeafSize);
  const size_t fullBytes = full.bvh.stats().bytes, records = full.bvh.size() * sizeof(PrimitiveRecord);
  ASSERT_GT(fullBytes, records + 4096);
  RenderSettings s;
  s.width = 48;
  s.height = 30;
  s.sampler.samplesPerPixel = 4;
  s.sampler.kind = SamplerKind::Jitter;
  const Image::Pixels want = render(full, s).image.data();
  uint32_t previousLeaf = kBvhLeafSize;
  for (size_t limit : {fullBytes - 1, (fullBytes + records) / 2, records + 1, size_t(0)}) {
    const Scene cheap = buildScene(desc, {limit, true});
    const BvhStats& b = cheap.bvh.stats();
    EXPECT_GT(b.leafSize, kBvhLeafSize) << limit;
    EXPECT_GE(b.leafSize, previousLeaf) << limit;  // less memory, never a dearer tree
    previousLeaf = b.leafSize;
    if (b.leafSize < kBvhMaxLeafSize) {
      EXPECT_LE(b.bytes, limit);
    }
    EXPECT_LT(b.bytes, fullBytes) << limit;
    EXPECT_LT(b.nodes, full.bvh.stats().nodes) << limit;
    EXPECT_EQ(render(cheap, s).image.data(), want) << "limit " << limit << ", leaves of " << b.leafSize;
  }
  EXPECT_EQ(previousLeaf, kBvhMaxLeafSize);  // below the records nothing fits: the cheapest tree
}

// A memory limit leaves the last lights without a buffer, never more than the limit, and
// never a different image: generated spheres and 40 lights, built under limits from nothing
// to plenty, rendered at one ray a pixel and at 9, against the scene built without a limit.
TEST(LightBuffer, AMemoryLimitLeavesLightsOutButNotAPixel) {
  GenerateOptions g;
  g.spheres = 2000;
  g.lights = 40;
  const SceneDesc desc = generateScene(g);
  const Scene full = buildScene(desc, {SIZE_MAX, true});
  size_t fullBytes = 0;
  for (const LightBuffer& lb : full.lightBuffers) {
    EXPECT_TRUE(lb.valid());
    fullBytes += lb.bytes();
  }
  const size_t bvh = full.bvh.stats().bytes + full.bvh.occluders().size() * sizeof(LightBuffer::Occluder);
  RenderSettings s;
  s.width = 48;
  s.height = 30;
  std::vector<Image::Pixels> images;
  for (int spp : {1, 9}) {
    s.sampler.samplesPerPixel = spp;
    images.push_back(render(full, s).image.data());
  }
  size_t previous = 0;
  // The build holds up to 20 bytes an entry (LightBuffer::kBuildBytesPerEntry) where the
  // buffer keeps 8: three times the buffers' bytes let every light have one.
  // Limits between those where the lights' equal shares hold all their entries and those
  // where the lights must be counted and served in order (LightBuffer::buildBatch).
  std::vector<size_t> limits{0, bvh};
  for (int k = 1; k <= 12; ++k) limits.push_back(bvh + fullBytes * size_t(k) / 4);
  limits.push_back(bvh + 3 * fullBytes + (1u << 20));
  for (size_t limit : limits) {
    const Scene limited = buildScene(desc, {limit, true});
    size_t bytes = 0, valid = 0;
    bool gap = false;  // the lights with a buffer come first
    for (size_t l = 0; l < limited.lightBuffers.size(); ++l) {
      const LightBuffer& lb = limited.lightBuffers[l];
      bytes += lb.bytes();
      valid += lb.valid();
      EXPECT_EQ(lb.overMemoryLimit(), !lb.valid()) << "limit " << limit;
      if (!lb.valid()) {
        gap = true;
      } else {
        EXPECT_FALSE(gap) << "limit " << limit;
        // A buffer that fits is the one built without a limit.
        EXPECT_EQ(lb.entries(), full.lightBuffers[l].entries()) << "limit " << limit << " light " << l;
      }
    }
    EXPECT_LE(bytes + bvh, std::max(limit, bvh)) << "limit " << limit;
    EXPECT_EQ(limited.lightsOverMemoryLimit, limited.lights.size() - valid);
    EXPECT_GE(valid, previous) << "limit " << limit;  // more memory, never fewer buffers
    previous = valid;
    if (limit <= bvh) {
      EXPECT_EQ(valid, 0u);
    }
    if (limit > bvh + 3 * fullBytes) {
      EXPECT_EQ(valid, limited.lights.size());
    }
    if (limit > bvh && limit < bvh + fullBytes) {
      EXPECT_LT(valid, limited.lights.size());
    }
    for (int k = 0; k < 2; ++k) {
      s.sampler.samplesPerPixel = k == 0 ? 1 : 9;
      EXPECT_EQ(render(limited, s).image.data(), images[size_t(k)]) << "limit " << limit << " spp " << s.sampler.samplesPerPixel;
    }
  }
  EXPECT_GT(previous, 0u);
}

// A light among few primitives costs about what its entries do: 100 spheres seen from lights
// far away (each sphere a speck, which asks for the finest cells) take under 16 KB a light,
// where the 256 x 256 cells a face of before took 1.5 MB.
TEST(LightBuffer, AFarLightAmongFewPrimitivesIsSmall) {
  GenerateOptions g;
  g.spheres = 100;
  g.lights = 0;
  SceneDesc desc = generateScene(g);
  for (int i = 0; i < 50; ++i) {
    LightDesc l;
    l.location = {300.0 * std::cos(i), 200.0 + i, 300.0 * std::sin(i)};
    desc.lights.push_back(l);
  }
  const Scene scene = buildScene(desc);
  for (const LightBuffer& lb : scene.lightBuffers) {
    ASSERT_TRUE(lb.valid());
    EXPECT_LT(lb.bytes(), 16u << 10) << lb.resolution() << " cells a side, " << lb.entries() << " entries";
  }
}

// Without --memory-limit the light buffers take at most 4 times the BVH's bytes (at least
// 64 MiB), so that their memory and build time grow with the scene, not with the scene times
// its lights; a limit given replaces that.
TEST(LightBuffer, ByDefaultTheirBudgetGrowsWithTheScene) {
  EXPECT_EQ(lightBufferBudget(0), kLightBufferFloor);
  EXPECT_EQ(lightBufferBudget(kLightBufferFloor / kLightBufferShare), kLightBufferFloor);
  EXPECT_EQ(lightBufferBudget(size_t(100) << 20), kLightBufferShare * (size_t(100) << 20));
  GenerateOptions g;
  g.spheres = 2000;
  g.lights = 12;
  const SceneDesc desc = generateScene(g);
  Scene scene = buildScene(desc, {SIZE_MAX, true});
  ASSERT_FALSE(scene.memoryLimitScaled);
  EXPECT_EQ(scene.memoryLimit, SIZE_MAX);
  const size_t bvh = scene.bvh.stats().bytes + scene.bvh.occluders().size() * sizeof(LightBuffer::Occluder);
  for (const size_t limit : {SIZE_MAX, bvh + lightBufferBudget(bvh) + 1, bvh + lightBufferBudget(bvh) / 2}) {
    buildLightBuffers(scene, limit, true);
    EXPECT_EQ(scene.memoryLimit, std::min(limit, bvh + lightBufferBudget(bvh))) << limit;
    EXPECT_EQ(scene.memoryLimitScaled, limit > bvh + lightBufferBudget(bvh)) << limit;
    size_t bytes = 0;
    for (const LightBuffer& lb : scene.lightBuffers) {
      EXPECT_TRUE(lb.valid());  // a small scene's buffers fit in the floor
      bytes += lb.bytes();
    }
    EXPECT_LE(bytes, lightBufferBudget(bvh));
  }
  // buildScene without memoryLimitGiven is the scaled build.
  const Scene byDefault = buildScene(desc, {SIZE_MAX, false});
  EXPECT_TRUE(byDefault.memoryLimitScaled);
  EXPECT_EQ(byDefault.memoryLimit, bvh + lightBufferBudget(bvh));
}

}  // namespace
}  // namespace pvrt
