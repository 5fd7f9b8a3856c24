// The material table: one small record per object, and one Surface for every set of
// objects whose finishes and interiors are equal, wherever they were written.
#include <gtest/gtest.h>

#include <vector>

#include "render/material.h"

namespace pvrt {
namespace {

MaterialDesc solid(const Color& c, double diffuse, double ior = 1) {
  MaterialDesc m;
  m.pigment.color = {c, 0, 0};
  m.finish.edit([&](FinishDesc& v) { v.diffuse = diffuse; });
  m.interior.edit([&](InteriorDesc& v) { v.ior = ior; });
  return m;
}

TEST(MaterialTable, EqualFinishesShareOneSurface) {
  MaterialTable table;
  MaterialDesc a = solid({1, 0, 0}, 0.7), b = solid({0, 1, 0}, 0.7), c = solid({0, 0, 1}, 0.5);
  b.finish = FinishDesc(*a.finish);  // equal, but not shared
  for (const MaterialDesc& m : {a, b, c, a}) table.add(m, Affine{});
  ASSERT_EQ(table.size(), 4u);
  EXPECT_EQ(table.surfaces().size(), 2u);
  EXPECT_EQ(table[0].surface, table[1].surface);
  EXPECT_EQ(table[0].surface, table[3].surface);
  EXPECT_NE(table[0].surface, table[2].surface);
  EXPECT_EQ(table.surface(table[2]).finish.diffuse, 0.5);
  EXPECT_EQ(table[1].color.rgb, (Color{0, 1, 0}));
}

// Any field tells surfaces apart, not only those the table hashes.
TEST(MaterialTable, SurfacesDifferingInOneFieldStayApart) {
  MaterialTable table;
  MaterialDesc base = solid({1, 1, 1}, 0.6);
  table.add(base, Affine{});
  MaterialDesc m = base;
  m.finish.edit([&](FinishDesc& v) { v.brilliance = 2; });
  table.add(m, Affine{});
  m = base;
  m.finish.edit([&](FinishDesc& v) { v.reflection.exponent = 0.5; });
  table.add(m, Affine{});
  m = base;
  m.interior.edit([&](InteriorDesc& v) { v.fadeDistance = 3; });
  table.add(m, Affine{});
  m = base;
  m.finish.edit([&](FinishDesc& v) { v.roughness = 0.01; });
  table.add(m, Affine{});
  EXPECT_EQ(table.surfaces().size(), 5u);
  EXPECT_DOUBLE_EQ(table.surface(table[4]).specularExponent, 100);
}

// POV-Ray keeps the ior as a float and, in Post_Process, gives an interior whose ior is 0
// the atmosphere's (1): an ior below the float range refracts nothing (blind9's ior 1e-300
// turned the glass into a dark mirror; POV-Ray passes straight through it).
TEST(MaterialTable, AnIorBelowTheFloatRangeIsTheAtmospheresAsInPovRay) {
  MaterialTable table;
  table.add(solid({1, 1, 1}, 0.1, 1e-300), Affine{});
  table.add(solid({1, 1, 1}, 0.1, 1e-40), Affine{});
  EXPECT_EQ(table.surface(table[0]).interior.ior, 1.0);
  EXPECT_EQ(table.surface(table[1]).interior.ior, double(1e-40f));
}

TEST(MaterialTable, DerivedFlags) {
  MaterialTable table;
  MaterialDesc glass = solid({1, 1, 1}, 0.1, 1.5);
  glass.pigment.color.filter = 0.9;
  glass.finish.edit([&](FinishDesc& v) { v.reflection.max = {0.1, 0.1, 0.1}; });
  glass.finish.edit([&](FinishDesc& v) { v.phong = 0.9; });
  table.add(glass, Affine{});
  table.add(solid({1, 1, 1}, 0.6), Affine{});
  EXPECT_FALSE(table[0].opaque);
  EXPECT_TRUE(table.surface(table[0]).reflective);
  EXPECT_TRUE(table.surface(table[0]).highlights);
  EXPECT_TRUE(table[1].opaque);
  EXPECT_FALSE(table.surface(table[1]).reflective);
  EXPECT_FALSE(table.surface(table[1]).highlights);
  EXPECT_FALSE(table.anyChecker());
}

// A checker alternates its colours by the parity of floor(x) + floor(y) + floor(z) in
// pattern space (the object's transform undone); a see-through second colour makes the
// material see-through.
TEST(MaterialTable, CheckerPigment) {
  MaterialTable table;
  MaterialDesc m;
  m.pigment.checker = std::make_shared<const CheckerDesc>(CheckerDesc{{{1, 1, 1}, 0, 0}, {{0, 0, 0}, 0, 0.5}});
  table.add(m, Affine::translate({0.5, 0, 0}));
  ASSERT_TRUE(table.anyChecker());
  const Material& mat = table[0];
  EXPECT_FALSE(mat.opaque);
  EXPECT_EQ(table.pigmentAt(mat, {0.75, 0.5, 0.5}).rgb, (Color{1, 1, 1}));   // pattern (0.25, .5, .5)
  EXPECT_EQ(table.pigmentAt(mat, {0.25, 0.5, 0.5}).transmit, 0.5);          // pattern (-0.25, .5, .5)
  EXPECT_EQ(table.pigmentAt(mat, {1.75, 1.5, 0.5}).rgb, (Color{1, 1, 1}));  // pattern (1.25, 1.5, .5)
  EXPECT_EQ(table.pigmentAt(mat, {1.75, 0.5, 0.5}).transmit, 0.5);
  // A point a rounding error below a cell's plane falls in the upper cell, as in POV-Ray.
  EXPECT_EQ(table.pigmentAt(mat, {0.5 - 1e-12, 0.5, 0.5}).rgb, (Color{1, 1, 1}));
}

// addObjects builds, on any number of threads, the table that add() builds one object at a
// time: the same materials, surfaces in the same order, the same checkers.
TEST(MaterialTable, AddObjectsIsAddInTurn) {
  std::vector<ObjectDesc> objects(20000);
  for (size_t i = 0; i < objects.size(); ++i) {
    MaterialDesc& m = objects[i].material;
    m = solid({0.1 * double(i % 7), 0.5, 1}, 0.1 * double(1 + (i * 7919) % 9), i % 13 == 0 ? 1.5 : 1);
    if (i % 5 == 0) m.finish.edit([](FinishDesc& f) { f.phong = 0.5; });
    if (i % 17 == 0) m.pigment.color.filter = 0.3;
    if (i % 11 == 0) m.pigment.checker = std::make_shared<const CheckerDesc>(CheckerDesc{{{1, 1, 1}, 0, 0}, {{0, 0, 0}, 0, i % 2 ? 0.5 : 0.0}});
    if (i % 3 == 0) objects[i].transforms.steps.push_back({TransformStep::Kind::Translate, {double(i), 0, 1}, {}, {}});
  }
  MaterialTable one;
  for (const ObjectDesc& o : objects) one.add(o.material, o.transforms.combined());
  ASSERT_GT(one.surfaces().size(), 20u);
  for (int threads : {1, 2, 3, 8}) {
    MaterialTable many;
    many.addObjects(objects, threads);
    ASSERT_EQ(many.size(), one.size());
    EXPECT_EQ(many.surfaces(), one.surfaces()) << threads << " threads";
    for (size_t i = 0; i < one.size(); ++i) {
      const Material &a = one[i], &b = many[i];
      ASSERT_EQ(a.color, b.color) << "object " << i << ", " << threads << " threads";
      ASSERT_EQ(a.surface, b.surface) << "object " << i << ", " << threads << " threads";
      ASSERT_EQ(a.checker, b.checker) << "object " << i << ", " << threads << " threads";
      ASSERT_EQ(a.opaque, b.opaque) << "object " << i << ", " << threads << " threads";
      if (a.checker < 0) continue;
      const Checker &ca = one.checker(a), &cb = many.checker(b);
      ASSERT_EQ(ca.color2, cb.color2);
      ASSERT_EQ(ca.worldToPattern.has_value(), cb.worldToPattern.has_value());
      const Vec3 p{0.3, 1.7, -2.1};
      if (ca.worldToPattern) {
        ASSERT_EQ(ca.worldToPattern->applyPoint(p), cb.worldToPattern->applyPoint(p));
      }
    }
  }
}

}  // namespace
}  // namespace pvrt
