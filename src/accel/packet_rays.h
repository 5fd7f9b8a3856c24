// A packet's rays a component per array, and the primitive tests that take four of them
// at once. Every lane does the scalar test's IEEE operations in the scalar test's order
// (with -ffp-contract=off, no fused multiply-adds), so a lane's answer is bit for bit the
// one the scalar test gives for that ray.
#pragma once

#include <cmath>
#include <cstdint>

#include "accel/packet.h"
#include "core/lanes.h"
#include "geometry/primitive.h"

namespace pvrt {

struct PacketRays {
  // Lanes past `count` up to the next multiple of four hold NaN: the ranges below ignore
  // them, and callers mask the tests' answers for them (a NaN ray hits a plane, with a
  // NaN t, in the scalar test too).
  alignas(32) double ox[kMaxPacket], oy[kMaxPacket], oz[kMaxPacket];
  alignas(32) double dx[kMaxPacket], dy[kMaxPacket], dz[kMaxPacket];
  int count = 0;
  int groups = 0;  // of four lanes

  void set(const Ray* rays, int n) {
    for (int k = 0; k < n; ++k) set(k, rays[k].origin, rays[k].dir);
    finish(n);
  }
  void set(int k, const Vec3& origin, const Vec3& dir) {
    ox[k] = origin.x, oy[k] = origin.y, oz[k] = origin.z;
    dx[k] = dir.x, dy[k] = dir.y, dz[k] = dir.z;
  }
  // After set(k, ...) for k in [0, n): the count, and the padding.
  void finish(int n) {
    count = n;
    groups = (n + 3) / 4;
    for (int k = n; k < groups * 4; ++k) ox[k] = oy[k] = oz[k] = dx[k] = dy[k] = dz[k] = NAN;
  }
  Ray ray(int k) const { return {{ox[k], oy[k], oz[k]}, {dx[k], dy[k], dz[k]}}; }

  // The componentwise range of the directions, or of the origins less `base`.
  void directionRange(Vec3& lo, Vec3& hi) const { range(dx, dy, dz, Vec3(0.0), lo, hi); }
  void originRange(const Vec3& base, Vec3& lo, Vec3& hi) const { range(ox, oy, oz, base, lo, hi); }

 private:
  void range(const double* x, const double* y, const double* z, const Vec3& base, Vec3& lo, Vec3& hi) const {
    using namespace lanes;
    const double* c[3] = {x, y, z};
    for (int a = 0; a < 3; ++a) {
      Double4 mn = splat(INFINITY), mx = splat(-INFINITY);
      const Double4 b = splat(base[a]);
      for (int g = 0; g < groups; ++g) {
        const Double4 v = load(c[a] + 4 * g) - b;
        mn = minOr(v, mn);  // a NaN lane keeps what it had
        mx = maxOr(v, mx);
      }
      double l[4], h[4];
      store(l, mn);
      store(h, mx);
      lo[a] = std::min({l[0], l[1], l[2], l[3]});
      hi[a] = std::max({h[0], h[1], h[2], h[3]});
    }
  }
};

// intersectWorldSphere() for rays first .. first+3 of `r` over (lo, hi[lane]): bit i of the
// result is set when ray first+i hits, and then t[i] is its hit distance.
inline unsigned intersectWorldSphere4(const SphereShape& s, float unitF, const PacketRays& r, int first, double lo,
                                      const double* hi, double* t) {
  using namespace lanes;
  const double unit = unitF, r2s = s.radius * s.radius;
  const Double4 r2 = splat(r2s);
  const Double4 ocx = splat(s.center.x) - load(r.ox + first);
  const Double4 ocy = splat(s.center.y) - load(r.oy + first);
  const Double4 ocz = splat(s.center.z) - load(r.oz + first);
  const Double4 dx = load(r.dx + first), dy = load(r.dy + first), dz = load(r.dz + first);
  const Double4 ocSquared = ocx * ocx + ocy * ocy + ocz * ocz;
  const Double4 closest = ocx * dx + ocy * dy + ocz * dz;
  // Outside and moving away: no hit (as the scalar test's first early return).
  unsigned live = ~(lessEqual(r2, ocSquared) & less(closest, splat(kPovEpsilon * unit))) & 0xFu;
  if (live == 0) return 0;
  // POV-Ray's arithmetic, or Haines's in the lanes whose sphere is beyond its reach.
  const Double4 eps = splat(kPovEpsilon * unit * unit);
  const unsigned far = less(r2 * splat(kPovSphereReach2), ocSquared) & live;
  Double4 halfChord2 = r2 - ocSquared + closest * closest;
  if (far != 0) {
    const Double4 px = ocx - dx * closest, py = ocy - dy * closest, pz = ocz - dz * closest;
    halfChord2 = select(far, r2 - (px * px + py * py + pz * pz), halfChord2);
  }
  live &= less(eps, halfChord2);  // a NaN half chord misses, as in the scalar test
  if (live == 0) return 0;
  const Double4 halfChord = lanes::sqrt(halfChord2);
  Double4 t1 = closest - halfChord, q = closest + halfChord;
  if (far != 0) {
    const Double4 farRoot = closest + copySign(halfChord, closest);
    const Double4 nearRoot = (ocSquared - r2) / farRoot;
    t1 = select(far, nearRoot, t1);
    q = select(far, farRoot, q);
  }
  // nearestRoot(t1, q, max(lo, depth), hi): the smaller of the roots inside the interval.
  const double loS = std::max(lo, kDepthTolerance * unit);
  const Double4 low = splat(loS), high = load(hi);
  const unsigned in1 = less(low, t1) & less(t1, high), in2 = less(low, q) & less(q, high);
  live &= in1 | in2;
  if (live == 0) return 0;
  double a[4], b[4];
  store(a, t1);
  store(b, q);
  for (unsigned m = live; m != 0; m &= m - 1) {
    const int i = __builtin_ctz(m);
    t[i] = (in1 >> i & 1u) && (in2 >> i & 1u) ? (a[i] > b[i] ? b[i] : a[i]) : (in1 >> i & 1u) ? a[i] : b[i];
  }
  return live;
}

// detail::hitPlane() for rays first .. first+3 of `r` over (lo, hi[lane]), as
// intersectWorldSphere4() gives its answers.
inline unsigned hitPlane4(const PlaneShape& p, float unitF, const PacketRays& r, int first, double lo, const double* hi,
                          double* t) {
  using namespace lanes;
  const double unit = unitF, depth = kDepthTolerance * unit;
  const Double4 dx = load(r.dx + first), dy = load(r.dy + first), dz = load(r.dz + first);
  const Double4 nx = splat(p.normal.x), ny = splat(p.normal.y), nz = splat(p.normal.z);
  const Double4 nd = nx * dx + ny * dy + nz * dz;
  const Double4 len2 = dx * dx + dy * dy + dz * dz;
  unsigned live = ~less(nd * nd, splat(kPovEpsilon * kPovEpsilon) * len2) & 0xFu;
  if (live == 0) return 0;
  const Double4 dist = splat(p.distance) - (nx * load(r.ox + first) + ny * load(r.oy + first) + nz * load(r.oz + first));
  const Double4 tt = dist / nd;
  live &= ~(lessEqual(tt, splat(lo)) | lessEqual(load(hi), tt) | lessEqual(tt * tt * len2, splat(depth * depth)));
  if (live != 0) store(t, tt);
  return live;
}

}  // namespace pvrt
