// Cylinders and cones as POV-Ray 3.7 intersects them (source/backend/shape/cones.cpp):
// in a canonical space where the axis is z, reached through POV-Ray's own transform
// (core/pov_transform.h: the shape's placement, then every transform written). Their
// caps standing on a plane tie with it only in exact arithmetic, and which one wins is
// decided by this rounding, so pvrt does it the same way (docs/fidelity.md).
#pragma once

#include <optional>

#include "core/pov_transform.h"
#include "core/ray.h"
#include "geometry/bounds.h"
#include "geometry/robust.h"

namespace pvrt {

// In canonical space a cylinder is x^2 + y^2 <= 1, 0 <= z <= 1; a cone is x^2 + y^2 <=
// z^2, dist <= z <= 1 (its wide end at z = 1).
struct PovConeShape {
  double dist = 0;
  bool cylinder = true;
  bool open = false;
};

// The canonical shape of a cylinder or cone and POV-Ray's transform onto it from world
// space (Compute_Cylinder_Data, Compute_Cone_Data); more transforms follow with then().
struct PovConePlacement {
  PovConeShape shape;
  PovTransform transform;
};
PovConePlacement placeCylinder(const Vec3& base, const Vec3& cap, double radius, bool open);
PovConePlacement placeCone(const Vec3& base, double baseRadius, const Vec3& cap, double capRadius, bool open);

// part 0: the side, 1: the base (z = dist), 2: the cap (z = 1).
struct PovConeHit {
  double t;
  int part;
};
// The nearest hit with lo < t < hi of the world ray whose canonical-space image is
// `local` (not unit: t is the world ray's parameter); among equal ones the first found.
std::optional<PovConeHit> hitPovCone(const PovConeShape& c, const Ray& local, double lo, double hi, double unit);
// The canonical-space normal at canonical point p, before POV-Ray carries it to world
// space and makes it unit.
Vec3 povConeNormal(const PovConeShape& c, const Vec3& p, int part);
// POV-Ray's Inside(), a hair generous for open shapes and strict for closed ones.
bool povConeInside(const PovConeShape& c, const Vec3& p);
Bounds povConeBounds(const PovConeShape& c);
// Canonical point p moved onto the surface part it hit, with a bound on its error.
SurfacePoint povConeSurfacePoint(const PovConeShape& c, const Vec3& p, int part);

}  // namespace pvrt
