// Ray-shape intersections checked against answers worked out by hand: hit distance,
// misses, rays starting inside, tolerances, normals, bounds and inside tests for every
// shape in geometry/primitive.h, with and without a transform.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "geometry/primitive.h"
#include "render/scene.h"
#include "scene/xml_loader.h"

namespace pvrt {
namespace {

constexpr double kTol = 1e-12;

void expectVecNear(const Vec3& got, const Vec3& want, double tol = kTol) {
  EXPECT_NEAR(got.x, want.x, tol) << "x";
  EXPECT_NEAR(got.y, want.y, tol) << "y";
  EXPECT_NEAR(got.z, want.z, tol) << "z";
}

Primitive prim(Shape s) {
  Primitive p;
  p.shape = std::move(s);
  return p;
}
Primitive prim(Shape s, const Affine& a) {
  Primitive p = prim(std::move(s));
  p.transform = share(Transform::from(a));
  EXPECT_TRUE(p.transform);
  return p;
}

// The nearest hit with POV-Ray's usual minimum depth, no upper limit to speak of.
std::optional<ShapeHit> hit(const Primitive& p, const Ray& r, double tMin = kMinIsectDepth) {
  return p.intersect(r, tMin, kMaxDistance);
}

const Vec3 kX{1, 0, 0}, kY{0, 1, 0}, kZ{0, 0, 1};

// ---------------------------------------------------------------- sphere

// Unit sphere at z=5 seen from the origin along +z: the near surface is at z=4.
TEST(Shapes, SphereHeadOnHitDistanceAndNormal) {
  const Primitive s = prim(SphereShape{{0, 0, 5}, 1});
  const Ray r{{0, 0, 0}, kZ};
  const auto h = hit(s, r);
  ASSERT_TRUE(h);
  EXPECT_NEAR(h->t, 4.0, kTol);
  expectVecNear(s.normal(r, *h), {0, 0, -1});
}

// Offset by x=0.6 the ray meets the sphere where z = 5 - sqrt(1 - 0.36) = 4.2; the
// normal (P - C) / r there is (0.6, 0, -0.8).
TEST(Shapes, SphereOffAxisHit) {
  const Primitive s = prim(SphereShape{{0, 0, 5}, 1});
  const Ray r{{0.6, 0, 0}, kZ};
  const auto h = hit(s, r);
  ASSERT_TRUE(h);
  EXPECT_NEAR(h->t, 4.2, 1e-12);
  expectVecNear(s.normal(r, *h), {0.6, 0, -0.8}, 1e-12);
}

TEST(Shapes, SphereMisses) {
  const Primitive s = prim(SphereShape{{0, 0, 5}, 1});
  EXPECT_FALSE(hit(s, {{1.5, 0, 0}, kZ}));   // passes beside it (1.5 > r)
  EXPECT_FALSE(hit(s, {{0, 0, 0}, -kZ}));    // points away from it
  EXPECT_FALSE(hit(s, {{0, 0, 10}, kZ}));    // the sphere is behind the origin
  // Within reach only beyond tMax: the near surface is at t=4.
  EXPECT_FALSE(s.intersect({{0, 0, 0}, kZ}, kMinIsectDepth, 3.9));
}

// From the centre the only root ahead is the far one, at distance r; from z=4.5 inside
// the sphere it is 6 - 4.5 = 1.5, and the normal still points outward.
TEST(Shapes, SphereRayFromInsideTakesTheFarRoot) {
  const Primitive s = prim(SphereShape{{0, 0, 5}, 1});
  const auto h1 = hit(s, {{0, 0, 5}, kZ});
  ASSERT_TRUE(h1);
  EXPECT_NEAR(h1->t, 1.0, kTol);
  const Ray r{{0, 0, 4.5}, kZ};
  const auto h2 = hit(s, r);
  ASSERT_TRUE(h2);
  EXPECT_NEAR(h2->t, 1.5, kTol);
  expectVecNear(s.normal(r, *h2), {0, 0, 1});
}

// A ray starting 5e-5 in front of the sphere: with POV-Ray's minimum depth 1e-4 the near
// hit is ignored and the far one (2 + 5e-5) is returned; with tMin=0 the near one counts.
TEST(Shapes, SphereHitsCloserThanTMinAreIgnored) {
  const Primitive s = prim(SphereShape{{0, 0, 0}, 1});
  const Ray r{{0, 0, -1 - 5e-5}, kZ};
  const auto far = hit(s, r, kMinIsectDepth);
  ASSERT_TRUE(far);
  EXPECT_NEAR(far->t, 2 + 5e-5, 1e-9);
  const auto near = hit(s, r, 0.0);
  ASSERT_TRUE(near);
  EXPECT_NEAR(near->t, 5e-5, 1e-9);
}

// A ray leaving the surface outward does not hit the sphere it starts on; one entering
// it hits the far side only (the root at t=0 is under the depth tolerance even for tMin=0).
TEST(Shapes, SphereRayStartingOnTheSurface) {
  const Primitive s = prim(SphereShape{{0, 0, 0}, 1});
  EXPECT_FALSE(hit(s, {{0, 0, 1}, kZ}, 0.0));
  const auto h = hit(s, {{0, 0, -1}, kZ}, 0.0);
  ASSERT_TRUE(h);
  EXPECT_NEAR(h->t, 2.0, kTol);
}

TEST(Shapes, SphereBoundsAndInside) {
  const Primitive s = prim(SphereShape{{1, 2, 3}, 0.5});
  const Bounds b = s.bounds();
  expectVecNear(b.lo, {0.5, 1.5, 2.5});
  expectVecNear(b.hi, {1.5, 2.5, 3.5});
  EXPECT_TRUE(s.inside({1, 2, 3}));
  EXPECT_TRUE(s.inside({1.4, 2, 3}));
  EXPECT_FALSE(s.inside({1.6, 2, 3}));
}

// ---------------------------------------------------------------- plane

// The plane y=1 (unit normal +y, distance 1) seen from y=5 looking down: t = 4.
TEST(Shapes, PlaneHitAndNormal) {
  const Primitive p = prim(PlaneShape{kY, 1});
  const Ray r{{3, 5, -2}, -kY};
  const auto h = hit(p, r);
  ASSERT_TRUE(h);
  EXPECT_NEAR(h->t, 4.0, kTol);
  expectVecNear(p.normal(r, *h), kY);
  // Obliquely, along (1,-1,0)/sqrt(2) from y=5: 4 units down is 4*sqrt(2) along the ray.
  const auto o = hit(p, {{0, 5, 0}, normalize({1, -1, 0})});
  ASSERT_TRUE(o);
  EXPECT_NEAR(o->t, 4 * std::sqrt(2.0), 1e-12);
}

TEST(Shapes, PlaneMisses) {
  const Primitive p = prim(PlaneShape{kY, 1});
  EXPECT_FALSE(hit(p, {{0, 5, 0}, kX}));   // parallel to it
  EXPECT_FALSE(hit(p, {{0, 5, 0}, kY}));   // moving away from it
  EXPECT_FALSE(hit(p, {{0, 0, 0}, -kY}));  // it is behind the ray
}

// The plane 5e-5 ahead: ignored with tMin = 1e-4, hit with tMin = 0. At 5e-7 ahead it
// is under POV-Ray's depth tolerance (1e-6) and ignored even with tMin = 0.
TEST(Shapes, PlaneToleranceIgnoresVeryCloseHits) {
  const Primitive p = prim(PlaneShape{kY, 0});
  EXPECT_FALSE(hit(p, {{0, 5e-5, 0}, -kY}, kMinIsectDepth));
  const auto h = hit(p, {{0, 5e-5, 0}, -kY}, 0.0);
  ASSERT_TRUE(h);
  EXPECT_NEAR(h->t, 5e-5, 1e-15);
  EXPECT_FALSE(hit(p, {{0, 5e-7, 0}, -kY}, 0.0));
}

// POV-Ray's plane's inside is the side the normal points away from.
TEST(Shapes, PlaneInsideIsBelowAndBoundsAreEmpty) {
  const Primitive p = prim(PlaneShape{kY, 1});
  EXPECT_TRUE(p.inside({0, 0, 0}));
  EXPECT_FALSE(p.inside({0, 2, 0}));
  EXPECT_TRUE(p.bounds().empty());
}

// POV-Ray makes the normal unit and keeps the distance: plane{<0,2,0>,1} is y=1 (not
// y=0.5, not y=2). Built from the scene description, through the real XML path.
TEST(Shapes, PlaneDistanceIsAlongTheUnitNormalWhenBuiltFromAScene) {
  const Scene scene = buildScene(loadSceneString(R"(<scene>
      <plane normal="0 2 0" distance="1"/></scene>)",
                                                 "plane.xml"));
  ASSERT_EQ(scene.bvh.size(), 1u);
  const Primitive& p = scene.bvh.primitive(0);
  const auto* shape = std::get_if<PlaneShape>(&p.shape);
  ASSERT_NE(shape, nullptr);
  expectVecNear(shape->normal, kY);
  EXPECT_DOUBLE_EQ(shape->distance, 1.0);
  uint64_t tests = 0;
  const auto h = scene.bvh.closest({{0, 5, 0}, -kY}, kMinIsectDepth, kMaxDistance, tests);
  ASSERT_TRUE(h);
  EXPECT_NEAR(h->hit.t, 4.0, kTol);  // y = 5 - 4 = 1
}

// A transformed plane is transformed itself: y=1 scaled by 2 becomes y=2, then moved up
// 3 it becomes y=5; a plane tilted by rotate z*90 (y -> -x) becomes x=-1.
TEST(Shapes, TransformedPlaneBuiltFromAScene) {
  const Scene scene = buildScene(loadSceneString(R"(<scene>
      <plane normal="0 1 0" distance="1"><scale v="2"/><translate v="0 3 0"/></plane>
      <plane normal="0 1 0" distance="1"><rotate v="0 0 90"/></plane></scene>)",
                                                 "plane.xml"));
  uint64_t tests = 0;
  const auto up = scene.bvh.closest({{0, 10, 0}, -kY}, kMinIsectDepth, kMaxDistance, tests);
  ASSERT_TRUE(up);
  EXPECT_EQ(scene.bvh.primitive(up->primitive).object, 0u);
  EXPECT_NEAR(up->hit.t, 5.0, 1e-12);
  const auto side = scene.bvh.closest({{5, -20, 0}, -kX}, kMinIsectDepth, kMaxDistance, tests);
  ASSERT_TRUE(side);
  EXPECT_EQ(scene.bvh.primitive(side->primitive).object, 1u);
  EXPECT_NEAR(side->hit.t, 6.0, 1e-12);
}

// ---------------------------------------------------------------- box

// The cube [-1,1]^3 from z=-5 along +z: enters the z=-1 face (face 4 = low z) at t=4.
TEST(Shapes, BoxHitFaceAndNormal) {
  const Primitive b = prim(BoxShape{{-1, -1, -1}, {1, 1, 1}});
  const Ray r{{0.3, -0.2, -5}, kZ};
  const auto h = hit(b, r);
  ASSERT_TRUE(h);
  EXPECT_NEAR(h->t, 4.0, kTol);
  EXPECT_EQ(h->part, 4);
  expectVecNear(b.normal(r, *h), {0, 0, -1});
  // From +x moving -x it enters the high-x face (face 1), normal +x.
  const Ray rx{{7, 0.5, 0.5}, -kX};
  const auto hx = hit(b, rx);
  ASSERT_TRUE(hx);
  EXPECT_NEAR(hx->t, 6.0, kTol);
  EXPECT_EQ(hx->part, 1);
  expectVecNear(b.normal(rx, *hx), kX);
}

// Diagonal ray (1,1,0)/sqrt(2) from (-3,-2.5,0): reaches x=-1 at s=2 (y=-0.5, inside the
// y slab) and y=-1 at s=1.5 (x=-1.5, outside): the entry is on the x face at 2*sqrt(2).
TEST(Shapes, BoxObliqueHitPicksTheLaterEntry) {
  const Primitive b = prim(BoxShape{{-1, -1, -1}, {1, 1, 1}});
  const Ray r{{-3, -2.5, 0}, normalize({1, 1, 0})};
  const auto h = hit(b, r);
  ASSERT_TRUE(h);
  EXPECT_NEAR(h->t, 2 * std::sqrt(2.0), 1e-12);
  expectVecNear(b.normal(r, *h), {-1, 0, 0});
}

// A ray through the edge where the top (y = 1) and front (z = -1) faces meet enters both
// slabs at the same depth. POV-Ray's Box::Intersect then shades the face the ray runs more
// squarely into: the front one when |d.z| > |d.y|, the top one the other way round; so
// within its CLOSE_TOLERANCE (1e-6) of the edge, and not farther.
TEST(Shapes, BoxEdgeHitTakesTheFaceTheRayMeetsMoreSquarely) {
  const Primitive b = prim(BoxShape{{-1, -1, -1}, {1, 1, 1}});
  const Ray steep{{0, 3, -2}, normalize({0, -2, 1})}, shallow{{0, 2, -3}, normalize({0, -1, 2})};
  const auto top = hit(b, steep), front = hit(b, shallow);
  ASSERT_TRUE(top && front);
  EXPECT_EQ(top->part, 3);    // high y
  EXPECT_EQ(front->part, 4);  // low z
  expectVecNear(b.normal(shallow, *front), {0, 0, -1});
  EXPECT_NEAR(front->t, std::sqrt(5.0), 1e-12);
  // 1e-7 higher the ray enters through the top, 1e-7 * sqrt(5) past the front plane: within
  // the tolerance, so still the front face.
  const auto near = hit(b, {{0, 2 + 1e-7, -3}, normalize({0, -1, 2})});
  ASSERT_TRUE(near);
  EXPECT_EQ(near->part, 4);
  // 1e-5 higher, beyond it: the top face.
  const auto above = hit(b, {{0, 2 + 1e-5, -3}, normalize({0, -1, 2})});
  ASSERT_TRUE(above);
  EXPECT_EQ(above->part, 3);
}

TEST(Shapes, BoxMisses) {
  const Primitive b = prim(BoxShape{{-1, -1, -1}, {1, 1, 1}});
  EXPECT_FALSE(hit(b, {{2, 0, -5}, kZ}));   // parallel to x slabs, outside them
  EXPECT_FALSE(hit(b, {{0, 0, -5}, -kZ}));  // box behind the ray
  // Passes the top-left corner: along (1,1,0) it leaves the y slab (y=1) after 1.5 units
  // of x, while x=-1 is 2 units of x away.
  EXPECT_FALSE(hit(b, {{-3, -0.5, 0}, normalize({1, 1, 0})}));
}

// From the centre the ray exits through the far face (face 5 = high z) at t=1, normal +z.
TEST(Shapes, BoxRayFromInsideTakesTheFarFace) {
  const Primitive b = prim(BoxShape{{-1, -1, -1}, {1, 1, 1}});
  const Ray r{{0, 0, 0}, kZ};
  const auto h = hit(b, r);
  ASSERT_TRUE(h);
  EXPECT_NEAR(h->t, 1.0, kTol);
  EXPECT_EQ(h->part, 5);
  expectVecNear(b.normal(r, *h), kZ);
}

// Near face 5e-5 ahead: ignored with tMin=1e-4, so the far face (2 + 5e-5) is the hit.
TEST(Shapes, BoxHitsCloserThanTMinAreIgnored) {
  const Primitive b = prim(BoxShape{{-1, -1, -1}, {1, 1, 1}});
  const auto h = hit(b, {{0, 0, -1 - 5e-5}, kZ});
  ASSERT_TRUE(h);
  EXPECT_NEAR(h->t, 2 + 5e-5, 1e-12);
  EXPECT_EQ(h->part, 5);
}

TEST(Shapes, BoxBoundsAndInside) {
  const Primitive b = prim(BoxShape{{-1, 0, 2}, {1, 3, 4}});
  expectVecNear(b.bounds().lo, {-1, 0, 2});
  expectVecNear(b.bounds().hi, {1, 3, 4});
  EXPECT_TRUE(b.inside({0, 1, 3}));
  EXPECT_FALSE(b.inside({0, 1, 5}));
  EXPECT_FALSE(b.inside({-1.5, 1, 3}));
}

// POV-Ray accepts a box's corners in any order: corner1 = <1,1,1>, corner2 = <-1,-1,-1>
// is the same cube, hit at t=4 from z=-5. A mirroring scale swaps corners again.
TEST(Shapes, BoxWithSwappedCornersBuiltFromAScene) {
  const Scene scene = buildScene(loadSceneString(R"(<scene>
      <box corner1="1 1 1" corner2="-1 -1 -1"/>
      <box corner1="0 -1 -1" corner2="1 1 1"><scale v="-2 1 1"/><translate v="0 0 10"/></box>
      </scene>)",
                                                 "box.xml"));
  ASSERT_EQ(scene.bvh.size(), 2u);
  for (uint32_t i = 0; i < scene.bvh.size(); ++i) {
    const Primitive p = scene.bvh.primitive(i);
    const auto* shape = std::get_if<BoxShape>(&p.shape);
    ASSERT_NE(shape, nullptr);
    EXPECT_FALSE(p.transform);  // axis-aligned: the transform is folded into the corners
    EXPECT_LE(shape->lo.x, shape->hi.x);
    EXPECT_LE(shape->lo.y, shape->hi.y);
    EXPECT_LE(shape->lo.z, shape->hi.z);
  }
  uint64_t tests = 0;
  const auto h = scene.bvh.closest({{0, 0, -5}, kZ}, kMinIsectDepth, kMaxDistance, tests);
  ASSERT_TRUE(h);
  EXPECT_EQ(scene.bvh.primitive(h->primitive).object, 0u);
  EXPECT_NEAR(h->hit.t, 4.0, kTol);
  // The second box spans x in [-2, 0] (x scaled by -2), z in [9, 11].
  const auto h2 = scene.bvh.closest({{-1.5, 0, 0}, kZ}, kMinIsectDepth, kMaxDistance, tests);
  ASSERT_TRUE(h2);
  EXPECT_EQ(scene.bvh.primitive(h2->primitive).object, 1u);
  EXPECT_NEAR(h2->hit.t, 9.0, kTol);
  EXPECT_FALSE(scene.bvh.closest({{1.5, 0, 5}, kZ}, kMinIsectDepth, kMaxDistance, tests));
}

// ---------------------------------------------------------------- cylinder

// Cylinders and cones as the scene builder makes them: POV-Ray's canonical shape with its
// transform (geometry/pov_cone.h). POV-Ray reads the written base into the end at canonical
// z = 1 (part 2) and the written cap into the other (part 1), wider end first for cones.
Primitive placed(const PovConePlacement& p) {
  Primitive prim;
  prim.shape = p.shape;
  prim.transform = share(p.transform.toTransform());
  return prim;
}
Primitive cylinder(const Vec3& base, const Vec3& cap, double radius, bool open = false) {
  return placed(placeCylinder(base, cap, radius, open));
}
Primitive cone(const Vec3& base, double baseRadius, const Vec3& cap, double capRadius, bool open = false) {
  return placed(placeCone(base, baseRadius, cap, capRadius, open));
}
const Primitive kCyl = cylinder({0, 0, 0}, {0, 2, 0}, 1);  // y in [0,2], radius 1

// From x=-5 at mid height: the side x=-1 at t=4, normal -x.
TEST(Shapes, CylinderSideHitAndNormal) {
  const Primitive& c = kCyl;
  const Ray r{{-5, 1, 0}, kX};
  const auto h = hit(c, r);
  ASSERT_TRUE(h);
  EXPECT_NEAR(h->t, 4.0, kTol);
  EXPECT_EQ(h->part, 0);
  expectVecNear(c.normal(r, *h), {-1, 0, 0});
  // Offset z=0.6: the side is at x = -sqrt(1 - 0.36) = -0.8, normal (-0.8, 0, 0.6).
  const Ray r2{{-5, 1, 0.6}, kX};
  const auto h2 = hit(c, r2);
  ASSERT_TRUE(h2);
  EXPECT_NEAR(h2->t, 4.2, 1e-12);
  expectVecNear(c.normal(r2, *h2), {-0.8, 0, 0.6}, 1e-12);
}

// Down the axis from y=5: a closed cylinder's top cap (the written cap, part 1) at y=2,
// t=3, normal +y; an open one has no caps and its side is parallel to the ray, so nothing
// is hit.
TEST(Shapes, CylinderClosedVersusOpenAlongTheAxis) {
  const Primitive& closed = kCyl;
  const Ray down{{0, 5, 0}, -kY};
  const auto h = hit(closed, down);
  ASSERT_TRUE(h);
  EXPECT_NEAR(h->t, 3.0, kTol);
  EXPECT_EQ(h->part, 1);
  expectVecNear(closed.normal(down, *h), kY);
  // Upward from below: the written base (part 2) at y=0, t=5, normal -y.
  const Ray up{{0.5, -5, 0}, kY};
  const auto hb = hit(closed, up);
  ASSERT_TRUE(hb);
  EXPECT_NEAR(hb->t, 5.0, kTol);
  EXPECT_EQ(hb->part, 2);
  expectVecNear(closed.normal(up, *hb), -kY);

  const Primitive open = cylinder({0, 0, 0}, {0, 2, 0}, 1, true);
  EXPECT_FALSE(hit(open, down));
  EXPECT_FALSE(hit(open, up));
  // The side is still there: from inside an open tube the ray leaves through it at t=1.
  const Ray out{{0, 1, 0}, kX};
  const auto hs = hit(open, out);
  ASSERT_TRUE(hs);
  EXPECT_NEAR(hs->t, 1.0, kTol);
  expectVecNear(open.normal(out, *hs), kX);
}

TEST(Shapes, CylinderMissesAboveAndBeside) {
  const Primitive& c = kCyl;
  EXPECT_FALSE(hit(c, {{-5, 2.5, 0}, kX}));  // above the top
  EXPECT_FALSE(hit(c, {{-5, 1, 1.5}, kX}));  // beside it
  EXPECT_FALSE(hit(c, {{1.5, 5, 0}, -kY}));  // parallel to the axis, outside the radius
}

// From the axis the ray leaves through the side at distance r = 1.
TEST(Shapes, CylinderRayFromInside) {
  const Primitive& c = kCyl;
  const auto h = hit(c, {{0, 1, 0}, normalize({1, 0, 1})});
  ASSERT_TRUE(h);
  EXPECT_NEAR(h->t, 1.0, 1e-12);
}

// Bounds: the caps are discs of radius 1 in y=0 and y=2. Inside: within radius and height.
TEST(Shapes, CylinderBoundsAndInside) {
  const Primitive& c = kCyl;
  expectVecNear(c.bounds().lo, {-1, 0, -1});
  expectVecNear(c.bounds().hi, {1, 2, 1});
  EXPECT_TRUE(c.inside({0.5, 1, 0.5}));
  EXPECT_FALSE(c.inside({0, 2.5, 0}));
  EXPECT_FALSE(c.inside({0.9, 1, 0.9}));  // radius sqrt(1.62) > 1
}

// ---------------------------------------------------------------- cone

// Base <0,0,0> radius 1, cap <0,1,0> radius 0.5: r(h) = 1 - h/2.
const Primitive kCone = cone({0, 0, 0}, 1, {0, 1, 0}, 0.5);

// At height 0.5 the radius is 0.75: a ray from x=-5 hits x=-0.75 at t=4.25. The surface
// is F = x^2 + z^2 - r(y)^2 = 0 with gradient (2x, -2 r r'(y), 2z) = (-1.5, 0.75, 0) there
// (r' = -1/2), i.e. the normal (-2, 1, 0)/sqrt(5): tilted up because the cone narrows.
TEST(Shapes, ConeSideHitAndGradientNormal) {
  const Primitive& c = kCone;
  const Ray r{{-5, 0.5, 0}, kX};
  const auto h = hit(c, r);
  ASSERT_TRUE(h);
  EXPECT_NEAR(h->t, 4.25, 1e-12);
  EXPECT_EQ(h->part, 0);
  expectVecNear(c.normal(r, *h), Vec3{-2, 1, 0} / std::sqrt(5.0), 1e-12);
}

// Along the axis the caps are hit when closed (top at y=1, base at y=0); an open cone's
// side is never reached on the axis (its apex, r=0, would be at y=2, outside the frustum).
TEST(Shapes, ConeCapsWhenClosedAndNoneWhenOpen) {
  const Primitive& closed = kCone;
  const Ray down{{0, 5, 0}, -kY};
  const auto top = hit(closed, down);
  ASSERT_TRUE(top);
  EXPECT_NEAR(top->t, 4.0, kTol);
  expectVecNear(closed.normal(down, *top), kY);
  const Ray up{{0.8, -5, 0}, kY};  // 0.8 < base radius 1, > cap radius 0.5
  const auto base = hit(closed, up);
  ASSERT_TRUE(base);
  EXPECT_NEAR(base->t, 5.0, kTol);
  expectVecNear(closed.normal(up, *base), -kY);

  const Primitive open = cone({0, 0, 0}, 1, {0, 1, 0}, 0.5, true);
  EXPECT_FALSE(hit(open, down));
  // Upward at x=0.8 the open cone's side is hit from inside where r(y) = 0.8: y = 0.4.
  const auto side = hit(open, up);
  ASSERT_TRUE(side);
  EXPECT_NEAR(side->t, 5.4, 1e-12);
}

// A pointed cone (cap radius 0, POV-Ray's default) from the side at height 0.5: r = 0.5.
TEST(Shapes, PointedConeAndMisses) {
  const Primitive c = cone({0, 0, 0}, 1, {0, 1, 0}, 0);
  const auto h = hit(c, {{-5, 0.5, 0}, kX});
  ASSERT_TRUE(h);
  EXPECT_NEAR(h->t, 4.5, 1e-12);
  EXPECT_FALSE(hit(c, {{-5, 0.5, 0.6}, kX}));  // 0.6 > r(0.5)
  EXPECT_FALSE(hit(c, {{-5, 1.5, 0}, kX}));    // above the apex
  EXPECT_TRUE(c.inside({0, 0.5, 0.4}));
  EXPECT_FALSE(c.inside({0, 0.5, 0.6}));
}

// ---------------------------------------------------------------- disc

// A disc as the scene builds one: POV-Ray's canonical disc through its transform, with
// more transforms after it.
Primitive disc(const Vec3& center, const Vec3& normal, double radius, double hole,
               const std::optional<PovTransform>& then = std::nullopt) {
  PovDiscPlacement placed = placeDisc(center, normal, radius, hole);
  if (then) placed.then(*then);
  Primitive p = prim(placed.shape);
  p.transform = share(placed.transform.toTransform());
  return p;
}
// A disc in y=0 of radius 2 with a hole of radius 1.
Primitive ring() { return disc({0, 0, 0}, kY, 2, 1); }

TEST(Shapes, DiscWithHoleHitsTheRingOnly) {
  const Primitive d = ring();
  const Ray ring{{1.5, 5, 0}, -kY};
  const auto h = hit(d, ring);
  ASSERT_TRUE(h);
  EXPECT_NEAR(h->t, 5.0, kTol);
  expectVecNear(d.normal(ring, *h), kY);
  EXPECT_FALSE(hit(d, {{0, 5, 0}, -kY}));     // through the centre of the hole
  EXPECT_FALSE(hit(d, {{0.5, 5, 0.5}, -kY}));  // through the hole off-centre
  EXPECT_FALSE(hit(d, {{2.5, 5, 0}, -kY}));   // outside the disc
  EXPECT_FALSE(hit(d, {{1.5, 5, 0}, kZ}));    // parallel to it
  // From below it is hit as well (a disc has two sides): same point, same normal.
  const auto below = hit(d, {{0, -3, 1.5}, kY});
  ASSERT_TRUE(below);
  EXPECT_NEAR(below->t, 3.0, kTol);
}

// Tilted disc: centre (0,0,5), normal (0,0,-1), radius 1. From the origin along
// (0.6,0,0.8) the plane z=5 is reached at t = 5/0.8 = 6.25, at x = 3.75: outside.
TEST(Shapes, DiscFacingTheRayAndOffsetMiss) {
  const Primitive d = disc({0, 0, 5}, -kZ, 1, 0);
  const auto h = hit(d, {{0.5, 0.5, 0}, kZ});
  ASSERT_TRUE(h);
  EXPECT_NEAR(h->t, 5.0, kTol);
  EXPECT_FALSE(hit(d, {{0, 0, 0}, {0.6, 0, 0.8}}));
}

// Bounds of a radius-2 disc in y=0: x and z within +-2, y flat. Inside: below the normal.
TEST(Shapes, DiscBoundsAndInside) {
  const Primitive d = ring();
  expectVecNear(d.bounds().lo, {-2, 0, -2});
  expectVecNear(d.bounds().hi, {2, 0, 2});
  // Behind it within POV-Ray's box of it (1e-3 either side of its plane), as a camera ray's
  // start counts it (PovDisc.HoldsACameraOnlyWithinItsBoundingBox); behind it beyond the box, not.
  EXPECT_TRUE(d.inside({0, -5e-4, 0}));
  EXPECT_FALSE(d.inside({0, -1, 0}));
  EXPECT_FALSE(d.inside({0, 1, 0}));
}

// Triangles: lone ones in pov_triangle_test.cpp, a mesh's in pov_mesh_test.cpp.

// ---------------------------------------------------------------- transformed shapes

// Unit sphere scaled by <2,1,1>: the ellipsoid x^2/4 + y^2 + z^2 = 1, met from x=-5 on the
// axis at x=-2 (t=3, normal -x). At y=0.6 it is met at x = -2*0.8 = -1.6 (t = 3.4) where
// the gradient (x/2, 2y, 2z) = (-0.8, 1.2, 0) gives the normal (-2, 3, 0)/sqrt(13).
TEST(Shapes, ScaledSphereHitAndNormal) {
  const Primitive s = prim(SphereShape{{0, 0, 0}, 1}, Affine::scale({2, 1, 1}));
  const Ray r{{-5, 0, 0}, kX};
  const auto h = hit(s, r);
  ASSERT_TRUE(h);
  EXPECT_NEAR(h->t, 3.0, 1e-12);
  expectVecNear(r.at(h->t), {-2, 0, 0}, 1e-12);
  expectVecNear(s.normal(r, *h), {-1, 0, 0}, 1e-12);
  const Ray r2{{-5, 0.6, 0}, kX};
  const auto h2 = hit(s, r2);
  ASSERT_TRUE(h2);
  EXPECT_NEAR(h2->t, 3.4, 1e-12);
  expectVecNear(s.normal(r2, *h2), Vec3{-2, 3, 0} / std::sqrt(13.0), 1e-12);
  // Along y the ellipsoid is still radius 1.
  const auto hy = hit(s, {{0, -5, 0}, kY});
  ASSERT_TRUE(hy);
  EXPECT_NEAR(hy->t, 4.0, 1e-12);
  EXPECT_FALSE(hit(s, {{-5, 1.1, 0}, kX}));
  expectVecNear(s.bounds().lo, {-2, -1, -1});
  expectVecNear(s.bounds().hi, {2, 1, 1});
  EXPECT_TRUE(s.inside({1.9, 0, 0}));
  EXPECT_FALSE(s.inside({0, 1.1, 0}));
}

// Cylinder y in [0,2] rotated x*90 (y -> z) and moved 3 along z: now z in [3,5]. From
// the origin along +z the base cap is at t=3 with normal -z; the far side of the ray's
// path from inside (origin (0,0,4)) is the top cap at t=1.
TEST(Shapes, RotatedTranslatedCylinder) {
  PovConePlacement moved = placeCylinder({0, 0, 0}, {0, 2, 0}, 1, false);
  moved.transform.then(PovTransform::rotation({90, 0, 0}));
  moved.transform.then(PovTransform::translation({0, 0, 3}));
  const Primitive c = placed(moved);
  const Ray r{{0, 0, 0}, kZ};
  const auto h = hit(c, r);
  ASSERT_TRUE(h);
  EXPECT_NEAR(h->t, 3.0, 1e-12);
  expectVecNear(c.normal(r, *h), {0, 0, -1}, 1e-12);
  const auto in = hit(c, {{0, 0, 4}, kZ});
  ASSERT_TRUE(in);
  EXPECT_NEAR(in->t, 1.0, 1e-12);
  // From the side along -y at z=4: radius-1 side at y=1, t=4, normal +y.
  const Ray side{{0, 5, 4}, -kY};
  const auto hs = hit(c, side);
  ASSERT_TRUE(hs);
  EXPECT_NEAR(hs->t, 4.0, 1e-12);
  expectVecNear(c.normal(side, *hs), kY, 1e-12);
  expectVecNear(c.bounds().lo, {-1, -1, 3}, 1e-12);
  expectVecNear(c.bounds().hi, {1, 1, 5}, 1e-12);
}

// A box rotated 30 degrees about y, from x=-5 along +x at y=z=0: the cube's face x=-1 is
// turned so that the ray meets it at local x=-1, i.e. at distance 1/cos(30) from the
// centre: t = 5 - 2/sqrt(3). The normal is the face's -x turned by 30 degrees about y:
// (-cos 30, 0, sin 30) (rotate y takes x to (cos, 0, -sin)).
TEST(Shapes, RotatedBoxHitAndNormal) {
  const Primitive b = prim(BoxShape{{-1, -1, -1}, {1, 1, 1}}, Affine::rotate({0, 30, 0}));
  const Ray r{{-5, 0, 0}, kX};
  const auto h = hit(b, r);
  ASSERT_TRUE(h);
  EXPECT_NEAR(h->t, 5 - 2 / std::sqrt(3.0), 1e-12);
  expectVecNear(b.normal(r, *h), {-std::sqrt(3.0) / 2, 0, 0.5}, 1e-12);
}

// A transformed (non-unit-direction in object space) disc keeps world distances: disc of
// radius 1 in y=0 scaled by 3 is radius 3; from y=10 at x=2.5 it is hit at t=10.
TEST(Shapes, ScaledDiscKeepsWorldDistance) {
  const Primitive d = disc({0, 0, 0}, kY, 1, 0, PovTransform::scaling(Vec3{3}));
  const auto h = hit(d, {{2.5, 10, 0}, -kY});
  ASSERT_TRUE(h);
  EXPECT_NEAR(h->t, 10.0, 1e-12);
  EXPECT_FALSE(hit(d, {{3.1, 10, 0}, -kY}));
}

// Cone::All_Intersections pushes the sides' roots, then the caps, and FindIntersection pops the
// last pushed first, keeping a hit only when strictly nearer: of two at one depth the later
// wins. blind14's a05: the camera's method-2 corner rays at (74, 12) and (86, 12) meet the
// base cap's rim (x = -0.3 and 0.3, y - 1.5 = 0.4: radius 0.5) where the side's root and the
// cap's depth are the same double; POV-Ray shades the cap there (it faces the camera), pvrt
// kept the side.
TEST(Shapes, ConeRimMetAtOneDepthBySideAndCapIsTheCap) {
  const Scene scene = buildScene(loadSceneString(
      "<scene><camera location=\"0 0 -6\" look_at=\"0 0 0\" right=\"1.6 0 0\"/>"
      "<cone base=\"0 1.5 -1\" base_radius=\"0.5\" cap=\"0 1.5 1\" cap_radius=\"0\"/></scene>"));
  for (int x : {74, 86}) {
    const Ray ray = scene.camera.ray(x, 12, -0.5, -0.5, 160, 100);
    const std::optional<ShapeHit> h = scene.bvh.intersect(0, ray, 1e-4, 1e7);
    ASSERT_TRUE(h.has_value()) << x;
    EXPECT_EQ(h->part, 2) << x << ": the written base's cap (canonical z = 1), not the side";
  }
}

}  // namespace
}  // namespace pvrt
