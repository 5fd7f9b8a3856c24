#include "core/shared_value.h"

#include <gtest/gtest.h>

#include "scene/scene_desc.h"
#include "scene/xml_loader.h"

namespace pvrt {
namespace {

TEST(SharedValue, DefaultsShareOneValue) {
  SharedValue<FinishDesc> a, b;
  EXPECT_TRUE(a.sharesWith(b));
  EXPECT_EQ(a->diffuse, FinishDesc{}.diffuse);
}

TEST(SharedValue, EditChangesThisCopyOnly) {
  SharedValue<FinishDesc> a;
  SharedValue<FinishDesc> b = a;
  b.edit([](FinishDesc& f) { f.phong = 0.5; });
  EXPECT_EQ(a->phong, 0);
  EXPECT_EQ(b->phong, 0.5);
  EXPECT_FALSE(a.sharesWith(b));
  EXPECT_FALSE(a == b);
}

TEST(SharedValue, ComparesByValue) {
  FinishDesc f;
  f.diffuse = 0.3;
  const SharedValue<FinishDesc> a(f), b(f);
  EXPECT_FALSE(a.sharesWith(b));
  EXPECT_TRUE(a == b);
}

TEST(SharingPool, EqualValuesShareAndUnequalOnesDoNot) {
  SharingPool<InteriorDesc, 4> pool;
  InteriorDesc glass, water;
  glass.ior = 1.5;
  water.ior = 1.33;
  const auto a = pool.share(glass), b = pool.share(water), c = pool.share(glass);
  EXPECT_TRUE(a.sharesWith(c));
  EXPECT_FALSE(a.sharesWith(b));
  EXPECT_EQ(b->ior, 1.33);
}

TEST(SharingPool, ForgetsTheOldestBeyondItsSize) {
  SharingPool<InteriorDesc, 2> pool;
  InteriorDesc v[3];
  for (int i = 0; i < 3; ++i) v[i].ior = 1 + i;
  const auto first = pool.share(v[0]);
  pool.share(v[1]);
  pool.share(v[2]);  // replaces v[0]
  const auto again = pool.share(v[0]);
  EXPECT_FALSE(first.sharesWith(again));
  EXPECT_TRUE(first == again);  // still equal: sharing is never visible
}

// The loader gives equal finishes written on different objects one copy, and different
// ones their own.
TEST(SharingPool, TheLoaderSharesEqualFinishes) {
  const SceneDesc s = loadSceneString(R"(<scene>
  <sphere center="0 0 0" radius="1"><finish phong="0.5"/></sphere>
  <sphere center="2 0 0" radius="1"><finish phong="0.5"/></sphere>
  <sphere center="4 0 0" radius="1"><finish phong="0.7"/></sphere>
</scene>)", "inline.xml");
  ASSERT_EQ(s.objects.size(), 3u);
  EXPECT_TRUE(s.objects[0].material.finish.sharesWith(s.objects[1].material.finish));
  EXPECT_FALSE(s.objects[0].material.finish.sharesWith(s.objects[2].material.finish));
  EXPECT_EQ(s.objects[2].material.finish->phong, 0.7);
}

}  // namespace
}  // namespace pvrt
