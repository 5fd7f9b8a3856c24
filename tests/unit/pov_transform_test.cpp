// core/pov_transform.h: POV-Ray's transforms, checked against what each must do (maps
// worked out by hand) and against the properties POV-Ray's construction guarantees bit
// for bit (a rotation's inverse is exactly its transpose).
#include <gtest/gtest.h>

#include <cmath>

#include "core/pov_transform.h"

namespace pvrt {
namespace {

void expectVecNear(const Vec3& got, const Vec3& want, double tol = 1e-14) {
  EXPECT_NEAR(got.x, want.x, tol) << "x";
  EXPECT_NEAR(got.y, want.y, tol) << "y";
  EXPECT_NEAR(got.z, want.z, tol) << "z";
}

// The same map as Affine::rotate (x, then y, then z, left-handed), which every transformed
// golden scene already holds to POV-Ray's.
TEST(PovTransform, RotationMapsAsAffineRotateDoes) {
  for (const Vec3 degrees : {Vec3{90, 0, 0}, Vec3{0, 30, 45}, Vec3{10, 20, 30}, Vec3{-75, 200, 5}}) {
    const Transform t = PovTransform::rotation(degrees).toTransform();
    const Affine want = Affine::rotate(degrees);
    for (const Vec3 p : {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}, Vec3{0.3, -2, 5}})
      expectVecNear(t.toWorld.applyPoint(p), want.applyPoint(p));
  }
}

// Each axis turn's inverse is its transpose, and POV-Ray composes the inverses in reverse:
// the inverse it keeps is the matrix transposed exactly, not merely nearly.
TEST(PovTransform, RotationInverseIsTheExactTranspose) {
  const PovTransform r = PovTransform::rotation({10, 20, 30});
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) EXPECT_EQ(r.inverse[i][j], r.matrix[j][i]) << i << "," << j;
}

// Scale, rotate and translate composed in order, and undone by the inverse kept beside.
TEST(PovTransform, ComposedStepsAndTheirInverse) {
  PovTransform t = PovTransform::scaling({2, 3, 4});
  t.then(PovTransform::rotation({0, 0, 90}));  // x -> y, y -> -x
  t.then(PovTransform::translation({1, 1, 1}));
  const Transform m = t.toTransform();
  // (1,1,1) scaled (2,3,4), turned to (-3,2,4), moved to (-2,3,5).
  expectVecNear(m.toWorld.applyPoint({1, 1, 1}), {-2, 3, 5});
  expectVecNear(m.toObject.applyPoint({-2, 3, 5}), {1, 1, 1});
  // Normals go through the inverse transposed: the scaled plane z = 1 keeps normal +z.
  expectVecNear(m.normalToWorld({0, 0, 1}), {0, 0, 1});
}

// A `matrix` keeps the map as written, and the inverse found by cofactors undoes it.
TEST(PovTransform, MatrixAndItsCofactorInverse) {
  const Affine a = Affine::povMatrix({1, 0.5, 0, 0, 2, 0.25, 0.3, 0, 1.5, 4, -2, 1});
  const Transform t = PovTransform::matrixOf(a).toTransform();
  EXPECT_EQ(t.toWorld, a);
  for (const Vec3 p : {Vec3{0, 0, 0}, Vec3{1, 2, 3}, Vec3{-7, 0.5, 11}}) {
    expectVecNear(t.toObject.applyPoint(t.toWorld.applyPoint(p)), p, 1e-13);
    expectVecNear(t.toObject.applyPoint(p), a.inverse()->applyPoint(p), 1e-13);
  }
}

// The canonical shape (axis z, radius 1, height 1) placed on an axis: canonical (0,0,0)
// goes to the origin, (0,0,1) to origin + up * length, (1,0,0) to a point `radius` from
// the axis.
TEST(PovTransform, CoordinateTransformPlacesTheCanonicalShape) {
  const Vec3 origin{1, 2, 3};
  for (const Vec3 up : {Vec3{0, 1, 0}, Vec3{0, 0, 1}, Vec3{0, 0, -1}, normalize(Vec3{1, -2, 0.5})}) {
    const Transform t = PovTransform::coordinate(origin, up, 0.5, 4).toTransform();
    expectVecNear(t.toWorld.applyPoint({0, 0, 0}), origin);
    expectVecNear(t.toWorld.applyPoint({0, 0, 1}), origin + up * 4, 1e-13);
    const Vec3 rim = t.toWorld.applyPoint({1, 0, 0}) - origin;
    EXPECT_NEAR(length(rim), 0.5, 1e-14);
    EXPECT_NEAR(dot(rim, up), 0, 1e-14);
  }
}

}  // namespace
}  // namespace pvrt
