// The four-lane sphere and plane tests must give every lane exactly the answer (hit or
// not, and the same t, bit for bit) that the scalar tests give for that ray: the images
// of every backend rest on it. Random rays, and the hard cases: tangent and grazing rays,
// rays from inside or from the surface, tiny and distant spheres, rays parallel to a
// plane, and intervals that end just before or after the hit.
#include "accel/packet_rays.h"

#include <gtest/gtest.h>

#include "random_geometry.h"

#include <vector>

namespace pvrt {
namespace {

class Lanes : public ::testing::Test {
 protected:
  test::RandomGeometry random{2026};
  double uniform(double lo, double hi) { return random.uniform(lo, hi); }
  Vec3 direction() { return random.direction(); }
  // Checks every ray of `rays` (any count up to kMaxPacket) against `check`.
  template <class Four, class One>
  void expectSameAnswers(const std::vector<Ray>& rays, const std::vector<double>& tMax, double tMin, Four&& four,
                         One&& one) {
    PacketRays packet;
    packet.set(rays.data(), int(rays.size()));
    alignas(32) double hi[kMaxPacket];
    for (int k = 0; k < packet.groups * 4; ++k) hi[k] = k < packet.count ? tMax[size_t(k)] : -INFINITY;
    for (int g = 0; g < packet.groups; ++g) {
      double t[4];
      const unsigned mask = four(packet, 4 * g, tMin, hi + 4 * g, t);
      for (int i = 0; i < 4; ++i) {
        const int k = 4 * g + i;
        if (k >= packet.count) continue;  // padding: callers mask it
        const std::optional<ShapeHit> want = one(rays[size_t(k)], tMin, tMax[size_t(k)]);
        ASSERT_EQ(want.has_value(), (mask >> i & 1u) != 0) << "ray " << k;
        if (want) {
          EXPECT_EQ(want->t, t[i]) << "ray " << k;
        }
        ++checked_;
        hits_ += want.has_value();
      }
    }
  }
  int checked_ = 0, hits_ = 0;
};

TEST_F(Lanes, SphereTestIsTheScalarOneLaneByLane) {
  for (int round = 0; round < 400; ++round) {
    const double scale = std::pow(10.0, uniform(-3, 3));
    const SphereShape s{Vec3{uniform(-5, 5), uniform(-5, 5), uniform(-5, 5)} * scale, uniform(0.01, 2) * scale};
    const float unit = round % 5 == 0 ? 0.001f : 1.0f;
    std::vector<Ray> rays;
    std::vector<double> tMax;
    const int n = 1 + round % kMaxPacket;
    for (int k = 0; k < n; ++k) {
      Vec3 o, d;
      switch (k % 6) {
        case 0:  // anywhere, toward anywhere near the sphere
          o = s.center + direction() * (s.radius * uniform(1.01, 50));
          d = normalize(s.center + direction() * (s.radius * uniform(0, 1.5)) - o);
          break;
        case 1: {  // tangent: aimed at a point of the silhouette
          o = s.center + direction() * (s.radius * uniform(2, 20));
          const Vec3 toC = normalize(s.center - o);
          Vec3 side = normalize(cross(toC, direction()));
          const double dist = length(s.center - o);
          const double along = std::sqrt(dist * dist - s.radius * s.radius);
          const Vec3 rim = o + normalize(toC * along + side * s.radius) * along;
          d = normalize(rim - o);
          break;
        }
        case 2:  // from inside
          o = s.center + direction() * (s.radius * uniform(0, 0.99));
          d = direction();
          break;
        case 3:  // from the surface, either way
          o = s.center + direction() * s.radius;
          d = direction();
          break;
        case 4:  // away from the sphere
          o = s.center + direction() * (s.radius * uniform(1.5, 9));
          d = normalize(o - s.center);
          break;
        default:  // far away
          o = s.center + direction() * (s.radius * 1e6);
          d = normalize(s.center - o);
          break;
      }
      rays.push_back({o, d});
      // Some intervals end just around the hit, most are open.
      tMax.push_back(k % 4 == 3 ? length(s.center - o) * uniform(0.5, 1.5) : kMaxDistance);
    }
    expectSameAnswers(
        rays, tMax, kMinIsectDepth,
        [&](const PacketRays& p, int first, double lo, const double* hi, double* t) {
          return intersectWorldSphere4(s, unit, p, first, lo, hi, t);
        },
        [&](const Ray& r, double lo, double hi) { return intersectWorldSphere(s, unit, r, lo, hi); });
  }
  EXPECT_GT(checked_, 10000);
  EXPECT_GT(hits_, checked_ / 4);
}

TEST_F(Lanes, PlaneTestIsTheScalarOneLaneByLane) {
  for (int round = 0; round < 300; ++round) {
    const PlaneShape p{direction(), uniform(-10, 10)};
    const float unit = round % 5 == 0 ? 0.001f : 1.0f;
    std::vector<Ray> rays;
    std::vector<double> tMax;
    const int n = 1 + round % kMaxPacket;
    for (int k = 0; k < n; ++k) {
      const Vec3 onPlane = p.normal * p.distance + normalize(cross(p.normal, direction())) * uniform(0, 20);
      Vec3 o = onPlane + p.normal * uniform(-10, 10), d = direction();
      if (k % 5 == 1) d = normalize(cross(p.normal, direction()));  // parallel
      if (k % 5 == 2) o = onPlane;                                    // starts on the plane
      if (k % 5 == 3) d = normalize(onPlane - o + direction() * 1e-9);
      rays.push_back({o, d});
      tMax.push_back(k % 3 == 2 ? uniform(0, 20) : kMaxDistance);
    }
    expectSameAnswers(
        rays, tMax, kMinIsectDepth,
        [&](const PacketRays& pk, int first, double lo, const double* hi, double* t) {
          return hitPlane4(p, unit, pk, first, lo, hi, t);
        },
        [&](const Ray& r, double lo, double hi) { return detail::hitPlane(p, r, lo, hi, unit); });
  }
  EXPECT_GT(checked_, 8000);
  EXPECT_GT(hits_, checked_ / 5);
}

// The packet's ranges bound every ray and ignore the padded lanes.
TEST_F(Lanes, RangesCoverTheRaysOnly) {
  std::vector<Ray> rays;
  for (int k = 0; k < 7; ++k) rays.push_back({{uniform(-1, 1), uniform(2, 3), uniform(-5, -4)}, direction()});
  PacketRays packet;
  packet.set(rays.data(), 7);
  Vec3 lo, hi;
  packet.originRange({1, 1, 1}, lo, hi);
  for (const Ray& r : rays) {
    for (int a = 0; a < 3; ++a) {
      EXPECT_LE(lo[a], r.origin[a] - 1);
      EXPECT_GE(hi[a], r.origin[a] - 1);
    }
  }
  EXPECT_GE(lo.y, 1.0);  // a padded lane counted as 0 - 1 would have pulled it below
  packet.directionRange(lo, hi);
  for (int a = 0; a < 3; ++a) {
    EXPECT_TRUE(std::isfinite(lo[a]) && std::isfinite(hi[a]));
    EXPECT_LE(lo[a], hi[a]);
  }
}

}  // namespace
}  // namespace pvrt
