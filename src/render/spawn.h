// Where rays start and how far they look. POV-Ray's fixed distances (1e-4 minimum depth,
// 1e-3 shadow tolerance, 1e7 maximum distance, the shapes' own tolerances) hold for scenes
// of ordinary size; here they are multiplied by the scene's length unit, which is exactly 1
// for every scene whose objects span between kUnitBand.lo and kUnitBand.hi and follows the
// span outside that band. Rays spawned from a surface start at pbrt-v4's error-bounded
// origin, so they cannot meet that surface again at any scale. See docs/robustness.md.
#pragma once

#include <algorithm>
#include <cmath>

#include "geometry/bounds.h"
#include "geometry/primitive.h"
#include "geometry/robust.h"

namespace pvrt {

inline constexpr double kShadowTolerance = 1e-3;  // POV-Ray's SHADOW_TOLERANCE

// Object spans (the longest side of the box around every bounded object) for which
// POV-Ray's constants are used as they are.
struct UnitBand {
  double lo, hi;
};
inline constexpr UnitBand kUnitBand{0.1, 1e4};

struct RayTolerances {
  double unit = 1;                       // the scene's length unit
  double minDepth = kMinIsectDepth;      // rays spawned from a surface ignore hits closer than this
  double shadow = kShadowTolerance;      // shadow segments ignore hits this close to either end
  double maxDistance = kMaxDistance;     // hits farther than this are dropped
  double primaryMinDepth = 0;            // camera rays: only the rounding of the camera position
};

// The length unit for objects within `objects` (empty: only planes, unit 1).
inline double sceneUnit(const Bounds& objects) {
  if (objects.empty()) return 1;
  const Vec3 e = objects.extent();
  const double span = std::max({e.x, e.y, e.z});
  if (!(span > 0) || !std::isfinite(span)) return 1;
  if (span < kUnitBand.lo) return span / kUnitBand.lo;
  if (span > kUnitBand.hi) return span / kUnitBand.hi;
  return 1;
}

inline RayTolerances rayTolerances(const Bounds& objects, const Vec3& camera) {
  RayTolerances t;
  t.unit = sceneUnit(objects);
  t.minDepth = kMinIsectDepth * t.unit;
  t.shadow = kShadowTolerance * t.unit;
  t.maxDistance = kMaxDistance * t.unit;
  const Vec3 c = vabs(camera);
  t.primaryMinDepth = errorGamma(8) * std::max({c.x, c.y, c.z});
  return t;
}

// A ray leaving the surface point `sp` (normal n, either orientation) along `dir`.
inline Ray spawnRay(const SurfacePoint& sp, const Vec3& n, const Vec3& dir) {
  return {offsetRayOrigin(sp, n, dir), dir};
}

}  // namespace pvrt
