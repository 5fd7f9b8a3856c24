// Affine transforms in POV-Ray's conventions: left-handed rotations in degrees (x, then y,
// then z), transforms applied in the order written, POV-Ray's row-vector matrix, inverses,
// and normals carried by the inverse transpose.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/transform.h"
#include "scene/scene_desc.h"

namespace pvrt {
namespace {

void expectVecNear(const Vec3& got, const Vec3& want, double tol = 1e-12) {
  EXPECT_NEAR(got.x, want.x, tol) << "x";
  EXPECT_NEAR(got.y, want.y, tol) << "y";
  EXPECT_NEAR(got.z, want.z, tol) << "z";
}

void expectAffineNear(const Affine& got, const Affine& want, double tol = 1e-12) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(got.m[i][j], want.m[i][j], tol) << "m[" << i << "][" << j << "]";
  expectVecNear(got.t, want.t, tol);
}

TransformStep step(TransformStep::Kind kind, const Vec3& v) {
  TransformStep s{};
  s.kind = kind;
  s.v = v;
  return s;
}

// POV-Ray 3.7: #debug vstr(vrotate(<1,2,3>, <30,40,50>), ", ", 0, 5) prints
// 1.80128, 2.50769, 2.11350.
TEST(Transform, VrotateMatchesPovRay) {
  const Vec3 p = Affine::rotate({30, 40, 50}).applyPoint({1, 2, 3});
  expectVecNear(p, {1.80128, 2.50769, 2.11350}, 1e-5);
  // A rotation keeps lengths: |<1,2,3>| = sqrt(14).
  EXPECT_NEAR(length(p), std::sqrt(14.0), 1e-12);
}

// Left-handed: rotate y*90 takes +x to -z, x*90 takes +y to +z, z*90 takes +x to +y.
TEST(Transform, RotationsAreLeftHanded) {
  expectVecNear(Affine::rotate({0, 90, 0}).applyPoint({1, 0, 0}), {0, 0, -1});
  expectVecNear(Affine::rotate({0, 90, 0}).applyPoint({0, 0, 1}), {1, 0, 0});
  expectVecNear(Affine::rotate({90, 0, 0}).applyPoint({0, 1, 0}), {0, 0, 1});
  expectVecNear(Affine::rotate({0, 0, 90}).applyPoint({1, 0, 0}), {0, 1, 0});
  // 30 degrees about y: x goes to (cos 30, 0, -sin 30).
  expectVecNear(Affine::rotate({0, 30, 0}).applyPoint({1, 0, 0}), {std::sqrt(3.0) / 2, 0, -0.5});
}

// rotate <90,90,0> turns about x first, then y: +y -> +z (x*90) -> +x (y*90). Doing y
// first would give +y -> +y -> +z, so the order is observable.
TEST(Transform, RotateVectorTurnsXThenYThenZ) {
  expectVecNear(Affine::rotate({90, 90, 0}).applyPoint({0, 1, 0}), {1, 0, 0});
  expectAffineNear(Affine::rotate({10, 20, 30}),
                   Affine::rotate({10, 0, 0}).then(Affine::rotate({0, 20, 0})).then(Affine::rotate({0, 0, 30})));
  // +x under <0,90,90>: y*90 -> -z, then z*90 leaves -z alone.
  expectVecNear(Affine::rotate({0, 90, 90}).applyPoint({1, 0, 0}), {0, 0, -1});
}

// scale 2, rotate y*90, translate x, in that order: (1,0,0) -> (2,0,0) -> (0,0,-2) ->
// (1,0,-2). In the reverse order it would be (1,0,0) -> (2,0,0) -> (0,0,-2) -> (0,0,-4).
TEST(Transform, ThenAppliesInWrittenOrder) {
  const Affine a = Affine::scale(Vec3{2}).then(Affine::rotate({0, 90, 0})).then(Affine::translate({1, 0, 0}));
  expectVecNear(a.applyPoint({1, 0, 0}), {1, 0, -2});
  const Affine b = Affine::translate({1, 0, 0}).then(Affine::rotate({0, 90, 0})).then(Affine::scale(Vec3{2}));
  expectVecNear(b.applyPoint({1, 0, 0}), {0, 0, -4});
  // Vectors ignore the translation: (1,0,0) -> (0,0,-2).
  expectVecNear(a.applyVector({1, 0, 0}), {0, 0, -2});
  // then() is the composition of the two maps, on any point.
  const Affine p = Affine::rotate({15, -40, 70}).then(Affine::translate({1, 2, 3}));
  const Affine q = Affine::scale({1, -2, 0.5}).then(Affine::rotate({5, 6, 7}));
  const Vec3 x{0.3, -1.7, 2.2};
  expectVecNear(p.then(q).applyPoint(x), q.applyPoint(p.applyPoint(x)));
}

// matrix <a,b,c, d,e,f, g,h,i, j,k,l> = <2,1,0, 0,3,1, 1,0,1, 4,5,6> on (1,2,3):
// x' = 1*2 + 2*0 + 3*1 + 4 = 9, y' = 1*1 + 2*3 + 3*0 + 5 = 12, z' = 1*0 + 2*1 + 3*1 + 6 = 11.
TEST(Transform, PovMatrixIsRowVectorForm) {
  const Affine m = Affine::povMatrix({2, 1, 0, 0, 3, 1, 1, 0, 1, 4, 5, 6});
  expectVecNear(m.applyPoint({1, 2, 3}), {9, 12, 11}, 0);
  // The origin goes to <j,k,l>; a unit x goes to <a,b,c> + <j,k,l>.
  expectVecNear(m.applyPoint({0, 0, 0}), {4, 5, 6}, 0);
  expectVecNear(m.applyPoint({1, 0, 0}), {6, 6, 6}, 0);
  // det [[2,1,0],[0,3,1],[1,0,1]] = 2*3 - 1*(0-1) + 0 = 7 (transposing does not change it).
  EXPECT_NEAR(m.determinant(), 7.0, 1e-12);
  // POV-Ray's shear matrix <1,0,0, 1,1,0, 0,0,1, 0,0,0> makes x' = x + y.
  expectVecNear(Affine::povMatrix({1, 0, 0, 1, 1, 0, 0, 0, 1, 0, 0, 0}).applyPoint({2, 3, 4}), {5, 3, 4}, 0);
}

// inverse() undoes the map: A^-1(A(p)) = p, and A then A^-1 is the identity.
TEST(Transform, InverseRoundTrips) {
  const Affine povm = Affine::povMatrix({2, 1, 0, 0, 3, 1, 1, 0, 1, 4, 5, 6});
  const auto inv = povm.inverse();
  ASSERT_TRUE(inv);
  // A^-1 of (9,12,11) is (1,2,3) (see PovMatrixIsRowVectorForm).
  expectVecNear(inv->applyPoint({9, 12, 11}), {1, 2, 3});
  expectAffineNear(povm.then(*inv), Affine{});
  expectAffineNear(inv->then(povm), Affine{});

  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> u(-3, 3);
  for (int i = 0; i < 200; ++i) {
    const Affine a = Affine::scale({u(rng) + 3.5, -(u(rng) + 3.5), u(rng) + 3.5})
                         .then(Affine::rotate({60 * u(rng), 60 * u(rng), 60 * u(rng)}))
                         .then(Affine::translate({u(rng), u(rng), u(rng)}));
    const auto ai = a.inverse();
    ASSERT_TRUE(ai);
    const Vec3 p{u(rng), u(rng), u(rng)};
    expectVecNear(ai->applyPoint(a.applyPoint(p)), p, 1e-11);
    expectVecNear(a.applyPoint(ai->applyPoint(p)), p, 1e-11);
    EXPECT_NEAR(a.determinant() * ai->determinant(), 1.0, 1e-12);
  }
  // Transform::from keeps both directions.
  const auto t = Transform::from(povm);
  ASSERT_TRUE(t);
  expectAffineNear(t->toWorld, povm, 0);
  expectAffineNear(t->toObject, *inv, 0);
}

// A matrix that flattens space has no inverse: a zero scale, or rows that depend on each
// other (third row = first + second). Transform::from refuses them too.
TEST(Transform, SingularMatrixHasNoInverse) {
  EXPECT_FALSE(Affine::scale({1, 0, 1}).inverse());
  const Affine dependent = Affine::povMatrix({1, 2, 3, 4, 5, 6, 5, 7, 9, 1, 1, 1});
  EXPECT_NEAR(dependent.determinant(), 0.0, 1e-12);
  EXPECT_FALSE(dependent.inverse());
  EXPECT_FALSE(Transform::from(dependent));
  EXPECT_FALSE(Affine::povMatrix({0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 2, 3}).inverse());
  // Nearly singular: rows (and columns) that depend on each other to 1e-15.
  EXPECT_FALSE(Affine::povMatrix({1, 1, 0, 1, 1 + 1e-15, 0, 0, 0, 1, 0, 0, 0}).inverse());
  // The test is relative: a uniformly tiny (or huge) scale is perfectly invertible.
  const auto tiny = Affine::scale(Vec3{1e-6}).inverse();
  ASSERT_TRUE(tiny);
  expectVecNear(tiny->applyPoint({1e-6, 2e-6, 3e-6}), {1, 2, 3}, 1e-9);
  EXPECT_TRUE(Affine::scale(Vec3{1e6}).inverse());
}

// Scaling one axis far more than the others flattens nothing: the test is relative to the
// rows' and the columns' lengths, not to the largest entry (which called <1e9, 1, 1> and
// <1, 1e-7, 1e-7> singular, so that such a legal scale was refused).
TEST(Transform, AnisotropicScalesAreInvertible) {
  for (const Vec3& s : {Vec3{1e9, 1, 1}, Vec3{1, 1e-7, 1e-7}, Vec3{1e15, 1e-15, 1}, Vec3{1, 1, 1e-16}}) {
    const auto inv = Affine::scale(s).inverse();
    ASSERT_TRUE(inv) << s.x << " " << s.y << " " << s.z;
    expectVecNear(inv->applyPoint(Affine::scale(s).applyPoint({1, 2, 3})), {1, 2, 3}, 1e-12);
  }
  // Turned before or after the scale: its columns, or its rows, stay orthogonal.
  const Affine turn = Affine::rotate({10, 35, 70});
  for (const Affine& a : {turn.then(Affine::scale({1e12, 1, 1})), Affine::scale({1e12, 1, 1}).then(turn)}) {
    const auto inv = a.inverse();
    ASSERT_TRUE(inv);
    // Condition number 1e12: the round trip keeps about 4 of the 16 digits.
    expectVecNear(inv->applyPoint(a.applyPoint({1, 2, 3})), {1, 2, 3}, 1e-3);
  }
}

// The shear y' = x + y (matrix <1,1,0, 0,1,0, 0,0,1, 0,0,0>) takes the plane y=0 to the
// plane y=x, whose unit normal is (-1,1,0)/sqrt(2). The inverse transpose gives exactly
// that; transforming the normal (0,1,0) like a vector would leave it (0,1,0), wrong.
TEST(Transform, NormalsUseTheInverseTranspose) {
  const Affine shear = Affine::povMatrix({1, 1, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0});
  expectVecNear(shear.applyPoint({1, 0, 0}), {1, 1, 0});
  const auto t = Transform::from(shear);
  ASSERT_TRUE(t);
  expectVecNear(t->normalToWorld({0, 1, 0}), Vec3{-1, 1, 0} / std::sqrt(2.0));
  expectVecNear(shear.applyVector({0, 1, 0}), {0, 1, 0});  // the naive (wrong) answer differs
  // A non-uniform scale <2,1,1> turns the sphere normal (1,1,0)/sqrt2 at (1,1,0)/sqrt2 into
  // the ellipsoid's gradient direction (x/4, y) at (2,1)/sqrt2 -> (1,2,0)/sqrt5.
  const auto s = Transform::from(Affine::scale({2, 1, 1}));
  ASSERT_TRUE(s);
  expectVecNear(s->normalToWorld(normalize({1, 1, 0})), Vec3{1, 2, 0} / std::sqrt(5.0));
}

// For any invertible map and any surface with tangents t1, t2 and normal n = t1 x t2, the
// transformed normal is unit, perpendicular to both transformed tangents, and on the side
// of their cross product when the map keeps handedness (det > 0).
TEST(Transform, TransformedNormalsStayPerpendicularToTransformedTangents) {
  std::mt19937_64 rng(77);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 500; ++i) {
    std::array<double, 12> v;
    for (double& x : v) x = u(rng);
    const Affine a = Affine::povMatrix(v);
    if (std::fabs(a.determinant()) < 0.05) continue;  // keep well-conditioned maps
    const auto t = Transform::from(a);
    ASSERT_TRUE(t);
    const Vec3 t1{u(rng), u(rng), u(rng)}, t2{u(rng), u(rng), u(rng)};
    const Vec3 n = cross(t1, t2);
    if (length(n) < 0.05) continue;
    const Vec3 nw = t->normalToWorld(n);
    const Vec3 w1 = a.applyVector(t1), w2 = a.applyVector(t2);
    EXPECT_NEAR(length(nw), 1.0, 1e-12);
    EXPECT_NEAR(dot(nw, w1) / length(w1), 0.0, 1e-9);
    EXPECT_NEAR(dot(nw, w2) / length(w2), 0.0, 1e-9);
    const double side = dot(nw, normalize(cross(w1, w2)));
    EXPECT_NEAR(std::fabs(side), 1.0, 1e-9);
    EXPECT_EQ(side > 0, a.determinant() > 0);
  }
}

TEST(Transform, BasicMapsAndIdentity) {
  EXPECT_TRUE(Affine{}.isIdentity());
  EXPECT_FALSE(Affine::translate({0, 0, 1e-12}).isIdentity());
  EXPECT_DOUBLE_EQ(Affine::scale({2, 3, 4}).determinant(), 24.0);
  expectVecNear(Affine::scale({2, 3, 4}).applyPoint({1, 1, 1}), {2, 3, 4}, 0);
  expectVecNear(Affine::translate({1, 2, 3}).applyPoint({1, 1, 1}), {2, 3, 4}, 0);
  expectVecNear(Affine::translate({1, 2, 3}).applyVector({1, 1, 1}), {1, 1, 1}, 0);
  // A rotation by 0 is exactly the identity; rotations are proper (det +1).
  EXPECT_TRUE(Affine::rotate({0, 0, 0}).isIdentity());
  EXPECT_NEAR(Affine::rotate({33, -71, 12}).determinant(), 1.0, 1e-14);
}

// TransformList::combined applies the steps in the order written, like Affine::then:
// scale 2, rotate y*90, translate x maps (1,0,0) to (1,0,-2); the same steps written in
// reverse map it to (0,0,-4).
TEST(Transform, TransformListCombinesInWrittenOrder) {
  using K = TransformStep::Kind;
  TransformList list;
  list.steps = {step(K::Scale, Vec3{2}), step(K::Rotate, {0, 90, 0}), step(K::Translate, {1, 0, 0})};
  expectVecNear(list.combined().applyPoint({1, 0, 0}), {1, 0, -2});
  TransformList reversed;
  reversed.steps = {step(K::Translate, {1, 0, 0}), step(K::Rotate, {0, 90, 0}), step(K::Scale, Vec3{2})};
  expectVecNear(reversed.combined().applyPoint({1, 0, 0}), {0, 0, -4});
  // The docs' example: scale 2 then translate x takes (1,0,0) to (3,0,0); swapped, (4,0,0).
  TransformList st;
  st.steps = {step(K::Scale, Vec3{2}), step(K::Translate, {1, 0, 0})};
  expectVecNear(st.combined().applyPoint({1, 0, 0}), {3, 0, 0}, 0);
  std::swap(st.steps[0], st.steps[1]);
  expectVecNear(st.combined().applyPoint({1, 0, 0}), {4, 0, 0}, 0);
  // A matrix step: the shear x' = x + y after translate y 1: (1,0,0) -> (1,1,0) -> (2,1,0).
  TransformList withMatrix;
  TransformStep shear{};
  shear.kind = K::Matrix;
  shear.matrix = {1, 0, 0, 1, 1, 0, 0, 0, 1, 0, 0, 0};
  withMatrix.steps = {step(K::Translate, {0, 1, 0}), shear};
  expectVecNear(withMatrix.combined().applyPoint({1, 0, 0}), {2, 1, 0}, 0);
  // No steps: the identity.
  EXPECT_TRUE(TransformList{}.combined().isIdentity());
  EXPECT_TRUE(TransformList{}.empty());
}

}  // namespace
}  // namespace pvrt
