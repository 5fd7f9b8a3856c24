// Discs as POV-Ray 3.7 intersects them (source/backend/shape/discs.cpp): in a canonical
// space where the disc lies in z = 0 around the origin, reached through POV-Ray's own
// transform (Compute_Disc's Compute_Coordinate_Transform, then every transform written,
// core/pov_transform.h). A disc lying on a plane ties with it only in exact arithmetic;
// which one a ray sees is decided by this rounding, so pvrt does it the same way
// (docs/fidelity.md).
#pragma once

#include <optional>

#include "core/pov_transform.h"
#include "core/ray.h"
#include "geometry/bounds.h"
#include "geometry/robust.h"

namespace pvrt {

// The canonical disc: z = 0, inner2 <= x^2 + y^2 <= outer2. Its normal is kept in world
// space as POV-Ray keeps it (the written normal made unit, then carried by each transform
// and made unit again), not derived from the composed transform.
struct PovDiscShape {
  double inner2 = 0, outer2 = 1;
  Vec3 normal{0, 0, 1};
};

struct PovDiscPlacement {
  PovDiscShape shape;
  PovTransform transform;
  // One more transform written (Disc::Transform): the normal and the map follow it.
  void then(const PovTransform& step);
};
// Parse_Disc and Compute_Disc: the disc around `center` facing `normal` (any length).
PovDiscPlacement placeDisc(const Vec3& center, const Vec3& normal, double radius, double holeRadius);

// Disc::Intersect on the canonical image `local` of a world ray (not unit: the depth is the
// world ray's parameter), with lo < depth < hi.
std::optional<double> hitPovDisc(const PovDiscShape& d, const Ray& local, double lo, double hi, double unit);
// Disc::Inside: below its plane in canonical space.
inline bool povDiscInside(const Vec3& p) { return p.z < 0.0; }
Bounds povDiscBounds(const PovDiscShape& d);
// A canonical point moved onto z = 0, with a bound on its error.
SurfacePoint povDiscSurfacePoint(const Vec3& p);

}  // namespace pvrt
