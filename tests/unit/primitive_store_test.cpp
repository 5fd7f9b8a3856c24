// PrimitiveStore: an untransformed sphere or plane is its 48-byte record alone; every other
// shape keeps its Primitive beside its record, and each comes back whole.
#include "geometry/primitive_store.h"

#include <gtest/gtest.h>

#include <cstring>

namespace pvrt {
namespace {

Primitive make(Shape shape, uint32_t object, SharedTransform transform = nullptr) {
  Primitive p{std::move(shape), std::move(transform), object + 100, object, object % 2 == 1, object % 3 != 0};
  p.unit = 0.25f * float(object + 1);
  return p;
}

bool sameBounds(const Bounds& a, const Bounds& b) {
  return std::memcmp(&a.lo, &b.lo, sizeof(Vec3)) == 0 && std::memcmp(&a.hi, &b.hi, sizeof(Vec3)) == 0;
}

TEST(PrimitiveStore, SpheresAndPlanesAreTheirRecordsAlone) {
  const SharedTransform scaled = share(Transform::from(Affine::scale({1, 2, 3})));
  std::vector<Primitive> prims{
      make(SphereShape{{1, 2, 3}, 0.5}, 0),
      make(PlaneShape{{0, 1, 0}, -1}, 1),
      make(SphereShape{{4, 5, 6}, 2}, 2, scaled),  // transformed: kept whole
      make(BoxShape{{0, 0, 0}, {1, 2, 3}}, 3),
      make(PovMeshBuilder().triangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0}), 4),
  };
  const std::vector<Primitive> original = prims;
  const PrimitiveStore store(std::move(prims));
  ASSERT_EQ(store.size(), original.size());
  EXPECT_EQ(store.others.size(), 3u);
  EXPECT_EQ(store.records[0].kind, PrimitiveRecord::Kind::Sphere);
  EXPECT_EQ(store.records[1].kind, PrimitiveRecord::Kind::Plane);
  EXPECT_EQ(store.records[2].kind, PrimitiveRecord::Kind::Other);
  EXPECT_EQ(store.records[4].other, 2u);
  for (size_t i = 0; i < original.size(); ++i) {
    const Primitive back = store.primitive(i);
    const Primitive& want = original[i];
    EXPECT_EQ(back.shape.index(), want.shape.index()) << i;
    EXPECT_EQ(back.transform, want.transform) << i;
    EXPECT_EQ(back.material, want.material) << i;
    EXPECT_EQ(back.object, want.object) << i;
    EXPECT_EQ(back.noShadow, want.noShadow) << i;
    EXPECT_EQ(back.opaque, want.opaque) << i;
    EXPECT_EQ(back.unit, want.unit) << i;
    EXPECT_TRUE(sameBounds(store.bounds(i), want.bounds())) << i;
    const PrimitiveRecord& r = store.records[i];
    EXPECT_EQ(r.material, want.material);
    EXPECT_EQ(r.object, want.object);
    EXPECT_EQ(r.noShadow, want.noShadow);
    EXPECT_EQ(r.opaque, want.opaque);
  }
  EXPECT_TRUE(store.bounds(1).empty());  // the plane
}

TEST(PrimitiveStore, SetUnitReachesRecordAndPrimitive) {
  PrimitiveStore store(std::vector<Primitive>{make(SphereShape{{0, 0, 0}, 1}, 0),
                                              make(BoxShape{{0, 0, 0}, {1, 1, 1}}, 1)});
  store.setUnit(0, 3.0f);
  store.setUnit(1, 5.0f);
  EXPECT_EQ(store.records[0].unit, 3.0f);
  EXPECT_EQ(store.records[1].unit, 5.0f);
  EXPECT_EQ(store.others[0].unit, 5.0f);
  EXPECT_EQ(store.primitive(1).unit, 5.0f);
}

}  // namespace
}  // namespace pvrt
