// POV-Ray 3.7's Cone (source/backend/shape/cones.cpp), the same operations in the same
// order. Its parser reads a cylinder's or cone's first point into the shape's "apex" and
// the second into its "base", so the written base ends up at canonical z = 1 (a cone's
// wider end goes there whichever it is).
#include "geometry/pov_cone.h"

#include <cmath>
#include <utility>

#include "geometry/primitive.h"

namespace pvrt {

namespace {

// Compute_Cylinder_Data: the axis from POV-Ray's base (the second point) to its apex.
PovConePlacement cylinderFrom(const Vec3& apex, const Vec3& base, double radius, bool open) {
  Vec3 axis = apex - base;
  const double len = length(axis);
  axis = axis * (1.0 / len);
  return {PovConeShape{0.0, true, open}, PovTransform::coordinate(base, axis, radius, len)};
}

}  // namespace

PovConePlacement placeCylinder(const Vec3& base, const Vec3& cap, double radius, bool open) {
  return cylinderFrom(base, cap, radius, open);
}

PovConePlacement placeCone(const Vec3& base, double baseRadius, const Vec3& cap, double capRadius, bool open) {
  // Compute_Cone_Data, in POV-Ray's names: apex = the first point, base = the second.
  Vec3 apex = base, bottom = cap;
  double apexRadius = baseRadius, bottomRadius = capRadius;
  Vec3 axis = apex - bottom;
  const double len = length(axis);
  axis = axis * (1.0 / len);
  if (std::fabs(apexRadius - bottomRadius) < kPovEpsilon) return cylinderFrom(apex, bottom, apexRadius, open);
  if (apexRadius < bottomRadius) {  // the wider end at the top
    std::swap(apex, bottom);
    std::swap(apexRadius, bottomRadius);
    axis = axis * -1.0;
  }
  // The cone's tip lies `toTip` below the narrow end.
  const double toTip = bottomRadius * len / (apexRadius - bottomRadius);
  const Vec3 tip = bottom - axis * toTip;
  const double fullLength = toTip + len;
  if ((apexRadius - bottomRadius) * len / fullLength < kPovEpsilon) return cylinderFrom(apex, bottom, apexRadius, open);
  return {PovConeShape{toTip / fullLength, false, open}, PovTransform::coordinate(tip, axis, apexRadius, fullLength)};
}

std::optional<PovConeHit> hitPovCone(const PovConeShape& c, const Ray& local, double lo, double hi, double unit) {
  const Vec3& p = local.origin;
  const double len = length(local.dir);
  const Vec3 d = local.dir * (1.0 / len);
  const double tolerance = kConeTolerance * unit;

  // Candidates in the order Cone::All_Intersections pushes them (the sides' roots, the cap at
  // z = 1, the base at dist). FindIntersection pops them from the top, the last pushed first,
  // keeping one only when strictly nearer: so of two at one depth the later wins (a ray through
  // the rim where the side and a cap meet at one depth shades the cap; blind14 a05).
  std::optional<PovConeHit> best;
  auto consider = [&](double t, int part) {
    const double depth = t / len;
    if (t > tolerance && depth > lo && depth < hi && (!best || depth <= best->t)) best = PovConeHit{depth, part};
  };
  auto side = [&](double t, double zMin) {
    const double z = p.z + t * d.z;
    if (z >= zMin && z <= 1.0) consider(t, 0);
  };

  if (c.cylinder) {
    const double a = d.x * d.x + d.y * d.y;
    if (a > kPovEpsilon) {
      const double b = p.x * d.x + p.y * d.y;
      const double cc = p.x * p.x + p.y * p.y - 1.0;
      double disc = b * b - a * cc;
      if (disc >= 0.0) {
        disc = std::sqrt(disc);
        side((-b + disc) / a, 0.0);
        side((-b - disc) / a, 0.0);
      }
    }
  } else {
    const double a = d.x * d.x + d.y * d.y - d.z * d.z;
    const double b = d.x * p.x + d.y * p.y - d.z * p.z;
    const double cc = p.x * p.x + p.y * p.y - p.z * p.z;
    if (std::fabs(a) < kPovEpsilon) {
      if (std::fabs(b) > kPovEpsilon) side(-0.5 * cc / b, c.dist);  // along the slant: one root
    } else {
      double disc = b * b - a * cc;
      if (disc >= 0.0) {
        disc = std::sqrt(disc);
        side((-b - disc) / a, c.dist);
        side((-b + disc) / a, c.dist);
      }
    }
  }
  if (!c.open && std::fabs(d.z) > kPovEpsilon) {
    auto cap = [&](double z, double radius2, int part) {
      const double t = (z - p.z) / d.z;
      const double x = p.x + t * d.x, y = p.y + t * d.y;
      if (x * x + y * y <= radius2) consider(t, part);
    };
    cap(1.0, 1.0, 2);
    cap(c.dist, c.cylinder ? 1.0 : c.dist * c.dist, 1);
  }
  return best;
}

Vec3 povConeNormal(const PovConeShape& c, const Vec3& p, int part) {
  if (part == 1) return {0.0, 0.0, -1.0};
  if (part == 2) return {0.0, 0.0, 1.0};
  return {p.x, p.y, c.cylinder ? 0.0 : -p.z};
}

bool povConeInside(const PovConeShape& c, const Vec3& p) {
  const double offset = c.open ? kPovEpsilon : -kPovEpsilon;
  const double w2 = p.x * p.x + p.y * p.y;
  const double radius2 = c.cylinder ? 1.0 : p.z * p.z;
  return !(w2 > radius2 + offset || p.z < c.dist - offset || p.z > 1.0 + offset);
}

Bounds povConeBounds(const PovConeShape& c) { return {{-1, -1, c.dist}, {1, 1, 1}}; }

SurfacePoint povConeSurfacePoint(const PovConeShape& c, const Vec3& p, int part) {
  Vec3 q = p;
  if (part == 1) q.z = c.dist;
  else if (part == 2) q.z = 1.0;
  else {
    const double r = std::sqrt(p.x * p.x + p.y * p.y);
    const double want = c.cylinder ? 1.0 : p.z;
    if (r > 0) q.x = p.x * (want / r), q.y = p.y * (want / r);
  }
  return {q, (vabs(q) + Vec3(1.0)) * errorGamma(8)};
}

}  // namespace pvrt
