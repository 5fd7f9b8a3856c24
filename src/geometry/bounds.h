// Axis-aligned bounding box.
#pragma once

#include <limits>

#include "core/ray.h"
#include "core/vec3.h"

namespace pvrt {

struct Bounds {
  Vec3 lo{std::numeric_limits<double>::infinity()};
  Vec3 hi{-std::numeric_limits<double>::infinity()};

  bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
  void extend(const Vec3& p) { lo = vmin(lo, p); hi = vmax(hi, p); }
  void extend(const Bounds& b) { lo = vmin(lo, b.lo); hi = vmax(hi, b.hi); }
  Vec3 centroid() const { return (lo + hi) * 0.5; }
  Vec3 extent() const { return hi - lo; }
  double surfaceArea() const {
    if (empty()) return 0;
    const Vec3 e = extent();
    return 2 * (e.x * e.y + e.y * e.z + e.z * e.x);
  }
  int longestAxis() const {
    const Vec3 e = extent();
    return e.x >= e.y && e.x >= e.z ? 0 : (e.y >= e.z ? 1 : 2);
  }
};

}  // namespace pvrt
