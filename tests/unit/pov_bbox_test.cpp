// POV-Ray's object boxes and their keys (geometry/pov_bbox.h), and the rule they give to
// ties between objects met at one depth (accel/tie_order.h, Bvh::replacesHit).
#include "geometry/pov_bbox.h"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "accel/pov_bbox_root.h"
#include "accel/pov_heap_order.h"
#include "accel/tie_order.h"
#include "render/scene.h"
#include "scene/xml_loader.h"

namespace pvrt {
namespace {

TEST(PovBBox, KeyIsTheFloatDepthWhereTheRayEntersTheBox) {
  // A box from y = 0 to 1 and a ray down the y axis from y = 3: the x and z slabs are not
  // crossed (zero direction, origin inside them), the y slab is entered at 3 - 1 = 2.
  const PovBBox box = makePovBBox(-1, 0, -1, 2, 1, 2);
  EXPECT_EQ(povBBoxKey(box, Ray{{0.25, 3, 0.25}, {0, -1, 0}}), 2.0);
  // A slanted ray: the key is computed from the float origin and the float 1 / direction,
  // as Check_And_Enqueue does, so it is a float value, not the double entry depth.
  const Ray slanted{{0.1, 3, -0.7}, Vec3{0.05, -1, 0.3} / length(Vec3{0.05, -1, 0.3})};
  const float den = float(1.0 / slanted.dir.y);
  const float expected = (0.0f + 1.0f - float(slanted.origin.y)) * den;  // the top face, ray going down
  const double key = povBBoxKey(box, slanted);
  EXPECT_EQ(key, double(float(key)));
  EXPECT_EQ(key, double(expected));
  EXPECT_NE(key, (1.0 - slanted.origin.y) / slanted.dir.y);
}

TEST(PovBBox, ABoxBehindOrBesideTheRayIsNotEnqueued) {
  const PovBBox box = makePovBBox(-1, 0, -1, 2, 1, 2);
  EXPECT_TRUE(std::isinf(povBBoxKey(box, Ray{{0, 3, 0}, {0, 1, 0}})));       // behind
  EXPECT_TRUE(std::isinf(povBBoxKey(box, Ray{{5, 3, 0}, {0, -1, 0}})));      // beside, parallel to x
  EXPECT_LT(povBBoxKey(box, Ray{{0, 0.5, 0}, {0, -1, 0}}), 0.0);             // from inside: negative
}

TEST(PovBBox, RecomputedBoxHoldsTheTurnedCorners) {
  // Recompute_BBox: a unit cube turned 45 degrees about y spans +-sqrt(2)/2 in x and z.
  const PovBBox cube = makePovBBox(-0.5, -0.5, -0.5, 1, 1, 1);
  const PovBBox turned = povRecomputed(cube, Affine::rotate({0, 45, 0}));
  EXPECT_NEAR(turned.lowerLeft[0], -std::sqrt(0.5), 1e-6);
  EXPECT_NEAR(turned.lengths[0], 2 * std::sqrt(0.5), 1e-6);
  EXPECT_NEAR(turned.lowerLeft[1], -0.5, 1e-7);
  EXPECT_NEAR(turned.lengths[1], 1.0, 1e-7);
}

// blind11: POV-Ray tests each object's float box (Intersect_BBox_Dir) before the object. A
// cylinder of radius 0.3 about x = 99998 has its side at x = 99997.7 and its box from the
// float 99997.703125, so a ray that crosses the side between the two meets the cylinder but
// not its box: POV-Ray sees nothing there (a shadow ray in scene far_origin_float_box).
TEST(PovBBox, ARayThroughTheSliverOfAnObjectOutsideItsFloatBoxMissesIt) {
  const Scene scene = buildScene(loadSceneString(
      R"(<scene><cylinder base="0 0 0" cap="0 1.5 0" radius="0.3"><translate v="99998 50000 -299999.5"/></cylinder>
         </scene>)",
      "far.xml"));
  const Primitive cylinder = scene.bvh.primitive(0);
  const std::optional<PovBBox> box = povBBoxOf(cylinder);
  ASSERT_TRUE(box.has_value());
  EXPECT_EQ(box->lowerLeft[0], 99997.703125f);
  // Through x = 99997.7015 at the axis's z, between the side and the box; the float origin,
  // 99997.6953125, is farther from the box still.
  const Ray sliver{{99997.696, 50001, -300001.5}, Vec3{0.00275, 0, 1} / length(Vec3{0.00275, 0, 1})};
  EXPECT_FALSE(povBBoxDirHits(*box, sliver));
  EXPECT_FALSE(cylinder.intersect(sliver, 1e-4, 1e7).has_value());
  uint64_t tests = 0;
  EXPECT_FALSE(scene.bvh.closest(sliver, 1e-4, 1e7, tests).has_value());
  // 0.005 farther in, through the box too: a hit.
  const Ray inside{{99997.701, 50001, -300001.5}, sliver.dir};
  EXPECT_TRUE(povBBoxDirHits(*box, inside));
  EXPECT_TRUE(cylinder.intersect(inside, 1e-4, 1e7).has_value());
}

// blind13: POV-Ray's Box, Sphere and Triangle skip the float box test (their Intersect_BBox
// returns true). A ray lying in a box's face plane, x = 0 with no x direction (the centre
// column of a picture whose camera is on that plane), made pvrt's test (0 - 0) * (1 / 0), NaN,
// and drop the hit: the box showed the wall behind it where POV-Ray shows the box.
TEST(PovBBox, BoxesSpheresAndTrianglesAreNotCutByTheirFloatBox) {
  const Scene scene = buildScene(loadSceneString(
      R"(<scene><box corner1="-1 0 0" corner2="0 1 1"/><sphere center="5 0 0" radius="1"/>
         <triangle p1="9 0 0" p2="11 0 0" p3="10 1 0"/><cylinder base="0 0 5" cap="0 1 5" radius="1"/></scene>)",
      "face.xml"));
  std::optional<Primitive> box;
  for (uint32_t i = 0; i < 4; ++i) {
    const Primitive p = scene.bvh.primitive(i);
    EXPECT_EQ(povTestsBBoxFirst(p), std::holds_alternative<PovConeShape>(p.shape)) << p.shape.index();
    if (std::holds_alternative<BoxShape>(p.shape)) box = p;
  }
  ASSERT_TRUE(box.has_value());
  const Ray inFace{{0, 0.5, -5}, {0, 0, 1}};
  ASSERT_TRUE(povBBoxOf(*box).has_value());
  EXPECT_FALSE(povBBoxDirHits(*povBBoxOf(*box), inFace));  // the NaN, as POV-Ray's test would give
  const std::optional<ShapeHit> hit = box->intersect(inFace, 1e-4, 1e7);
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(hit->t, 5.0);
  uint64_t tests = 0;
  EXPECT_TRUE(scene.bvh.closest(inFace, 1e-4, 1e7, tests).has_value());
}

// A red box from y = 0 to 1 and a green disc lying on its top face, both seen straight down
// at the disc's centre: the two meet the ray at exactly one depth.
std::string boxAndDisc(bool discFirst, int lights) {
  const std::string box = R"(<box corner1="-1 0 -1" corner2="1 1 1"><pigment color="1 0 0"/></box>)";
  const std::string disc = R"(<disc center="0 1 0" normal="0 1 0" radius="0.6"><pigment color="0 1 0"/></disc>)";
  std::string lightXml;
  for (int i = 0; i < lights; ++i) lightXml += R"(<light_source location="3 6 -4"/>)";
  return "<scene><camera location=\"0 3 -3\" look_at=\"0 1 0\"/>" + lightXml + (discFirst ? disc + box : box + disc) +
         "</scene>";
}

uint32_t objectSeen(const Scene& scene, const Ray& ray) {
  uint64_t tests = 0;
  const auto hit = scene.bvh.closest(ray, 1e-4, 1e7, tests);
  EXPECT_TRUE(hit.has_value());
  return hit ? scene.bvh.object(hit->primitive) : ~0u;
}

TEST(TieOrder, ObjectsAndLightsFewerThanThreeTieInDeclarationOrder) {
  const Ray down{{0.1, 3, 0.1}, {0, -1, 0}};
  // Two objects and no light: POV-Ray walks them as declared, and the first one's hit stays.
  const Scene boxFirst = buildScene(loadSceneString(boxAndDisc(false, 0), "tie.xml"));
  EXPECT_EQ(boxFirst.bvh.tieRule(), TieRule::Declaration);
  EXPECT_EQ(objectSeen(boxFirst, down), 0u);  // the box
  const Scene discFirst = buildScene(loadSceneString(boxAndDisc(true, 0), "tie.xml"));
  EXPECT_EQ(objectSeen(discFirst, down), 0u);  // the disc
}

TEST(TieOrder, FromThreeTheObjectWhoseBoxTheRayEntersFirstWins) {
  // With a light the bounding tree decides: the disc's box is padded by SMALL_TOLERANCE above
  // its plane, so the ray enters it first, whichever was declared first (POV-Ray 3.7.0.10
  // shows the disc there: docs/fidelity.md).
  const Ray down{{0.1, 3, 0.1}, {0, -1, 0}};
  for (bool discFirst : {false, true}) {
    const Scene scene = buildScene(loadSceneString(boxAndDisc(discFirst, 1), "tie.xml"));
    EXPECT_EQ(scene.bvh.tieRule(), TieRule::BoxEntry);
    EXPECT_EQ(objectSeen(scene, down), discFirst ? 0u : 1u) << "disc first: " << discFirst;
  }
}

TEST(TieOrder, PacketsDecideTiesAsSingleRays) {
  // Eight rays from one point, four of them onto the disc's tie with the box top, four past
  // the disc onto the box top alone: closestPacket gives each what closest() gives it.
  for (bool discFirst : {false, true})
    for (int lights : {0, 1}) {
      const Scene scene = buildScene(loadSceneString(boxAndDisc(discFirst, lights), "tie.xml"));
      Ray rays[8];
      const Vec3 from{0.05, 3, -0.02};
      for (int k = 0; k < 8; ++k) {
        const Vec3 to{k < 4 ? 0.1 * k - 0.15 : 0.2 * k - 0.2, 1, k % 2 ? 0.1 : -0.2};
        rays[k] = Ray{from, (to - from) / length(to - from)};
      }
      std::optional<ClosestHit> packet[8];
      uint64_t tests = 0;
      scene.bvh.closestPacket(rays, 8, 1e-4, 1e7, packet, tests);
      for (int k = 0; k < 8; ++k) {
        const auto single = scene.bvh.closest(rays[k], 1e-4, 1e7, tests);
        ASSERT_EQ(single.has_value(), packet[k].has_value());
        EXPECT_EQ(single->primitive, packet[k]->primitive) << "ray " << k << " lights " << lights;
        EXPECT_EQ(single->hit.t, packet[k]->hit.t);
      }
    }
}

TEST(TieOrder, EqualPlaneKeysPopFromPovRaysHeapOutOfOrder) {
  // Worked by hand through priority_queue_insert and Priority_Queue_Delete.
  EXPECT_EQ(povPlanePopOrder(0, 2), (std::vector<int>{0, 1}));
  EXPECT_EQ(povPlanePopOrder(0, 3), (std::vector<int>{0, 2, 1}));
  EXPECT_EQ(povPlanePopOrder(1, 3), (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(povPlanePopOrder(2, 3), (std::vector<int>{0, 2, 1}));
  EXPECT_EQ(povPlanePopOrder(0, 4), (std::vector<int>{0, 3, 2, 1}));
  EXPECT_EQ(povPlanePopOrder(4, 4), (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(povPlanePopOrder(3, 5), (std::vector<int>{0, 2, 3, 1, 4}));
}

// Coincident spheres: their boxes are one box, so their keys are equal and POV-Ray's heap
// decides (docs/fidelity.md: with a plane, of a red and a green sphere POV-Ray 3.7.0.10 shows
// the green one; pvrt showed the red). Five coincident spheres: the root holds the five,
// pushed in declaration order onto an empty heap, which pops the first one first.
TEST(TieOrder, ObjectsWithEqualKeysTieInPovRaysHeapOrder) {
  const std::string sphere = R"(<sphere center="0 0 0" radius="1"/>)";
  const Ray ahead{{0.1, 0.05, -5}, {0, 0, 1}};
  const Scene withPlane = buildScene(loadSceneString(
      "<scene>" + sphere + sphere + R"(<plane normal="0 1 0" distance="-3"/></scene>)", "tie.xml"));
  EXPECT_EQ(objectSeen(withPlane, ahead), 1u);
  const Scene five = buildScene(loadSceneString("<scene>" + sphere + sphere + sphere + sphere + sphere + "</scene>", "tie.xml"));
  EXPECT_EQ(objectSeen(five, ahead), 0u);
}

TEST(TieOrder, PovRaysRootHoldsTheObjectsUnlessSplittingThemPays) {
  // Five unit boxes in a row, 2 apart: no split beats sort_and_split's first guess (the whole
  // box's area times size - 3), so the root holds the five boxes themselves.
  std::vector<PovBBox> row;
  for (int k = 0; k < 5; ++k) row.push_back(makePovBBox(2 * k, 0, 0, 1, 1, 1));
  EXPECT_EQ(povRootEntryBoxes(row).size(), 5u);
  // Two clusters of three, 100 apart: cut in two nodes of three, which make the root.
  std::vector<PovBBox> clusters;
  for (double x : {0.0, 1.1, 2.2, 100.0, 101.1, 102.2}) clusters.push_back(makePovBBox(x, 0, 0, 1, 1, 1));
  const std::vector<PovBBox> root = povRootEntryBoxes(clusters);
  ASSERT_EQ(root.size(), 2u);
  EXPECT_EQ(root[0].lowerLeft[0], 0.0f);
  EXPECT_NEAR(root[0].lengths[0], 3.2f, 1e-6);
  EXPECT_EQ(root[1].lowerLeft[0], 100.0f);
}

// blind12: a corridor of two walls and a floor seen along the line where the right wall meets
// the floor (POV-Ray 3.7.0.10 shows the floor there, pvrt showed the wall: reduced from
// scene c10_deep_trace, /tmp/blind12/red/r10_corner.xml). The ray meets both planes at exactly
// one depth; POV-Ray's heap pops the planes first, third, second with nothing else queued,
// first, second, third beside one finite object whose box the ray enters.
TEST(TieOrder, PlanesMetAtOneDepthTieInPovRaysHeapOrder) {
  const std::string planes = R"(<plane normal="1 0 0" distance="-1"/><plane normal="-1 0 0" distance="-1"/>
                                <plane normal="0 1 0" distance="-1"/>)";
  const Ray corner{{0, 0, 0}, Vec3{1, -1, 1} / std::sqrt(3.0)};
  const Scene alone = buildScene(loadSceneString("<scene>" + planes + "</scene>", "corner.xml"));
  EXPECT_EQ(alone.bvh.tieRule(), TieRule::BoxEntry);
  EXPECT_EQ(objectSeen(alone, corner), 2u);  // the floor
  // A sphere beyond the corner, whose box the ray enters: one finite entry queued.
  const Scene beside = buildScene(loadSceneString(
      "<scene>" + planes + R"(<sphere center="2 -2 2" radius="0.1"/></scene>)", "corner.xml"));
  EXPECT_EQ(objectSeen(beside, corner), 1u);  // the right wall
  // A sphere off the ray: none queued, the floor again.
  const Scene off = buildScene(loadSceneString(
      "<scene>" + planes + R"(<sphere center="-2 2 2" radius="0.1"/></scene>)", "corner.xml"));
  EXPECT_EQ(objectSeen(off, corner), 2u);
  // Packets decide as single rays.
  Ray rays[4] = {corner, corner, Ray{{0, 0, 0}, Vec3{0.2, -1, 1} / length(Vec3{0.2, -1, 1})}, corner};
  std::optional<ClosestHit> packet[4];
  uint64_t tests = 0;
  alone.bvh.closestPacket(rays, 4, 1e-4, 1e7, packet, tests);
  for (int k = 0; k < 4; ++k) {
    const auto single = alone.bvh.closest(rays[k], 1e-4, 1e7, tests);
    ASSERT_TRUE(single.has_value() && packet[k].has_value());
    EXPECT_EQ(single->primitive, packet[k]->primitive) << "ray " << k;
  }
}

}  // namespace
}  // namespace pvrt
