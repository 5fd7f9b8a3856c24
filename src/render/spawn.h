// Where rays start and how far they look. POV-Ray's fixed distances (1e-4 minimum depth,
// 1e-3 shadow tolerance, 1e7 maximum distance, the shapes' own tolerances) hold for scenes
// of ordinary size. Here each is multiplied by a length unit: the scene's for the ray
// tolerances, each object's own for its shape tolerances. A unit is exactly 1 for sizes
// between kUnitBand.lo and kUnitBand.hi (POV-Ray's numbers, bit for bit) and follows the
// size outside it. Rays spawned from a surface start at pbrt-v4's error-bounded origin, so
// they cannot meet that surface again at any scale. See docs/robustness.md.
#pragma once

#include <algorithm>
#include <cmath>

#include "geometry/bounds.h"
#include "geometry/primitive.h"
#include "geometry/robust.h"

namespace pvrt {

inline constexpr double kShadowTolerance = 1e-3;  // POV-Ray's SHADOW_TOLERANCE

// Sizes (the longest side of an object's box) for which POV-Ray's constants are used as
// they are.
struct UnitBand {
  double lo, hi;
};
inline constexpr UnitBand kUnitBand{0.1, 1e4};

// The maximum distance is at least this many typical object sizes (and never below
// POV-Ray's 1e7, which it is for typical sizes up to 100): a camera a few objects above a
// plane then sees it to within 1e-4 radians of its horizon at any scale.
inline constexpr double kHorizonSizes = 1e5;

// The length unit of an object, or of a scene whose typical object, this size. Below the
// band the unit is the size itself: the scene is traced as it would be were it scaled to
// objects of size 1, well inside the band (so a small copy of a scene is traced as the
// scene is). Above it, size / hi: continuous at hi, and as fine as POV-Ray's relative to
// a scene of objects of size 1. 0, infinite or NaN (no bounded object): 1.
inline double unitFor(double size) {
  if (!(size > 0) || !std::isfinite(size)) return 1;
  if (size < kUnitBand.lo) return size;
  if (size > kUnitBand.hi) return size / kUnitBand.hi;
  return 1;
}

// The longest side of a box (0 for an empty one: planes).
inline double sizeOf(const Bounds& b) {
  if (b.empty()) return 0;
  const Vec3 e = b.extent();
  return std::max({e.x, e.y, e.z});
}

struct RayTolerances {
  double typicalSize = 0;                // the lower median of the objects' sizes (0: only planes)
  double unit = 1;                       // the scene's length unit: unitFor(typicalSize)
  double minDepth = kMinIsectDepth;      // rays spawned from a surface ignore hits closer than this
  double shadow = kShadowTolerance;      // shadow segments ignore hits this close to either end
  double maxDistance = kMaxDistance;     // hits farther than this are dropped
  double primaryMinDepth = 0;            // camera rays: only the rounding of the camera position
};

// The scene's tolerances from its typical object size (render/scene.cpp).
RayTolerances rayTolerances(double typicalSize, const Vec3& camera);

// The thickness of the slab around the surface in which sp's point may lie, along n.
inline double errorSlab(const SurfacePoint& sp, const Vec3& n) { return dot(vabs(n), sp.error); }

// Where a ray leaving the hit point `sp` (normal n, either orientation) along `dir`
// starts, when it ignores every hit nearer than `near`. POV-Ray starts it at the hit point
// itself (MIN_ISECT_DEPTH then keeps it off the surface it left), and so does pvrt wherever
// that is safe: where the ray leaves the error slab within half of `near`, the surface
// cannot be met again beyond it. Elsewhere (a grazing ray, or coordinates so large that
// the slab is thicker than `near`: where POV-Ray's own image has acne) it starts at the
// error-bounded origin. docs/robustness.md, docs/fidelity.md.
inline Vec3 spawnOrigin(const SurfacePoint& sp, const Vec3& n, const Vec3& dir, double near) {
  if (errorSlab(sp, n) < 0.5 * near * std::fabs(dot(dir, n))) return sp.p;
  return offsetRayOrigin(sp, n, dir);
}
inline Ray spawnRay(const SurfacePoint& sp, const Vec3& n, const Vec3& dir, double near) {
  return {spawnOrigin(sp, n, dir, near), dir};
}

// Every shadow segment of a hit starts at one origin, whatever the light (its direction
// l has n.l >= kPovEpsilon). The hit point itself, as in POV-Ray, when the slab is thin
// enough that only a light within kShadowGrazing of the horizon (n.l below it, and so a
// diffuse share below it) could find the surface again past `near` (the shorter of the
// shadow tolerance and the cached blocker's minimum depth); else the error-bounded origin.
inline constexpr double kShadowGrazing = 1e-6;
inline double shadowSlabLimit(const RayTolerances& tol) {
  return 0.5 * kShadowGrazing * std::min(tol.minDepth, tol.shadow);
}
inline Vec3 shadowSegmentOrigin(const SurfacePoint& sp, const Vec3& n, double slabLimit) {
  if (errorSlab(sp, n) < slabLimit) return sp.p;
  return offsetRayOrigin(sp, n, n);
}

}  // namespace pvrt
