// Ray-shape intersection, normals, bounds and inside tests for every shape.
// Each intersector works on an arbitrary (not necessarily unit) direction D and
// returns the ray parameter t; tolerances are POV-Ray's, measured along unit rays and
// multiplied by the scene's length unit (docs/robustness.md).
#include "geometry/primitive.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>

#include "geometry/pov_bbox.h"

namespace pvrt {

namespace {

using detail::hitUnitSphere;
using detail::nearestRoot;

// ---------------------------------------------------------------- sphere

std::optional<ShapeHit> hitSphere(const SphereShape& s, const Ray& ray, double lo, double hi, bool unitDir,
                                  double unit) {
  if (unitDir) return hitUnitSphere(s.center, s.radius * s.radius, ray.origin, ray.dir, lo, hi, unit);
  const double len = length(ray.dir);
  auto h = hitUnitSphere(s.center, s.radius * s.radius, ray.origin, ray.dir / len, lo * len, hi * len, unit);
  if (h) h->t /= len;
  return h;
}

// ---------------------------------------------------------------- box

// POV-Ray's slab test (Box::Intersect in shape/boxes.cpp), decision for decision: the x,
// y and z slabs in turn, the entry depth from 0 up and the exit depth down. Where a y or z
// depth comes within kBoxCloseTolerance of the one found so far (the ray meets an edge),
// the depth stays and the face becomes the later slab's when the ray runs more along its
// axis: at an edge hit exactly (round numbers do it) POV-Ray shades the face the ray
// faces more squarely, where a plain slab test keeps the first axis's.
std::optional<ShapeHit> hitBox(const BoxShape& b, const Ray& ray, double lo, double hi, double unit) {
  const Vec3& d = ray.dir;
  const double len = length(d);  // 1 but for the local rays of turned boxes
  const double close = kBoxCloseTolerance * unit;
  // Does the ray run more along axis a than along the axis of `face` (POV-Ray compares y
  // with x whatever face holds, and z with the held face's axis)?
  const auto squarer = [&d](int a, int face) {
    if (a == 1) return std::fabs(d.y) > std::fabs(d.x);
    return a == 2 && face >= 0 && std::fabs(d.z) > std::fabs(d[face / 2]);
  };
  double tNear = 0, tFar = INFINITY;
  int nearFace = -1, farFace = -1;
  for (int a = 0; a < 3; ++a) {
    const double o = ray.origin[a];
    // Parallel to this slab: POV-Ray's EPSILON on the direction as it is, the world ray's or,
    // for a turned box, the one MInvTransDirection gives (not made unit).
    if (std::fabs(d[a]) <= kPovEpsilon) {
      if (o < b.lo[a] || o > b.hi[a]) return std::nullopt;
      continue;
    }
    const bool rising = d[a] > 0;  // face 2a is the low side, 2a+1 the high side
    const double tIn = ((rising ? b.lo[a] : b.hi[a]) - o) / d[a];
    const double tOut = ((rising ? b.hi[a] : b.lo[a]) - o) / d[a];
    const int fIn = 2 * a + (rising ? 0 : 1), fOut = 2 * a + (rising ? 1 : 0);
    const double tol = a == 0 ? 0 : close;  // the first slab has nothing to be close to
    if (tOut < tNear) return std::nullopt;
    if (tOut <= tFar - tol) {
      tFar = tOut;
      farFace = fOut;
    } else if (tOut <= tFar + tol && squarer(a, farFace)) {
      farFace = fOut;
    }
    if (tIn >= tNear + tol) {
      if (tIn > tFar) return std::nullopt;
      tNear = tIn;
      nearFace = fIn;
    } else if (tIn >= tNear - tol && squarer(a, nearFace)) {
      nearFace = fIn;
    }
  }
  const double minT = std::max(lo, kDepthTolerance * unit / len);
  // All_Intersections pushes the entry depth, then the exit depth, and Find_Intersection
  // pops them from the top keeping only a strictly nearer one: a ray that enters and leaves
  // at one depth, along an edge, is given the exit side.
  if (tNear > minT && tNear < hi && nearFace >= 0)
    return ShapeHit{tNear, tFar == tNear && farFace >= 0 ? farFace : nearFace};
  if (tFar > minT && tFar < hi && farFace >= 0) return ShapeHit{tFar, farFace};
  return std::nullopt;
}

// ---------------------------------------------------------------- mesh triangles

// Mesh::Intersect and test_hit for one triangle: the ray carried into mesh space
// (MInvTransPoint, MInvTransDirection) with its direction made unit there (times 1 / len),
// the triangle's depth along it, and the world depth depth / len. Without a transform the
// world ray itself, len 1.
std::optional<ShapeHit> hitMeshTriangle(const PovMeshTriangleShape& t, const Transform* transform, const Ray& ray,
                                        double lo, double hi, double unit) {
  if (t.axis == PovMeshTriangleShape::kNever) return std::nullopt;
  if (!transform) {
    const auto depth = hitPovMeshTriangle(t, ray.origin, ray.dir, kDepthTolerance * unit);
    if (!depth || *depth <= lo || *depth >= hi) return std::nullopt;
    return ShapeHit{*depth};
  }
  // A ray meets many triangles of one mesh in a row (a BVH leaf holds neighbours): the last
  // mesh-space ray is kept, per thread, and used again for the same ray and transform (the
  // same bits, compared as bits: a turned mesh of 10^5 triangles rendered in 3.2 s of CPU
  // instead of 3.6).
  struct MeshRay {
    const Transform* transform = nullptr;
    Vec3 origin, dir;          // the world ray
    Vec3 meshOrigin, meshDir;  // in mesh space, the direction unit
    double len = 0;
  };
  thread_local MeshRay last;
  if (last.transform != transform || std::memcmp(&last.origin, &ray.origin, sizeof(Vec3)) != 0 ||
      std::memcmp(&last.dir, &ray.dir, sizeof(Vec3)) != 0) {
    last.transform = transform;
    last.origin = ray.origin;
    last.dir = ray.dir;
    last.meshOrigin = transform->toObject.applyPoint(ray.origin);
    const Vec3 dir = transform->toObject.applyVector(ray.dir);
    last.len = std::sqrt(dir.x * dir.x + dir.y * dir.y + dir.z * dir.z);
    const double k = 1.0 / last.len;
    last.meshDir = {dir.x * k, dir.y * k, dir.z * k};
  }
  const auto depth = hitPovMeshTriangle(t, last.meshOrigin, last.meshDir, kDepthTolerance * unit);
  if (!depth) return std::nullopt;
  const double world = *depth / last.len;
  if (world <= lo || world >= hi) return std::nullopt;
  return ShapeHit{world};
}

struct Intersector {
  const Ray& ray;
  double lo, hi;
  bool unitDir;  // world rays have unit directions; local rays of transformed shapes need not
  double unit;   // the scene's length unit, for the shape tolerances
  std::optional<ShapeHit> operator()(const SphereShape& s) const { return hitSphere(s, ray, lo, hi, unitDir, unit); }
  std::optional<ShapeHit> operator()(const PlaneShape& p) const { return detail::hitPlane(p, ray, lo, hi, unit); }
  std::optional<ShapeHit> operator()(const BoxShape& b) const { return hitBox(b, ray, lo, hi, unit); }
  std::optional<ShapeHit> operator()(const PovDiscShape& d) const {
    const auto t = hitPovDisc(d, ray, lo, hi, unit);
    if (!t) return std::nullopt;
    return ShapeHit{*t};
  }
  // Primitive::intersect answers these before it makes a local ray.
  std::optional<ShapeHit> operator()(const PovMeshTriangleShape&) const { return std::nullopt; }
  std::optional<ShapeHit> operator()(const PovTriangleShape& t) const { return pov(t.p1, t.p2, t.p3, t.normal); }
  std::optional<ShapeHit> operator()(const PovSmoothTriangleShape& t) const {
    return pov(t.p1, t.p2, t.p3, t.normal);
  }
  std::optional<ShapeHit> operator()(const PovConeShape& c) const {
    const auto h = hitPovCone(c, ray, lo, hi, unit);
    if (!h) return std::nullopt;
    return ShapeHit{h->t, h->part};
  }
  std::optional<ShapeHit> pov(const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& n) const {
    const auto t = hitPovTriangle(p1, p2, p3, n, ray, lo, hi, unit);
    if (!t) return std::nullopt;
    return ShapeHit{*t};
  }
};

// The object-space hit point p moved onto the exact surface, with a bound on its error
// per component (pbrt-v4's bounds for spheres and triangles, generous ones elsewhere).
// Only the distance from the surface matters: an error along the surface merely moves
// the point along it.
struct Reproject {
  const Vec3& p;
  const ShapeHit& hit;
  SurfacePoint operator()(const SphereShape& s) const { return sphereSurfacePoint(s, p); }
  SurfacePoint operator()(const PlaneShape& s) const { return planeSurfacePoint(s, p); }
  SurfacePoint operator()(const BoxShape& b) const {
    // The face's own coordinate is exact; the other two are where the ray put them.
    const int axis = hit.part / 2;
    Vec3 q = p;
    q[axis] = hit.part % 2 ? b.hi[axis] : b.lo[axis];
    Vec3 error = vabs(q) * errorGamma(1);
    error[axis] = 0;
    return {q, error};
  }
  SurfacePoint operator()(const PovDiscShape&) const { return povDiscSurfacePoint(p); }
  SurfacePoint operator()(const PovMeshTriangleShape& t) const {
    return flatSurfacePoint(t.faceNormal(), t.corner(0), p);
  }
  SurfacePoint operator()(const PovTriangleShape& t) const { return flatSurfacePoint(t.normal, t.p1, p); }
  SurfacePoint operator()(const PovSmoothTriangleShape& t) const { return flatSurfacePoint(t.normal, t.p1, p); }
  SurfacePoint operator()(const PovConeShape& c) const { return povConeSurfacePoint(c, p, hit.part); }
};

// Object-space normal at object-space point p.
struct Normal {
  const Vec3& p;
  const ShapeHit& hit;
  Vec3 operator()(const SphereShape& s) const { return sphereNormal(s, p); }
  Vec3 operator()(const PlaneShape& s) const { return s.normal; }
  Vec3 operator()(const BoxShape&) const {
    Vec3 n;
    n[hit.part / 2] = hit.part % 2 ? 1.0 : -1.0;
    return n;
  }
  Vec3 operator()(const PovDiscShape& d) const { return d.normal; }  // world space already (Primitive::normal)
  // A mesh's: the float face normal, and a smooth one's interpolated normal not yet made
  // unit (Primitive::normal makes it unit, before or after carrying it out of mesh space).
  Vec3 operator()(const PovMeshTriangleShape& t) const { return t.faceNormal(); }
  Vec3 operator()(const PovMeshSmoothTriangleShape& t) const { return povSmoothMeshNormal(t, p); }
  Vec3 operator()(const PovTriangleShape& t) const { return t.normal; }
  Vec3 operator()(const PovSmoothTriangleShape& t) const { return povSmoothNormal(t, p); }
  Vec3 operator()(const PovConeShape& c) const { return povConeNormal(c, p, hit.part); }
};

struct LocalBounds {
  Bounds operator()(const SphereShape& s) const {
    return {s.center - Vec3(s.radius), s.center + Vec3(s.radius)};
  }
  Bounds operator()(const PlaneShape&) const { return {}; }
  Bounds operator()(const BoxShape& b) const { return {b.lo, b.hi}; }
  Bounds operator()(const PovDiscShape& d) const { return povDiscBounds(d); }
  Bounds operator()(const PovMeshTriangleShape& t) const { return tri(t.corner(0), t.corner(1), t.corner(2)); }
  Bounds operator()(const PovTriangleShape& t) const { return tri(t.p1, t.p2, t.p3); }
  Bounds operator()(const PovSmoothTriangleShape& t) const { return tri(t.p1, t.p2, t.p3); }
  Bounds operator()(const PovConeShape& c) const { return povConeBounds(c); }
  static Bounds tri(const Vec3& a, const Vec3& b, const Vec3& c) {
    Bounds r;
    r.extend(a);
    r.extend(b);
    r.extend(c);
    return r;
  }
};

struct Inside {
  const Vec3& p;
  bool operator()(const SphereShape& s) const {
    const Vec3 d = p - s.center;
    return dot(d, d) < s.radius * s.radius;
  }
  bool operator()(const PlaneShape& s) const { return dot(s.normal, p) - s.distance < kPovEpsilon; }
  bool operator()(const BoxShape& b) const {
    return p.x >= b.lo.x && p.x <= b.hi.x && p.y >= b.lo.y && p.y <= b.hi.y && p.z >= b.lo.z && p.z <= b.hi.z;
  }
  bool operator()(const PovDiscShape&) const { return povDiscInside(p); }
  bool operator()(const PovMeshTriangleShape&) const { return false; }
  bool operator()(const PovTriangleShape&) const { return false; }
  bool operator()(const PovSmoothTriangleShape&) const { return false; }
  bool operator()(const PovConeShape& c) const { return povConeInside(c, p); }
};

// A mesh's triangle (either kind), or null.
const PovMeshTriangleShape* meshTriangle(const Shape& shape) {
  if (const auto* t = std::get_if<PovMeshTriangleShape>(&shape)) return t;
  return std::get_if<PovMeshSmoothTriangleShape>(&shape);
}

std::optional<ShapeHit> intersectShape(const Primitive& p, const Ray& ray, double tMin, double tMax) {
  if (const PovMeshTriangleShape* t = meshTriangle(p.shape))
    return hitMeshTriangle(*t, p.transform.get(), ray, tMin, tMax, p.unit);
  if (!p.transform) return std::visit(Intersector{ray, tMin, tMax, true, p.unit}, p.shape);
  // An affine map keeps the ray parameter: the local hit at t is the world hit at t.
  const Ray local{p.transform->toObject.applyPoint(ray.origin), p.transform->toObject.applyVector(ray.dir)};
  return std::visit(Intersector{local, tMin, tMax, false, p.unit}, p.shape);
}

// Whether the ray's origin and the box lie within kPovFloatReach, where pvrt follows POV-Ray's
// float box test (geometry/pov_bbox.h): beyond, it cuts whole pieces off objects.
bool withinFloatBoxReach(const PovBBox& box, const Ray& ray) {
  if (std::fabs(ray.origin.x) + std::fabs(ray.origin.y) + std::fabs(ray.origin.z) >= kPovFloatReach) return false;
  for (int a = 0; a < 3; ++a)
    if (std::fabs(box.lowerLeft[a]) >= kPovFloatReach || std::fabs(box.lowerLeft[a] + box.lengths[a]) >= kPovFloatReach)
      return false;
  return true;
}

}  // namespace

std::optional<ShapeHit> Primitive::intersect(const Ray& ray, double tMin, double tMax, bool throughTree) const {
  const std::optional<ShapeHit> hit = intersectShape(*this, ray, tMin, tMax);
  // POV-Ray tests a cylinder, cone or disc only when the ray meets its float bounding box,
  // which far from the origin leaves slivers of it out (a cylinder 1e5 away: blind11). In its
  // bounding tree every finite object's box is first a leaf that Check_And_Enqueue may turn
  // away, in float depths of its own: a ray along a box's edge, which the box's own test hits,
  // can fall outside them (blind12 c22). Boxes, spheres and triangles skip the first test (a
  // ray lying in a box's face plane made it 0 * inf, NaN, a miss: blind13). Testing the boxes
  // after a hit gives the same answer, and only the rays that hit pay for it.
  // The shadow cache's object is tested alone (throughTree false): its own Intersect_BBox only.
  if (!hit) return hit;
  const bool boxFirst = povTestsBBoxFirst(*this), treeLeaf = povTreeLeaf && throughTree;
  if (!boxFirst && !treeLeaf) return hit;
  const std::optional<PovBBox> box = povBBox();
  if (box && withinFloatBoxReach(*box, ray) &&
      ((boxFirst && !povBBoxDirHits(*box, ray)) || (treeLeaf && !std::isfinite(povBBoxKey(*box, ray)))))
    return std::nullopt;
  return hit;
}

SurfacePoint Primitive::surfacePoint(const Ray& ray, const ShapeHit& hit) const {
  // Shaded where POV-Ray's hit point is, origin + t * dir in world space (VEvaluateRay);
  // the point moved onto the surface, within its error bound, bounds how far that is.
  const Vec3 at = ray.at(hit.t);
  if (!transform) return hitPointNear(at, std::visit(Reproject{at, hit}, shape));
  const Ray local{transform->toObject.applyPoint(ray.origin), transform->toObject.applyVector(ray.dir)};
  const SurfacePoint sp = std::visit(Reproject{local.at(hit.t), hit}, shape);
  // Carry the point and its error to world space (pbrt-v4's bound for an affine map).
  const Affine& m = transform->toWorld;
  Vec3 error;
  for (int i = 0; i < 3; ++i) {
    double carried = 0, rounding = std::fabs(m.t[i]);
    for (int j = 0; j < 3; ++j) {
      carried += std::fabs(m.m[i][j]) * sp.error[j];
      rounding += std::fabs(m.m[i][j] * sp.p[j]);
    }
    error[i] = (1 + errorGamma(3)) * carried + errorGamma(3) * rounding;
  }
  return hitPointNear(at, {m.applyPoint(sp.p), error});
}

Vec3 Primitive::normal(const Ray& ray, const ShapeHit& hit) const {
  const Vec3 world = ray.at(hit.t);
  // Mesh::Normal: a smooth triangle's normal made unit after MTransNormal, or alone without
  // a transform; a flat one's float normal carried out and made unit, or as it is.
  if (std::holds_alternative<PovMeshSmoothTriangleShape>(shape) && !transform) {
    const Vec3 n = std::visit(Normal{world, hit}, shape);
    return n * (1.0 / std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z));
  }
  // Every shape's normal is unit already (a sphere's (P-C)/r as POV-Ray leaves it).
  if (!transform) return std::visit(Normal{world, hit}, shape);
  // POV-Ray keeps a disc's normal in world space, carried step by step (pov_disc.h).
  if (const auto* disc = std::get_if<PovDiscShape>(&shape)) return disc->normal;
  const Vec3 local = transform->toObject.applyPoint(world);
  return transform->normalToWorld(std::visit(Normal{local, hit}, shape));
}

Bounds Primitive::bounds() const {
  const Bounds local = std::visit(LocalBounds{}, shape);
  if ((!transform && !meshTriangle(shape)) || local.empty()) return local;
  Bounds world = local;
  if (transform) {
    world = Bounds{};
    for (int i = 0; i < 8; ++i) {
      const Vec3 corner{(i & 1) ? local.hi.x : local.lo.x, (i & 2) ? local.hi.y : local.lo.y,
                        (i & 4) ? local.hi.z : local.lo.z};
      world.extend(transform->toWorld.applyPoint(corner));
    }
  }
  if (meshTriangle(shape)) {
    // A mesh triangle's hit is found in mesh space, its point made in world space: either
    // may stray a few ulps past the corners' box, where POV-Ray's hit must still be found.
    const Vec3 m = vmax(vabs(world.lo), vabs(world.hi));
    const double pad = 1e-9 * std::max({m.x, m.y, m.z});
    world.lo = world.lo - Vec3(pad);
    world.hi = world.hi + Vec3(pad);
  }
  return world;
}

bool Primitive::inside(const Vec3& p) const {
  const Vec3 local = transform ? transform->toObject.applyPoint(p) : p;
  if (!std::visit(Inside{local}, shape)) return false;
  // TracePixel::InitRayContainerState counts an object only when the point is also inside
  // its bounding box (Inside_BBox). Every other shape's inside lies within its box (but for
  // rounding at its surface); a disc's is the half-space below it, and its box a slab 2e-3 thick: a camera farther
  // from the disc's plane is inside no disc.
  if (std::holds_alternative<PovDiscShape>(shape))
    if (const std::optional<PovBBox> box = povBBox()) return povBBoxHolds(*box, p);
  return true;
}


}  // namespace pvrt
