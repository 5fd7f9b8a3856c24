#include "accel/packet.h"

#include <algorithm>
#include <cmath>

#include "core/lanes.h"

namespace pvrt {

void PacketCone::setRange(const Vec3& lo, const Vec3& hi) {
  for (int a = 0; a < 3; ++a) {
    // Components that straddle or touch zero give no bound along this axis (a
    // reciprocal interval through infinity); the other two axes still cull.
    sign_[a] = lo[a] > 0 ? 1 : hi[a] < 0 ? -1 : 0;
    invA_[a] = sign_[a] ? 1.0 / lo[a] : 0.0;
    invB_[a] = sign_[a] ? 1.0 / hi[a] : 0.0;
    if (!std::isfinite(invA_[a]) || !std::isfinite(invB_[a])) sign_[a] = 0;  // denormal components
  }
}

double PacketCone::entry(const Bounds& b, double sHi) const {
  double enter = sLo_, leave = sHi;
  for (int a = 0; a < 3; ++a) {
    if (sign_[a] == 0) continue;
    // Along this axis the ray with component v is inside the slab for s between
    // (near - apex)/v and (far - apex)/v; 1/v lies between invA and invB, and these
    // bounds are monotone in 1/v, so the extremes come from the two ends.
    const double nearD = (sign_[a] > 0 ? b.lo[a] : b.hi[a]) - apex_[a];
    const double farD = (sign_[a] > 0 ? b.hi[a] : b.lo[a]) - apex_[a];
    const double n1 = nearD * invA_[a], n2 = nearD * invB_[a];
    const double f1 = farD * invA_[a], f2 = farD * invB_[a];
    enter = std::max(enter, std::min(n1, n2));
    leave = std::min(leave, std::max(f1, f2));
  }
  // Slack far above rounding (a few ulps): culling must never be less generous than
  // testing each ray on its own.
  return enter <= leave + 1e-9 * (std::fabs(enter) + std::fabs(leave)) ? enter : INFINITY;
}

unsigned PacketCone::entries(const float (&lo)[3][4], const float (&hi)[3][4], double sHi, double* enter) const {
  using namespace lanes;
  Double4 in = splat(sLo_), out = splat(sHi);
  for (int a = 0; a < 3; ++a) {
    if (sign_[a] == 0) continue;
    const Double4 apex = splat(apex_[a]), invA = splat(invA_[a]), invB = splat(invB_[a]);
    const Double4 nearD = widen(sign_[a] > 0 ? lo[a] : hi[a]) - apex;
    const Double4 farD = widen(sign_[a] > 0 ? hi[a] : lo[a]) - apex;
    // As in entry(); a NaN bound (from a NaN box) leaves the interval as it was.
    in = maxOr(minOr(nearD * invA, nearD * invB), in);
    out = minOr(maxOr(farD * invA, farD * invB), out);
  }
  store(enter, in);
  return lessEqual(in, out + splat(1e-9) * (abs(in) + abs(out)));
}

}  // namespace pvrt
