// The slab tests of one ray against the child boxes of a wide BVH node: the exact one in
// double precision, four children at a time (used by the packet walks, whose answers
// must be those of single rays), and the fast one in float precision, a whole node at a
// time, which single rays walk with. The float test is conservative: it enters every box
// the double one enters (and rarely a few more, whose primitives then simply miss), so
// the hits found, and the image, are the same.
#pragma once

#include <cmath>

#include "accel/bvh.h"
#include "core/lanes.h"
#include "core/ray.h"

namespace pvrt {

// One ray, ready for the four-box slab test: its origin and reciprocal direction in
// every lane, and which side of each slab it meets first (by the sign bit of the
// direction, so that -0 counts as negative, as its reciprocal -inf does).
struct RaySlabs {
  lanes::Double4 origin[3], inv[3];
  bool nearIsHi[3];
  RaySlabs() = default;  // uninitialised, for arrays filled later
  explicit RaySlabs(const Ray& ray) {
    for (int a = 0; a < 3; ++a) {
      origin[a] = lanes::splat(ray.origin[a]);
      inv[a] = lanes::splat(1.0 / ray.dir[a]);
      nearIsHi[a] = std::signbit(ray.dir[a]);
    }
  }
};

// The slab test of four children of a node at once: bit c of the result is set when the
// ray enters child c's box after tMin and before tMax, and enter[c] is where. The far
// distances get a few ulps of slack so that boundary hits are kept.
inline unsigned hitsQuad(const BvhNode::Quad& q, const RaySlabs& r, double tMin, double tMax, double* enter) {
  using namespace lanes;
  Double4 in = splat(tMin), out = splat(tMax);
  const Double4 slack = splat(1 + 4e-16);
  for (int a = 0; a < 3; ++a) {
    const Double4 t0 = (widen(r.nearIsHi[a] ? q.hi[a] : q.lo[a]) - r.origin[a]) * r.inv[a];
    const Double4 t1 = (widen(r.nearIsHi[a] ? q.lo[a] : q.hi[a]) - r.origin[a]) * r.inv[a] * slack;
    // A NaN (0 * inf on a slab boundary) must not reject: it leaves the bound as it was.
    in = maxOr(t0, in);
    out = minOr(t1, out);
  }
  store(enter, in);
  return lessEqual(in, out);
}

// hitsQuad for every used quad of `n`: bit c for child c, enter[c] for each of its slots.
inline unsigned hitsChildren(const BvhNode& n, const RaySlabs& r, double tMin, double tMax, double* enter) {
  unsigned mask = hitsQuad(n.quad[0], r, tMin, tMax, enter);
  for (int q = 1; q < n.quads(); ++q) mask |= hitsQuad(n.quad[q], r, tMin, tMax, enter + 4 * q) << (4 * q);
  return mask;
}

// One ray for the float test. Its origin o is rounded to the float o', and the test
// measures slab distances from o': each is then off by (o - o') / d along its axis, which
// `pad` (rounded up) adds on both sides. What remains are the relative errors of a few
// float operations (below 2^-21 together), which the comparison's factor kSlack covers:
// the test enters a box whenever the exact distances (and so the double test) do.
struct FloatRaySlabs {
  static constexpr float kSlack = 1 + 0x1p-18f;
  lanes::Float8 origin[3], inv[3], pad[3];
  bool nearIsHi[3];
  explicit FloatRaySlabs(const Ray& ray) {
    for (int a = 0; a < 3; ++a) {
      const double inverse = 1.0 / ray.dir[a];
      const float o = float(ray.origin[a]);
      const double shift = ray.origin[a] - double(o);  // exact
      // Rounded to float, the pad loses at most 2^-24 of itself (or 2^-150 below the
      // normal floats): what the factor and the smallest float added here make up for.
      // Computed without a branch that depends on the ray: those mispredict.
      double p = std::fabs(shift) * std::fabs(inverse) * (1 + 0x1p-19) + 0x1p-149;
      if (std::fabs(inverse) > 0x1.fffffep127) {
        // A component so small that its reciprocal is no float: the distances along this
        // axis cannot be bounded in float, so the axis constrains nothing (a rare, slower
        // but right walk). A zero component needs no pad: o' lies on the same side of every
        // bound as o, or on it (a NaN, which constrains nothing either).
        p = std::isinf(inverse) ? 0.0 : INFINITY;
      }
      origin[a] = lanes::splat8(o);
      inv[a] = lanes::splat8(float(inverse));
      pad[a] = lanes::splat8(float(p));
      nearIsHi[a] = std::signbit(ray.dir[a]);
    }
  }
  // The bound of the float test's comparison for an interval that ends at tMax: a box is
  // entered when its entry distance is at most this.
  static float limit(float out) { return out * kSlack; }
};

// The float slab test of all the children of `n` at once: bit c of the result is set when
// the ray may enter child c's box after tMin and before tMax (always when the double test
// says it does), and enter[c] is a lower bound of where, give or take 2^-18 relative.
inline unsigned hitsNode(const BvhNode& n, const FloatRaySlabs& r, float tMin, float tMax, float* enter) {
  using namespace lanes;
  static_assert(kBvhQuads == 2, "one eight-lane test per node");
  Float8 in = splat8(tMin), out = splat8(tMax);
  for (int a = 0; a < 3; ++a) {
    const float* nearLo = r.nearIsHi[a] ? n.quad[0].hi[a] : n.quad[0].lo[a];
    const float* nearHi = r.nearIsHi[a] ? n.quad[1].hi[a] : n.quad[1].lo[a];
    const float* farLo = r.nearIsHi[a] ? n.quad[0].lo[a] : n.quad[0].hi[a];
    const float* farHi = r.nearIsHi[a] ? n.quad[1].lo[a] : n.quad[1].hi[a];
    const Float8 t0 = (load8(nearLo, nearHi) - r.origin[a]) * r.inv[a] - r.pad[a];
    const Float8 t1 = (load8(farLo, farHi) - r.origin[a]) * r.inv[a] + r.pad[a];
    // A NaN (0 * inf on a slab boundary, or inf - inf) leaves the bound as it was.
    in = maxOr(t0, in);
    out = minOr(t1, out);
  }
  store(enter, in);
  // Empty slots reject by themselves, unless a NaN left them unconstrained.
  return lessEqual(in, out * splat8(FloatRaySlabs::kSlack)) & ((1u << n.used) - 1);
}

}  // namespace pvrt
