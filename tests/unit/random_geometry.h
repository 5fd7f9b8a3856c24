// Random points and directions for the geometry tests, from a fixed seed so that a failure
// reproduces.
#pragma once

#include <cstdint>
#include <random>

#include "core/vec3.h"

namespace pvrt::test {

class RandomGeometry {
 public:
  explicit RandomGeometry(uint64_t seed) : rng_(seed) {}

  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng_); }
  // 0 .. n-1, each equally likely.
  int pick(int n) { return std::uniform_int_distribution<int>(0, n - 1)(rng_); }
  // Uniform in the cube [-half, half]^3.
  Vec3 point(double half) { return {uniform(-half, half), uniform(-half, half), uniform(-half, half)}; }
  // Uniform on the unit sphere (a normalised Gaussian).
  Vec3 direction() {
    std::normal_distribution<double> g;
    Vec3 d;
    do d = {g(rng_), g(rng_), g(rng_)};
    while (length(d) < 1e-6);
    return normalize(d);
  }

 private:
  std::mt19937_64 rng_;
};

}  // namespace pvrt::test
