// Triangles written alone (triangle, smooth_triangle; not a mesh's), intersected with
// POV-Ray 3.7's own arithmetic so that their hit points and normals, and so their pixels,
// are POV-Ray's bit for bit (docs/fidelity.md). POV-Ray keeps such a triangle in world
// space: every transform moves its vertices at once and the triangle is set up again
// (normal, plane distance, projection axis, and a vertex swap that keeps the projected
// winding one way), so the rounding of each step stays in its vertices. A mesh's
// triangles stay in mesh space instead, as POV-Ray's do (geometry/pov_mesh.h).
#pragma once

#include <optional>

#include "core/ray.h"
#include "core/transform.h"
#include "geometry/robust.h"

namespace pvrt {

// After the last set-up: p1 and p2 as POV-Ray left them (possibly swapped), and its face
// normal normalize((p1 - p2) x (p3 - p2)) computed before that swap.
struct PovTriangleShape { Vec3 p1, p2, p3; Vec3 normal; };
// The same with unit vertex normals (swapped with their vertices).
struct PovSmoothTriangleShape { Vec3 p1, p2, p3; Vec3 n1, n2, n3; Vec3 normal; };

// Builds a lone triangle as POV-Ray's parser does: set up once as written, then once
// after each transform in the order written. A triangle of zero area is degenerate: its
// transforms are skipped and it is never hit (POV-Ray warns "Degenerate triangle").
class PovTriangleBuilder {
 public:
  PovTriangleBuilder(const Vec3& p1, const Vec3& p2, const Vec3& p3);
  // A smooth triangle: its vertex normals made unit (a zero one makes it degenerate).
  PovTriangleBuilder(const Vec3& p1, const Vec3& n1, const Vec3& p2, const Vec3& n2, const Vec3& p3,
                     const Vec3& n3);

  void scale(const Vec3& s);      // vertices times s; normals divided by s, made unit again
  void translate(const Vec3& d);  // vertices plus d
  // Any other transform (rotate, matrix): vertices through `toWorld`, vertex normals
  // through the transpose of `toObject`, not made unit again.
  void transform(const Affine& toWorld, const Affine& toObject);

  // Zero area, or (smooth) vertex normals not all strictly on one side of the face, at
  // some set-up: POV-Ray then skips its later transforms and never hits it.
  bool degenerate() const { return degenerate_; }
  PovTriangleShape flat() const { return {p_[0], p_[1], p_[2], normal_}; }
  PovSmoothTriangleShape smooth() const { return {p_[0], p_[1], p_[2], n_[0], n_[1], n_[2], normal_}; }

 private:
  void setUp();

  Vec3 p_[3], n_[3];
  Vec3 normal_;
  bool smooth_ = false, degenerate_ = false;
};

// POV-Ray's hit of a lone triangle along a unit-direction world ray: the plane's distance
// t, then the hit point's projection tested against the three edges. Hits with
// lo < t < hi and t >= the depth tolerance (times `unit`) only.
std::optional<double> hitPovTriangle(const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& normal,
                                       const Ray& ray, double lo, double hi, double unit);
// The smooth triangle's normal at the hit point `at` (origin + t * dir, as POV-Ray forms
// it), interpolated its way: unit, not yet turned toward the ray.
Vec3 povSmoothNormal(const PovSmoothTriangleShape& t, const Vec3& at);
// The hit point as POV-Ray forms it, origin + t * dir, kept where it is (the shading sees
// POV-Ray's point), with a bound on its distance from the exact plane of the triangle.
SurfacePoint povTrianglePoint(const Vec3& p1, const Vec3& normal, const Vec3& at);

}  // namespace pvrt
