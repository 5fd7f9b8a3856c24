// geometry/pov_triangle.h: lone triangles set up and intersected as POV-Ray does, checked
// against answers worked out by hand, and the bound on the hit point it reports.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "geometry/primitive.h"

namespace pvrt {
namespace {

const Vec3 kZ{0, 0, 1};

void expectVecNear(const Vec3& got, const Vec3& want, double tol = 1e-12) {
  EXPECT_NEAR(got.x, want.x, tol) << "x";
  EXPECT_NEAR(got.y, want.y, tol) << "y";
  EXPECT_NEAR(got.z, want.z, tol) << "z";
}

std::optional<double> hit(const PovTriangleShape& t, const Ray& r) {
  return hitPovTriangle(t.p1, t.p2, t.p3, t.normal, r, 1e-4, 1e7, 1.0);
}

// The right triangle x, y >= 0, x + y <= 1 in z = 0, from z = -5 along +z: t = 5 inside,
// nothing beyond the hypotenuse or left of x = 0, whichever way its corners are written
// (the set-up swaps two corners so that one sign of the edge tests serves both windings),
// and from behind as well.
TEST(PovTriangle, HitsInsideMissesOutsideEitherWinding) {
  for (const auto& shape : {PovTriangleBuilder({0, 0, 0}, {1, 0, 0}, {0, 1, 0}).flat(),
                            PovTriangleBuilder({0, 0, 0}, {0, 1, 0}, {1, 0, 0}).flat()}) {
    const auto t = hit(shape, {{0.25, 0.25, -5}, kZ});
    ASSERT_TRUE(t);
    EXPECT_DOUBLE_EQ(*t, 5.0);
    EXPECT_TRUE(hit(shape, {{0.25, 0.25, 5}, -kZ}));
    EXPECT_FALSE(hit(shape, {{0.6, 0.6, -5}, kZ}));
    EXPECT_FALSE(hit(shape, {{-0.1, 0.5, -5}, kZ}));
    EXPECT_FALSE(hit(shape, {{0.5, -0.1, -5}, kZ}));
    EXPECT_FALSE(hit(shape, {{0.25, 0.25, -5}, {1, 0, 0}}));  // parallel to its plane
  }
}

// The face normal is (p1 - p2) x (p3 - p2) made unit, taken before any swap:
// (-1,0,0) x (-1,1,0) = (0,0,-1) for the first winding, +z for the other.
TEST(PovTriangle, FaceNormalFromTheCornersAsWritten) {
  expectVecNear(PovTriangleBuilder({0, 0, 0}, {1, 0, 0}, {0, 1, 0}).flat().normal, {0, 0, -1}, 0);
  expectVecNear(PovTriangleBuilder({0, 0, 0}, {0, 1, 0}, {1, 0, 0}).flat().normal, {0, 0, 1}, 0);
}

// Corners on one line make no triangle; its transforms are then skipped.
TEST(PovTriangle, ZeroAreaIsDegenerate) {
  PovTriangleBuilder b({0, 0, 0}, {1, 1, 1}, {2, 2, 2});
  EXPECT_TRUE(b.degenerate());
  b.translate({5, 0, 0});
  EXPECT_EQ(b.flat().p1, Vec3(0, 0, 0));
}

// Transforms move the corners one step at a time; the result is the composed map's.
TEST(PovTriangle, StepsMoveTheCornersAsTheComposedMapDoes) {
  PovTriangleBuilder b({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  b.scale({1.5, 1.5, 1.5});
  const Affine rotate = Affine::rotate({0, 30, 45});
  b.transform(rotate, *rotate.inverse());
  b.translate({-0.8, 0.2, 0});
  const Affine all = Affine::scale({1.5, 1.5, 1.5}).then(rotate).then(Affine::translate({-0.8, 0.2, 0}));
  const PovTriangleShape t = b.flat();
  // Corners 1 and 2 may have been swapped by a set-up; corner 3 never is.
  expectVecNear(t.p3, all.applyPoint({0, 1, 0}));
  const bool swapped = length(t.p1 - all.applyPoint({1, 0, 0})) < 1e-12;
  expectVecNear(swapped ? t.p2 : t.p1, all.applyPoint({0, 0, 0}));
}

// A smooth triangle's normal is the interpolation of its unit vertex normals by the hit
// point's barycentric weights, made unit; at the first corner it is that corner's normal.
TEST(PovTriangle, SmoothNormalInterpolatesUnitVertexNormals) {
  const Vec3 n1 = normalize({0, 0, -1}), n2 = normalize({1, 0, -1}), n3 = normalize({0, 2, -2});
  const PovSmoothTriangleShape t = PovTriangleBuilder({0, 0, 0}, {0, 0, -1}, {1, 0, 0}, {1, 0, -1}, {0, 1, 0},
                                                      {0, 2, -2})
                                       .smooth();
  for (const auto& [x, y] : {std::pair{1.0 / 3, 1.0 / 3}, std::pair{0.7, 0.1}, std::pair{0.05, 0.9}}) {
    const Vec3 want = normalize(n1 * (1 - x - y) + n2 * x + n3 * y);
    expectVecNear(povSmoothNormal(t, {x, y, 0}), want);
  }
  // At a corner (whichever was swapped into p1) the normal is that corner's own.
  expectVecNear(povSmoothNormal(t, t.p1), t.n1);
}

// Scaling divides the vertex normals by the scale and makes them unit again (a plane's
// normal under a scale); a smooth triangle whose normals do not all lie on one side of
// its face is degenerate.
TEST(PovTriangle, ScaledNormalsAndDisagreeingNormals) {
  PovTriangleBuilder b({0, 0, 0}, {1, 0, -1}, {1, 0, 0}, {1, 0, -1}, {0, 1, 0}, {1, 0, -1});
  b.scale({2, 1, 1});
  const PovSmoothTriangleShape t = b.smooth();
  for (const Vec3& n : {t.n1, t.n2, t.n3}) expectVecNear(n, normalize({0.5, 0, -1}));
  EXPECT_FALSE(b.degenerate());
  EXPECT_TRUE(PovTriangleBuilder({0, 0, 0}, {0, 0, 1}, {1, 0, 0}, {0, 0, -1}, {0, 1, 0}, {0, 0, 1}).degenerate());
}

// The hit point is kept where the ray puts it; the bound it comes with covers its distance
// from the triangle's exact plane, for triangles far from the origin and rays from afar.
TEST(PovTriangle, HitPointBoundCoversTheDistanceToThePlane) {
  std::mt19937_64 rng(26);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 2000; ++i) {
    const double scale = std::pow(10.0, 4 * u(rng));
    const Vec3 c = Vec3{u(rng), u(rng), u(rng)} * 100.0 * scale;
    const Vec3 p1 = c + Vec3{u(rng), u(rng), u(rng)} * scale, p2 = c + Vec3{u(rng), u(rng), u(rng)} * scale,
               p3 = c + Vec3{u(rng), u(rng), u(rng)} * scale;
    const PovTriangleShape t = PovTriangleBuilder(p1, p2, p3).flat();
    const Vec3 target = (t.p1 + t.p2 + t.p3) / 3.0;
    const Vec3 origin = target + Vec3{u(rng), u(rng), u(rng)} * 50.0 * scale;
    const Ray r{origin, normalize(target - origin)};
    const auto h = hitPovTriangle(t.p1, t.p2, t.p3, t.normal, r, 0, 1e30, 1.0);
    if (!h) continue;
    const SurfacePoint sp = povTrianglePoint(t.p1, t.normal, r.at(*h));
    EXPECT_EQ(sp.p, r.at(*h));
    // The distance from the plane through p1, up to this test's own rounding (far below
    // the bound, which counts the rounding of every coordinate of the point).
    const Vec3 exactN = normalize(cross(p1 - p2, p3 - p2));
    const double off = std::fabs(dot(exactN, sp.p - p1));
    EXPECT_LE(off, dot(vabs(exactN), sp.error) * 1.01 + 1e-300) << i;
  }
}

}  // namespace
}  // namespace pvrt
