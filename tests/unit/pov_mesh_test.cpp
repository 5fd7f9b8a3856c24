// geometry/pov_mesh.h: a mesh's triangles kept, intersected and shaded as POV-Ray 3.7's
// shape/mesh.cpp does. Each expected value is worked out here from POV-Ray's formulas,
// written out again step by step (Parse_Mesh, Compute_Mesh_Triangle, compute_smooth_triangle,
// Mesh::Intersect, intersect_mesh_triangle, test_hit, Mesh::Normal, Smooth_Mesh_Normal), and
// compared to the bit with what a scene built from XML gives.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>

#include "render/scene.h"
#include "scene/xml_loader.h"

namespace pvrt {
namespace {

// Each value rounded through memory, as POV-Ray's float fields hold it.
double f(double x) {
  volatile float v = float(x);
  return double(v);
}
Vec3 f(const Vec3& v) { return {f(v.x), f(v.y), f(v.z)}; }
double dotPov(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Vec3 unitPov(const Vec3& v) {
  const double k = 1.0 / std::sqrt(dotPov(v, v));
  return {v.x * k, v.y * k, v.z * k};
}
bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
void expectSameBits(const Vec3& got, const Vec3& want) {
  EXPECT_TRUE(sameBits(got.x, want.x)) << got.x << " != " << want.x;
  EXPECT_TRUE(sameBits(got.y, want.y)) << got.y << " != " << want.y;
  EXPECT_TRUE(sameBits(got.z, want.z)) << got.z << " != " << want.z;
}

std::string sceneWith(const std::string& mesh) {
  return "<scene><camera location=\"0.1 2.5 -6\" look_at=\"0 1 0\"/>" + mesh + "</scene>";
}

// The nearest hit of the one mesh in `scene` along `ray`.
struct Found {
  double t;
  Vec3 normal;
};
Found nearest(const Scene& scene, const Ray& ray) {
  uint64_t tests = 0;
  const auto h = scene.bvh.closest(ray, 1e-4, 1e7, tests);
  EXPECT_TRUE(h);
  if (!h) return {0, {}};
  return {h->hit.t, scene.bvh.normal(h->primitive, ray, h->hit)};
}

const Vec3 kP1{0.3, 0.1, 0.7}, kP2{1.1, 0.2, -0.4}, kP3{-0.2, 0.9, 0.25};
const char* kCorners = "p1=\"0.3 0.1 0.7\" p2=\"1.1 0.2 -0.4\" p3=\"-0.2 0.9 0.25\"";
const char* kTransforms = "<scale v=\"1.3 0.7 0.9\"/><rotate v=\"20 35 -10\"/><translate v=\"0.3 1.1 0.2\"/>";

PovTransform meshTransform() {
  PovTransform t = PovTransform::identity();
  t.then(PovTransform::scaling({1.3, 0.7, 0.9}));
  t.then(PovTransform::rotation({20, 35, -10}));
  t.then(PovTransform::translation({0.3, 1.1, 0.2}));
  return t;
}

// The face normal (p3 - p1) x (p2 - p1) made unit in double, then stored as float; the
// plane's distance -(n.p1) stored as float.
void facePlane(const Vec3& p1, const Vec3& p2, const Vec3& p3, Vec3& normal, double& distance) {
  const Vec3 v1 = p2 - p1, v2 = p3 - p1;
  const Vec3 n = unitPov({v2.y * v1.z - v2.z * v1.y, v2.z * v1.x - v2.x * v1.z, v2.x * v1.y - v2.y * v1.x});
  normal = f(n);
  distance = -f(dotPov(n, p1));
}

// A flat triangle of a scaled, turned and moved mesh: the ray carried into mesh space by
// POV-Ray's inverse matrix, its direction made unit there, the plane of the float normal
// and float distance solved along it, and the depth divided by the length; the normal is
// the float normal carried out (MTransNormal) and made unit.
TEST(PovMesh, TransformedFlatTriangleDepthAndNormalArePovRays) {
  const Scene scene =
      buildScene(loadSceneString(sceneWith(std::string("<mesh><triangle ") + kCorners + "/>" + kTransforms + "</mesh>")));
  const Transform trans = meshTransform().toTransform();
  const Vec3 centroid = trans.toWorld.applyPoint((kP1 + kP2 + kP3) / 3.0);
  const Vec3 origin{0.1, 2.5, -6};
  const Ray ray{origin, normalize(centroid - origin)};

  Vec3 n;
  double distance;
  facePlane(kP1, kP2, kP3, n, distance);
  const Vec3 o = trans.toObject.applyPoint(ray.origin);
  Vec3 d = trans.toObject.applyVector(ray.dir);
  const double len = std::sqrt(dotPov(d, d));
  const double k = 1.0 / len;
  d = {d.x * k, d.y * k, d.z * k};
  const double depth = -(distance + dotPov(n, o)) / dotPov(n, d);

  const Found got = nearest(scene, ray);
  EXPECT_TRUE(sameBits(got.t, depth / len)) << got.t << " != " << depth / len;
  expectSameBits(got.normal, unitPov(trans.toObject.applyTransposed(n)));
}

// Without a transform the ray is used as it is, and the float normal is the normal, not
// made unit again; with an identity transform written, the ray still goes through the
// matrices and is made unit again (POV-Ray's Trans is set by any transform).
TEST(PovMesh, UntransformedTriangleKeepsItsFloatNormal) {
  const Scene bare = buildScene(loadSceneString(sceneWith(std::string("<mesh><triangle ") + kCorners + "/></mesh>")));
  const Vec3 origin{0.1, 2.5, -6};
  const Ray ray{origin, normalize((kP1 + kP2 + kP3) / 3.0 - origin)};
  Vec3 n;
  double distance;
  facePlane(kP1, kP2, kP3, n, distance);
  const Found got = nearest(bare, ray);
  EXPECT_TRUE(sameBits(got.t, -(distance + dotPov(n, ray.origin)) / dotPov(n, ray.dir)));
  expectSameBits(got.normal, n);

  const Scene identity = buildScene(
      loadSceneString(sceneWith(std::string("<mesh><triangle ") + kCorners + "/><translate v=\"0 0 0\"/></mesh>")));
  const Transform trans = PovTransform::translation({0, 0, 0}).toTransform();
  Vec3 d = trans.toObject.applyVector(ray.dir);
  const double len = std::sqrt(dotPov(d, d));
  d = d * (1.0 / len);
  const double depth = -(distance + dotPov(n, trans.toObject.applyPoint(ray.origin))) / dotPov(n, d);
  EXPECT_TRUE(sameBits(nearest(identity, ray).t, depth / len));
}

// A smooth triangle of the transformed mesh: the hit point VEvaluateRay of the world ray,
// carried into mesh space; u from the float vector Perp (compute_smooth_triangle, which
// makes it unit and scales it in float), v along the axis of p3 - p2's largest coordinate,
// the float vertex normals interpolated, carried out and made unit.
TEST(PovMesh, SmoothNormalIsSmoothMeshNormalsOfFloatData) {
  const std::string tri = std::string("<smooth_triangle p1=\"0.3 0.1 0.7\" n1=\"0.2 0.3 -1\" p2=\"1.1 0.2 -0.4\" ") +
                          "n2=\"0.7 0.1 -0.6\" p3=\"-0.2 0.9 0.25\" n3=\"-0.3 0.8 -0.5\"/>";
  const Scene scene = buildScene(loadSceneString(sceneWith("<mesh>" + tri + kTransforms + "</mesh>")));
  const Transform trans = meshTransform().toTransform();
  const Vec3 origin{0.1, 2.5, -6};
  const Vec3 aim = trans.toWorld.applyPoint(kP1 * 0.2 + kP2 * 0.5 + kP3 * 0.3);
  const Ray ray{origin, normalize(aim - origin)};
  const Found got = nearest(scene, ray);

  // Set-up (the corners as written): the swap of p1 and p2 where the projected winding
  // runs the other way.
  Vec3 p1 = kP1, p2 = kP2, p3 = kP3;
  Vec3 n1 = unitPov({0.2, 0.3, -1}), n2 = unitPov({0.7, 0.1, -0.6}), n3 = unitPov({-0.3, 0.8, -0.5});
  const Vec3 v1 = p2 - p1, v2 = p3 - p1;
  const Vec3 face = unitPov({v2.y * v1.z - v2.z * v1.y, v2.z * v1.x - v2.x * v1.z, v2.x * v1.y - v2.y * v1.x});
  const Vec3 a = vabs(face);
  const int axis = a.x > a.y ? (a.x > a.z ? 0 : 2) : (a.y > a.z ? 1 : 2);
  const int s = axis == 0 ? 1 : 0, t = axis == 2 ? 1 : 2;
  if ((p2[s] - p3[s]) * (p2[t] - p1[t]) < (p2[t] - p3[t]) * (p2[s] - p1[s])) {
    std::swap(p1, p2);
    std::swap(n1, n2);
  }
  const Vec3 p3p2 = vabs(p3 - p2);
  const int vAxis = p3p2.x > p3p2.y ? (p3p2.x > p3p2.z ? 0 : 2) : (p3p2.y > p3p2.z ? 1 : 2);
  Vec3 t1 = unitPov(p2 - p3);
  const Vec3 t2 = p1 - p3;
  t1 = t1 * dotPov(t2, t1);
  volatile float perp[3] = {float(t1.x - t2.x), float(t1.y - t2.y), float(t1.z - t2.z)};
  volatile float sum = perp[0] * perp[0] + perp[1] * perp[1] + perp[2] * perp[2];
  volatile float len = std::sqrt(float(sum));
  volatile float inv = float(1.0 / double(len));
  for (int i = 0; i < 3; ++i) perp[i] = perp[i] * inv;
  const double uDen = t2.x * double(perp[0]) + t2.y * double(perp[1]) + t2.z * double(perp[2]);
  volatile float scale = float(-uDen);
  volatile float inv2 = float(1.0 / double(scale));
  for (int i = 0; i < 3; ++i) perp[i] = perp[i] * inv2;

  // Smooth_Mesh_Normal at the hit point carried into mesh space.
  const Vec3 at = trans.toObject.applyPoint(ray.at(got.t));
  const Vec3 q1 = f(p1), q2 = f(p2), q3 = f(p3), m1 = f(n1), m2 = f(n2), m3 = f(n3);
  const Vec3 d = at - q1;
  const double u = d.x * double(perp[0]) + d.y * double(perp[1]) + d.z * double(perp[2]);
  ASSERT_GT(u, 1e-10);
  const double v = (d[vAxis] / u + q1[vAxis] - q2[vAxis]) / (q3[vAxis] - q2[vAxis]);
  Vec3 r;
  for (int i = 0; i < 3; ++i) r[i] = m1[i] + u * (m2[i] - m1[i] + v * (m3[i] - m2[i]));
  expectSameBits(got.normal, unitPov(trans.toObject.applyTransposed(r)));
}

// mesh_hash takes a stored float within 1e-10 in every coordinate for a new one: the
// second triangle's face normal, (-1e-17, 0, 1) in double, becomes the first's (0, 0, 1).
TEST(PovMesh, NormalsWithin1e10OfAStoredOneTakeIt) {
  PovMeshBuilder b;
  const PovMeshTriangleShape first = b.triangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  const PovMeshTriangleShape second = b.triangle({0, 0, 0}, {1, 0, 1e-17}, {0, 1, 0});
  EXPECT_EQ(first.normal[0], 0.0f);
  EXPECT_EQ(second.normal[0], 0.0f);
  EXPECT_EQ(std::fabs(second.normal[2]), 1.0f);
  // Alone, the same triangle keeps its own tiny coordinate.
  PovMeshBuilder alone;
  EXPECT_NE(alone.triangle({0, 0, 0}, {1, 0, 1e-17}, {0, 1, 0}).normal[0], 0.0f);
}

// Vertex normals whose unit vectors are all within 1e-10 (squared) of n1 make a flat
// triangle; a zero normal becomes <1, 0, 0>; a degenerate triangle is never hit.
TEST(PovMesh, SmoothTrianglesParserRules) {
  PovMeshBuilder b;
  bool smooth = true;
  b.smoothTriangle({0, 0, 0}, {0, 0, 1}, {1, 0, 0}, {0, 1e-6, 1}, {0, 1, 0}, {0, 0, 1}, smooth);
  EXPECT_FALSE(smooth);
  b.smoothTriangle({0, 0, 0}, {0, 0, 1}, {1, 0, 0}, {0, 1e-4, 1}, {0, 1, 0}, {0, 0, 1}, smooth);
  EXPECT_TRUE(smooth);
  const PovMeshSmoothTriangleShape zero =
      b.smoothTriangle({0, 0, 0}, {0, 0, 0}, {1, 0, 0}, {0, 0, 1}, {0, 1, 0}, {0, 0, 1}, smooth);
  EXPECT_TRUE(smooth);
  bool found = false;
  for (int i = 0; i < 3; ++i) found = found || (zero.n[i][0] == 1.0f && zero.n[i][1] == 0 && zero.n[i][2] == 0);
  EXPECT_TRUE(found);
  const PovMeshTriangleShape line = b.triangle({0, 0, 0}, {1, 1, 1}, {2, 2, 2});
  EXPECT_FALSE(hitPovMeshTriangle(line, {1, 1, -5}, {0, 0, 1}, 1e-6));
}

// A ray through the shared edge of two coplanar triangles (a square's diagonal, seen
// straight on) is hit by both at the same depth, as POV-Ray's edge tests (strict <) let a
// point on an edge pass.
TEST(PovMesh, SharedDiagonalIsHitByBoth) {
  PovMeshBuilder b;
  const PovMeshTriangleShape lower = b.triangle({-1, -1, 1}, {1, -1, 1}, {1, 1, 1});
  const PovMeshTriangleShape upper = b.triangle({-1, -1, 1}, {1, 1, 1}, {-1, 1, 1});
  for (double s : {-0.75, -0.25, 0.0, 0.5}) {
    const Vec3 dir = unitPov({s, s, 1});
    const auto a = hitPovMeshTriangle(lower, {0, 0, 0}, dir, 1e-6), c = hitPovMeshTriangle(upper, {0, 0, 0}, dir, 1e-6);
    ASSERT_TRUE(a && c) << s;
    EXPECT_EQ(*a, *c);
  }
}

// POV-Ray's shadow cache holds an object, and a mesh is one: trying a cached mesh triangle
// tries every triangle of its mesh (Bvh::objectHit), and nothing of another object.
TEST(PovMesh, CachedTriangleStandsForItsWholeMesh) {
  const Scene scene = buildScene(loadSceneString(sceneWith(
      "<mesh><triangle p1=\"-1 0 -1\" p2=\"1 0 -1\" p3=\"1 0 1\"/>"
      "<triangle p1=\"-1 0 -1\" p2=\"1 0 1\" p3=\"-1 0 1\"/></mesh>"
      "<triangle p1=\"-1 0 -1\" p2=\"1 0 -1\" p3=\"1 0 1\"><translate v=\"0 -1 0\"/></triangle>"
      "<sphere center=\"5 0 0\" radius=\"0.5\"/>")));
  ASSERT_EQ(scene.bvh.size(), 4u);
  // A ray down through the mesh's second triangle only (x < z), and the lone triangle below
  // misses there too (it is the first triangle's shape).
  const Ray down{{-0.5, 1, 0.5}, {0, -1, 0}};
  int meshTriangles = 0;
  for (uint32_t i = 0; i < 4; ++i) {
    uint64_t tests = 0;
    const bool alone = scene.bvh.intersect(i, down, 1e-4, 10).has_value();
    const bool whole = scene.bvh.objectHit(i, down, 1e-4, 10, tests);
    if (scene.bvh.object(i) == 0) {  // the mesh
      ++meshTriangles;
      EXPECT_TRUE(whole) << i;
      if (!alone) {
        EXPECT_GE(tests, 2u) << "the other triangle was tried";
      }
    } else {
      EXPECT_EQ(whole, alone) << i;
      EXPECT_FALSE(whole) << i;
      EXPECT_EQ(tests, 1u) << i;
    }
  }
  EXPECT_EQ(meshTriangles, 2);
  // Beyond the range, the mesh is not hit.
  for (uint32_t i = 0; i < 4; ++i) {
    uint64_t tests = 0;
    if (scene.bvh.object(i) == 0) {
      EXPECT_FALSE(scene.bvh.objectHit(i, down, 1e-4, 0.5, tests));
    }
  }
}

}  // namespace
}  // namespace pvrt
