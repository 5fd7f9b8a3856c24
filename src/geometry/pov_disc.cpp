#include "geometry/pov_disc.h"

#include <cmath>

#include "geometry/primitive.h"

namespace pvrt {

namespace {
// VNormalize: times 1 / length.
Vec3 povNormalize(const Vec3& v) { return v * (1.0 / std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z)); }
}  // namespace

PovDiscPlacement placeDisc(const Vec3& center, const Vec3& normal, double radius, double holeRadius) {
  PovDiscPlacement placed;
  placed.shape.outer2 = radius * radius;
  placed.shape.inner2 = holeRadius * holeRadius;
  Vec3 n = povNormalize(normal);
  placed.transform = PovTransform::coordinate(center, n, 1.0, 1.0);
  // Compute_Coordinate_Transform sets the z of the normal it is given to +-1 when it is
  // that close to an axis, and the disc keeps that normal.
  if (std::fabs(n.z) > 1.0 - kPovEpsilon) n.z = n.z < 0.0 ? -1.0 : 1.0;
  placed.shape.normal = n;
  return placed;
}

void PovDiscPlacement::then(const PovTransform& step) {
  // MTransNormal, then VNormalize, as Transform::normalToWorld does.
  shape.normal = step.toTransform().normalToWorld(shape.normal);
  transform.then(step);
}

std::optional<double> hitPovDisc(const PovDiscShape& d, const Ray& local, double lo, double hi, double unit) {
  const Vec3& p = local.origin;
  Vec3 dir = local.dir;
  const double len = std::sqrt(dir.x * dir.x + dir.y * dir.y + dir.z * dir.z);
  dir = dir * (1.0 / len);  // VInverseScaleEq
  if (!(std::fabs(dir.z) > kPovEpsilon)) return std::nullopt;
  const double t = -p.z / dir.z;
  if (!(t >= 0.0)) return std::nullopt;
  const double u = p.x + t * dir.x, v = p.y + t * dir.y;
  const double r2 = u * u + v * v;
  if (!(r2 >= d.inner2 && r2 <= d.outer2)) return std::nullopt;
  const double depth = t / len;
  if (!(depth > kDepthTolerance * unit && depth > lo && depth < hi)) return std::nullopt;
  return depth;
}

Bounds povDiscBounds(const PovDiscShape& d) {
  const double r = std::sqrt(d.outer2);
  return {{-r, -r, 0.0}, {r, r, 0.0}};
}

SurfacePoint povDiscSurfacePoint(const Vec3& p) { return flatSurfacePoint({0, 0, 1}, {0, 0, 0}, p); }

}  // namespace pvrt
