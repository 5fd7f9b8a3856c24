#pragma once

#include <cassert>
#include <cmath>

namespace pvrt {

// The largest x whose square root, correctly rounded, is at most k (0 <= k < infinity).
// Rounding never reverses an order, so std::sqrt(x) <= k exactly when x <= squareBound(k):
// a hot comparison of a length with a fixed bound can then skip the square root and still
// decide every case as the length would.
inline double squareBound(double k) {
  assert(k >= 0 && k < INFINITY);
  double x = k * k;
  while (x > 0 && std::sqrt(x) > k) x = std::nextafter(x, 0.0);
  while (std::sqrt(std::nextafter(x, INFINITY)) <= k) x = std::nextafter(x, INFINITY);
  return x;
}

}  // namespace pvrt
