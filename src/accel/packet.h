// Coherent ray packets: up to kMaxPacket rays or shadow segments that share one point
// (the camera for the primary rays of a pixel, the light for their shadow segments).
// The BVH culls a subtree for the whole packet with one interval-arithmetic test on the
// range of their directions (Boulos et al., "Packet-based Whitted and distribution ray
// tracing", 2007), so the cost of walking the tree is paid once per packet instead of
// once per ray; each ray is still intersected with each primitive exactly as alone.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "core/ray.h"
#include "geometry/bounds.h"

namespace pvrt {

inline constexpr int kMaxPacket = 64;
// Below this many rays per pixel a packet saves too little to pay for itself.
inline constexpr size_t kMinPacket = 4;

// Every point the packet can reach is apex + s * v for one of its vectors v and some
// s in [sLo, sHi]. Built from the vectors; tests boxes conservatively.
class PacketCone {
 public:
  // `vector(k)` gives the k-th vector (computed on the fly: no array to fill).
  template <class VectorOf>
  PacketCone(const Vec3& apex, VectorOf&& vector, int count, double sLo) : apex_(apex), sLo_(sLo) {
    Vec3 lo(INFINITY), hi(-INFINITY);
    for (int k = 0; k < count; ++k) {
      const Vec3 v = vector(k);
      lo = vmin(lo, v);
      hi = vmax(hi, v);
    }
    setRange(lo, hi);
  }
  // The cone of vectors whose components lie in [lo, hi].
  PacketCone(const Vec3& apex, const Vec3& lo, const Vec3& hi, double sLo) : apex_(apex), sLo_(sLo) {
    setRange(lo, hi);
  }

  // The smallest s in [sLo, sHi] at which some vector's segment may reach the box (a
  // lower bound, for ordering boxes front to back), or infinity only when none can.
  double entry(const Bounds& b, double sHi) const;
  // entry() for four boxes at once, given as float bounds [axis][box] (a quad of a BVH
  // node's children): bit c of the result is set when box c may be reached, and enter[c] is the
  // entry. Never less generous than entry().
  unsigned entries(const float (&lo)[3][4], const float (&hi)[3][4], double sHi, double* enter) const;

 private:
  void setRange(const Vec3& lo, const Vec3& hi);

  Vec3 apex_;
  double invA_[3], invB_[3];  // the reciprocals of the extreme components (same sign)
  int sign_[3];
  double sLo_;
};

}  // namespace pvrt
