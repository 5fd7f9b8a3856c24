// Floating-point error bounds for hit points and the error-bounded origin of rays spawned
// from a surface (pbrt-v4's OffsetRayOrigin; Pharr, Jakob and Humphreys, "Physically Based
// Rendering", 4th ed., section 6.8). A spawned ray starts on the far side of the hit point's
// error box, on the side it leaves toward, so it cannot meet the surface it left again,
// whatever the scale or position of the scene. docs/robustness.md explains the choices.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "core/vec3.h"

namespace pvrt {

// gamma(n) = n u / (1 - n u): the relative error bound of n successive roundings (u = 2^-53).
constexpr double errorGamma(int n) {
  constexpr double u = std::numeric_limits<double>::epsilon() * 0.5;
  return n * u / (1 - n * u);
}

inline Vec3 vabs(const Vec3& v) { return {std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}; }

// The next double above / below v: std::nextafter without the library call (this runs
// for every shadow and secondary ray). Infinities and NaN are returned unchanged.
inline double nextUp(double v) {
  if (!(v < INFINITY)) return v;
  if (v == 0) return std::numeric_limits<double>::denorm_min();
  const uint64_t bits = std::bit_cast<uint64_t>(v);
  return std::bit_cast<double>(v > 0 ? bits + 1 : bits - 1);
}
inline double nextDown(double v) { return -nextUp(-v); }

// A hit point re-projected onto its surface, with a per-component bound on its distance
// from the exact surface point (world space).
struct SurfacePoint {
  Vec3 p;
  Vec3 error;
};

// The hit point p as POV-Ray computes it (origin + t * direction, VEvaluateRay), with a
// bound on its distance from the surface: how far it is from `onSurface`, a point on the
// surface within that point's own error bound.
inline SurfacePoint hitPointNear(const Vec3& p, const SurfacePoint& onSurface) {
  return {p, (vabs(p - onSurface.p) + onSurface.error) * (1 + errorGamma(2))};
}

// The origin for a ray leaving `sp` along `dir`: p moved along the normal `n` (either
// orientation) by the error box's extent in that direction, to the side `dir` points to,
// each component then rounded one step further away from p.
inline Vec3 offsetRayOrigin(const SurfacePoint& sp, const Vec3& n, const Vec3& dir) {
  const double d = dot(vabs(n), sp.error);
  Vec3 offset = n * d;
  if (dot(dir, n) < 0) offset = -offset;
  Vec3 o = sp.p + offset;
  for (int i = 0; i < 3; ++i) {
    if (offset[i] > 0) o[i] = nextUp(o[i]);
    else if (offset[i] < 0) o[i] = nextDown(o[i]);
  }
  return o;
}

}  // namespace pvrt
