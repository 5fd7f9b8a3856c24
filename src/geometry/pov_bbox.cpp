#include "geometry/pov_bbox.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <variant>

#include "geometry/primitive.h"

namespace pvrt {

namespace {

constexpr double kBoundHuge = 2.0e10;        // POV-Ray's BOUND_HUGE
constexpr double kSmallTolerance = 0.001;    // SMALL_TOLERANCE
constexpr double kEpsilon = 1.0e-10;         // EPSILON
constexpr double kNotEnqueued = std::numeric_limits<double>::infinity();

// Builds the box of the shapes POV-Ray keeps in the same form as pvrt does.
struct BoxOfShape {
  const Primitive& p;
  std::optional<PovBBox> through(const PovBBox& local) const {
    return p.transform ? povRecomputed(local, p.transform->toWorld) : local;
  }
  std::optional<PovBBox> operator()(const SphereShape& s) const {
    // Sphere::Compute_BBox; a transformed sphere is pvrt's own unit sphere, not POV-Ray's.
    if (p.transform) return std::nullopt;
    return povSphereBBox(s.center, s.radius);
  }
  std::optional<PovBBox> operator()(const BoxShape& b) const {
    // Box::Compute_BBox: Assign_BBox_Vect of bounds[0], VSub of the corners into floats.
    PovBBox box;
    const double lo[3] = {b.lo.x, b.lo.y, b.lo.z}, hi[3] = {b.hi.x, b.hi.y, b.hi.z};
    for (int a = 0; a < 3; ++a) {
      box.lowerLeft[a] = float(lo[a]);
      box.lengths[a] = float(hi[a] - lo[a]);
    }
    return through(box);
  }
  std::optional<PovBBox> operator()(const PovDiscShape& d) const {
    if (!p.transform) return std::nullopt;
    const double rad = std::sqrt(d.outer2);  // Disc::Compute_BBox
    return through(makePovBBox(-rad, -rad, -kSmallTolerance, 2.0 * rad, 2.0 * rad, 2.0 * kSmallTolerance));
  }
  std::optional<PovBBox> operator()(const PovConeShape& c) const {
    if (!p.transform) return std::nullopt;
    // Cone::Compute_BBox (a cylinder's dist is 0): the canonical shape from z = dist to 1.
    return through(makePovBBox(-1.0, -1.0, c.dist, 2.0, 2.0, 1.0 - c.dist));
  }
  template <class Corners>
  std::optional<PovBBox> triangle(const Corners& t) const {
    // Triangle::Compute_BBox (smooth triangles inherit it): the corners' range padded by EPSILON.
    const Vec3 mins{std::min({t.p1.x, t.p2.x, t.p3.x}) - kEpsilon, std::min({t.p1.y, t.p2.y, t.p3.y}) - kEpsilon,
                    std::min({t.p1.z, t.p2.z, t.p3.z}) - kEpsilon};
    const Vec3 maxs{std::max({t.p1.x, t.p2.x, t.p3.x}) + kEpsilon, std::max({t.p1.y, t.p2.y, t.p3.y}) + kEpsilon,
                    std::max({t.p1.z, t.p2.z, t.p3.z}) + kEpsilon};
    return povBBoxFromMinMax(mins, maxs);
  }
  std::optional<PovBBox> operator()(const PovTriangleShape& t) const { return triangle(t); }
  std::optional<PovBBox> operator()(const PovSmoothTriangleShape& t) const { return triangle(t); }
  // Planes are unbounded; a mesh's triangles are parts of one object whose box is the mesh's.
  std::optional<PovBBox> operator()(const PlaneShape&) const { return std::nullopt; }
  std::optional<PovBBox> operator()(const PovMeshTriangleShape&) const { return std::nullopt; }
  std::optional<PovBBox> operator()(const PovMeshSmoothTriangleShape&) const { return std::nullopt; }
};

}  // namespace

PovBBox makePovBBox(double llx, double lly, double llz, double lex, double ley, double lez) {
  PovBBox b;
  b.lowerLeft[0] = float(llx), b.lowerLeft[1] = float(lly), b.lowerLeft[2] = float(llz);
  b.lengths[0] = float(lex), b.lengths[1] = float(ley), b.lengths[2] = float(lez);
  return b;
}

PovBBox povSphereBBox(const Vec3& c, double r) {
  return makePovBBox(c.x - r, c.y - r, c.z - r, 2.0 * r, 2.0 * r, 2.0 * r);
}

PovBBox povBBoxFromMinMax(const Vec3& mins, const Vec3& maxs) {
  return makePovBBox(mins.x, mins.y, mins.z, maxs.x - mins.x, maxs.y - mins.y, maxs.z - mins.z);
}

PovBBox povRecomputed(const PovBBox& box, const Affine& toWorld) {
  const double ll[3] = {box.lowerLeft[0], box.lowerLeft[1], box.lowerLeft[2]};
  const double len[3] = {box.lengths[0], box.lengths[1], box.lengths[2]};
  double mins[3] = {kBoundHuge, kBoundHuge, kBoundHuge}, maxs[3] = {-kBoundHuge, -kBoundHuge, -kBoundHuge};
  for (int i = 1; i <= 8; ++i) {
    Vec3 corner{ll[0], ll[1], ll[2]};
    corner.x += (i & 1) ? len[0] : 0.0;
    corner.y += (i & 2) ? len[1] : 0.0;
    corner.z += (i & 4) ? len[2] : 0.0;
    corner = toWorld.applyPoint(corner);  // MTransPoint
    const double c[3] = {corner.x, corner.y, corner.z};
    for (int a = 0; a < 3; ++a) {
      if (c[a] < mins[a]) mins[a] = c[a];
      if (c[a] > maxs[a]) maxs[a] = c[a];
    }
  }
  for (int a = 0; a < 3; ++a) {
    mins[a] = std::max(mins[a], -kBoundHuge / 2);
    maxs[a] = std::min(maxs[a], kBoundHuge / 2);
  }
  return povBBoxFromMinMax({mins[0], mins[1], mins[2]}, {maxs[0], maxs[1], maxs[2]});
}

std::optional<PovBBox> povBBoxOf(const Primitive& p) { return std::visit(BoxOfShape{p}, p.shape); }

bool povTestsBBoxFirst(const Primitive& p) {
  return std::holds_alternative<PovConeShape>(p.shape) || std::holds_alternative<PovDiscShape>(p.shape) ||
         std::holds_alternative<PovMeshTriangleShape>(p.shape) ||
         std::holds_alternative<PovMeshSmoothTriangleShape>(p.shape);
}

bool povBBoxHolds(const PovBBox& box, const Vec3& p) {
  const double c[3] = {p.x, p.y, p.z};
  for (int a = 0; a < 3; ++a)
    if (c[a] < double(box.lowerLeft[a]) || c[a] > double(box.lowerLeft[a]) + double(box.lengths[a])) return false;
  return true;
}

bool povBBoxDirHits(const PovBBox& box, const Ray& ray) {
  const double o[3] = {ray.origin.x, ray.origin.y, ray.origin.z};
  const double d[3] = {ray.dir.x, ray.dir.y, ray.dir.z};
  float tmin = 0, tmax = 0;
  for (int a = 0; a < 3; ++a) {
    // Make_min_max_from_BBox (a float sum), then the slab of the side the ray meets first.
    const float origin = float(o[a]), invdir = float(1.0 / d[a]);
    const float lo = box.lowerLeft[a], hi = box.lowerLeft[a] + box.lengths[a];
    const bool back = invdir < 0.0f;  // the variant bit of Intersect_BBox
    const float near = ((back ? hi : lo) - origin) * invdir, far = ((back ? lo : hi) - origin) * invdir;
    if (a > 0) {
      if (tmin > far || near > tmax) return false;
      tmin = std::max(tmin, near);  // Intersect_BBox_Dir's "if (tymin > tmin) tmin = tymin"
      tmax = std::min(tmax, far);
    } else {
      tmin = near, tmax = far;
    }
  }
  // Find_Intersection's maxd, HUGE_VAL, and MIN_ISECT_DEPTH (geometry/primitive.h), as floats.
  const float maxd = std::numeric_limits<float>::infinity(), mind = float(kMinIsectDepth);
  return tmin < maxd && tmax > mind;
}

PovRayInfo::PovRayInfo(const Ray& ray) {
  const double o[3] = {ray.origin.x, ray.origin.y, ray.origin.z};
  const double d[3] = {ray.dir.x, ray.dir.y, ray.dir.z};
  for (int a = 0; a < 3; ++a) {
    num[a] = float(o[a]);
    nonzero[a] = d[a] != 0.0;
    positive[a] = d[a] > 0.0;
    den[a] = nonzero[a] ? float(1.0 / d[a]) : 0.0f;
  }
}

double povBBoxKey(const PovBBox& box, const PovRayInfo& ray) {
  double dmin = -kBoundHuge, dmax = kBoundHuge;
  for (int a = 0; a < 3; ++a) {
    const float num = ray.num[a];
    const float ll = box.lowerLeft[a], len = box.lengths[a];
    if (!ray.nonzero[a]) {
      if (num < ll || num > len + ll) return kNotEnqueued;
      continue;
    }
    const float den = ray.den[a];
    const float near = (ll - num) * den;  // the float products of Check_And_Enqueue
    const float span = len * den;
    double tmin, tmax;
    if (ray.positive[a]) {
      tmin = near;
      tmax = tmin + span;
    } else {
      tmax = near;
      tmin = tmax + span;
    }
    if (a == 0) {
      if (tmax < kEpsilon) return kNotEnqueued;
      dmin = tmin, dmax = tmax;
      if (dmin > dmax) return kNotEnqueued;
      continue;
    }
    // The y and z slabs, in Check_And_Enqueue's order of tests.
    if (tmax < dmax) {
      if (tmax < kEpsilon) return kNotEnqueued;
      if (tmin > dmin) {
        if (tmin > tmax) return kNotEnqueued;
        dmin = tmin;
      } else if (dmin > tmax) {
        return kNotEnqueued;
      }
      dmax = tmax;
    } else if (tmin > dmin) {
      if (tmin > dmax) return kNotEnqueued;
      dmin = tmin;
    }
  }
  return dmin;
}

}  // namespace pvrt
