// Renderable shapes after the build stage: world-space data ready for intersection.
// A closed set of shape types dispatched by std::variant (no virtual call per ray).
// Each shape intersects in its own object space when it carries a transform.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <utility>
#include <variant>

#include "core/ray.h"
#include "core/transform.h"
#include "geometry/bounds.h"
#include "geometry/pov_bbox.h"
#include "geometry/pov_cone.h"
#include "geometry/pov_disc.h"
#include "geometry/pov_mesh.h"
#include "geometry/pov_triangle.h"
#include "geometry/robust.h"

namespace pvrt {

// POV-Ray's tolerances (shared/povray-semantics.md section 7), for a scene whose length
// unit is 1; every one that is a length is multiplied by the scene's unit (Primitive::unit,
// render/spawn.h), which is 1 for scenes of ordinary size (docs/robustness.md).
inline constexpr double kDepthTolerance = 1e-6;   // spheres, planes, boxes, discs, triangles
inline constexpr double kConeTolerance = 1e-9;    // cylinders and cones
inline constexpr double kPovEpsilon = 1e-10;
inline constexpr double kMinIsectDepth = 1e-4;    // every hit closer than this is ignored
inline constexpr double kMaxDistance = 1e7;       // every hit farther than this is dropped
inline constexpr double kBoxCloseTolerance = 1e-6;  // box slab depths this close meet at an edge

// Spheres farther than this many squared radii from the ray's origin are tested with
// Haines's arithmetic (below): POV-Ray's r^2 - |oc|^2 + (oc.d)^2 loses about
// 2u |oc|^2 to cancellation, which at 10^5 radii is 10^-6 of r^2 and grows from there
// until its silhouettes and hit depths are noise. Nearer, POV-Ray's own arithmetic.
inline constexpr double kPovSphereReach2 = 1e10;

struct SphereShape { Vec3 center; double radius; };
struct PlaneShape { Vec3 normal; double distance; };  // unit normal; n.X = d
struct BoxShape { Vec3 lo, hi; };
// Cylinders, cones and discs are PovConeShape and PovDiscShape (geometry/pov_cone.h,
// pov_disc.h): POV-Ray's canonical shapes, always with their transforms. Lone triangles are
// PovTriangleShape and PovSmoothTriangleShape (geometry/pov_triangle.h), in world space; a
// mesh's are PovMeshTriangleShape and PovMeshSmoothTriangleShape (geometry/pov_mesh.h), in
// mesh space, with the mesh's transform (when it has one) shared by all of them.
using Shape = std::variant<SphereShape, PlaneShape, BoxShape, PovConeShape, PovDiscShape, PovTriangleShape,
                           PovSmoothTriangleShape, PovMeshTriangleShape, PovMeshSmoothTriangleShape>;

// The nearest hit of one primitive: its distance along the world ray and whatever the
// shape needs later to compute its normal (face of a box, part of a cylinder, ...).
struct ShapeHit {
  double t = 0;
  int part = 0;  // shape-specific: box face, cylinder side/cap
  double u = 0, v = 0;  // barycentrics for triangles
};

struct Primitive {
  Shape shape;
  SharedTransform transform;  // object -> world, when the shape is not in world space
  uint32_t material = 0;
  uint32_t object = 0;  // index of the ObjectDesc it came from (meshes give many primitives)
  bool noShadow = false;
  bool opaque = true;  // its material lets no light through: a shadow ray hitting it is blocked
  float unit = 1.0f;   // the scene's length unit: the shape tolerances above are multiplied by it
  // POV-Ray's float bounding box of the object (povBBoxOf), made once when the scene's store
  // takes the primitive (PrimitiveStore::compact), since every hit tests it; povBBox() makes it
  // for a primitive made by hand.
  bool povBoxKnown = false;
  std::optional<PovBBox> povBox{};
  // POV-Ray's bounding tree holds the object (a scene of at least Bounding_Threshold objects
  // and lights: Bvh::setTieRule), so a ray reaches it only where Check_And_Enqueue's float
  // slabs let its box in, as well as Intersect_BBox's.
  bool povTreeLeaf = false;

  // Nearest hit with tMin < t < tMax along `ray` (world space). Counts nothing. `throughTree`
  // false: the object tested alone, as POV-Ray's FindIntersection(object, ...) tests the shadow
  // cache's object (its Intersect_BBox, but no leaf of the bounding tree: povTreeLeaf ignored).
  std::optional<ShapeHit> intersect(const Ray& ray, double tMin, double tMax, bool throughTree = true) const;
  // POV-Ray's hit point, origin + t * dir (world space), with a bound on its distance
  // from the surface.
  SurfacePoint surfacePoint(const Ray& ray, const ShapeHit& hit) const;
  // Geometric normal at the hit (world space, unit, not yet flipped toward the ray).
  Vec3 normal(const Ray& ray, const ShapeHit& hit) const;
  // povBox, or where it is not known yet, povBBoxOf(*this).
  std::optional<PovBBox> povBBox() const { return povBoxKnown ? povBox : povBBoxOf(*this); }
  // World-space bounds; empty() for unbounded shapes (planes).
  Bounds bounds() const;
  // POV-Ray's Inside(): is the world point inside the solid? (false for flat shapes
  // that have no inside, such as triangles).
  bool inside(const Vec3& p) const;
};

namespace detail {
// The nearest of two candidate roots that lies inside (lo, hi).
inline std::optional<double> nearestRoot(double t1, double t2, double lo, double hi) {
  if (t1 > t2) std::swap(t1, t2);
  if (t1 > lo && t1 < hi) return t1;
  if (t2 > lo && t2 < hi) return t2;
  return std::nullopt;
}

// The sphere test on a direction taken as unit length (world rays are; local rays of
// transformed spheres are normalised by the caller, as POV-Ray does). POV-Ray's
// Sphere::Intersect (shape/spheres.cpp), operation for operation, so that hit depths and
// hit points are POV-Ray's to the bit (docs/fidelity.md); for spheres beyond
// kPovSphereReach2, Haines et al.'s careful arithmetic (Ray Tracing Gems, chapter 7): the
// squared half chord r^2 - |f - (f.d)d|^2 from the perpendicular distance, and the stable
// pair of roots q and c / q.
inline std::optional<ShapeHit> hitUnitSphere(const Vec3& center, double r2, const Vec3& origin, const Vec3& dir,
                                             double lo, double hi, double unit) {
  const Vec3 oc = center - origin;
  const double ocSquared = dot(oc, oc);
  const double closest = dot(oc, dir);  // distance to the point of closest approach
  if (ocSquared >= r2 && closest < kPovEpsilon * unit) return std::nullopt;
  const double eps = kPovEpsilon * unit * unit;
  double t1, t2;
  if (ocSquared <= kPovSphereReach2 * r2) {
    const double halfChord2 = r2 - ocSquared + closest * closest;
    if (!(halfChord2 > eps)) return std::nullopt;
    const double halfChord = std::sqrt(halfChord2);
    t1 = closest - halfChord;
    t2 = closest + halfChord;
  } else {
    const Vec3 perp = oc - dir * closest;
    const double halfChord2 = r2 - dot(perp, perp);
    if (!(halfChord2 > eps)) return std::nullopt;
    t2 = closest + std::copysign(std::sqrt(halfChord2), closest);  // the root farther from 0
    t1 = (ocSquared - r2) / t2;                                     // the product of the roots over it
  }
  const auto t = nearestRoot(t1, t2, std::max(lo, kDepthTolerance * unit), hi);
  if (!t) return std::nullopt;
  return ShapeHit{*t};
}

// The plane test. Tested against every ray (planes are unbounded), so the two tolerance
// checks compare squares instead of taking the direction's length: |nd| < eps |D| and
// t |D| <= depth (`unit` scales the depth tolerance).
inline std::optional<ShapeHit> hitPlane(const PlaneShape& p, const Ray& ray, double lo, double hi, double unit) {
  const double nd = dot(p.normal, ray.dir);
  const double len2 = dot(ray.dir, ray.dir);
  if (nd * nd < kPovEpsilon * kPovEpsilon * len2) return std::nullopt;
  const double t = (p.distance - dot(p.normal, ray.origin)) / nd;
  const double depth = kDepthTolerance * unit;
  if (t <= lo || t >= hi || t * t * len2 <= depth * depth) return std::nullopt;
  return ShapeHit{t};
}

}  // namespace detail

// intersect() of an untransformed sphere, for callers that keep spheres in a compact
// array of their own (the BVH's leaves): the same arithmetic, so the same answers; inline
// so that the BVH's leaf loops compile it into themselves.
inline std::optional<ShapeHit> intersectWorldSphere(const SphereShape& s, float unit, const Ray& ray, double tMin,
                                                    double tMax) {
  return detail::hitUnitSphere(s.center, s.radius * s.radius, ray.origin, ray.dir, tMin, tMax, unit);
}

// The hit point p of an untransformed sphere moved onto its surface, with the bound on its
// error (pbrt-v4's), and the sphere's normal there: Primitive's for spheres, inline for
// callers that keep spheres in a compact array of their own.
inline SurfacePoint sphereSurfacePoint(const SphereShape& s, const Vec3& p) {
  const Vec3 v = p - s.center;
  const double len = length(v);
  if (!(len > 0)) return {p, vabs(p) * errorGamma(8) + Vec3(s.radius * errorGamma(8))};
  const Vec3 q = s.center + v * (s.radius / len);
  return {q, (vabs(q - s.center) + vabs(q)) * errorGamma(6)};
}
// A hit point p moved onto the plane through `at` with unit normal n, with the bound on
// its error (planes and discs).
inline SurfacePoint flatSurfacePoint(const Vec3& n, const Vec3& at, const Vec3& p) {
  const Vec3 q = p - n * dot(n, p - at);
  return {q, (vabs(q) + vabs(at)) * errorGamma(8)};
}
// The hit point p of an untransformed plane moved onto it.
inline SurfacePoint planeSurfacePoint(const PlaneShape& s, const Vec3& p) {
  return flatSurfacePoint(s.normal, s.normal * s.distance, p);
}
// POV-Ray's hit point p on an untransformed sphere or plane, with the bound on its
// distance from the surface (Primitive::surfacePoint's answer).
inline SurfacePoint sphereHitPoint(const SphereShape& s, const Vec3& p) {
  return hitPointNear(p, sphereSurfacePoint(s, p));
}
inline SurfacePoint planeHitPoint(const PlaneShape& s, const Vec3& p) {
  return hitPointNear(p, planeSurfacePoint(s, p));
}
// (P - C) times 1 / r (Sphere::Normal: VInverseScaleEq), unit but for rounding, as
// POV-Ray leaves it.
inline Vec3 sphereNormal(const SphereShape& s, const Vec3& p) { return (p - s.center) * (1.0 / s.radius); }

}  // namespace pvrt
