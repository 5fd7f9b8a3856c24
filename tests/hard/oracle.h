// Exact answers for the hard cases and the comparison of a render against them.
// An oracle gives every pixel its analytic colour plus the signed values of the discrete
// decisions behind it (a silhouette, a shadow edge, the critical angle...), each zero on
// its boundary. A pixel that differs from its analytic colour is an *edge* pixel when
// one of those boundaries passes within a pixel of it (its distance in pixels estimated
// from the neighbouring pixels' values), and an *error* otherwise.
#pragma once

#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "image/image.h"

namespace pvrt::hard {

inline constexpr double kNone = std::numeric_limits<double>::quiet_NaN();

struct Expected {
  Color c;
  std::array<double, 5> margin{kNone, kNone, kNone, kNone, kNone};  // decision values, 0 on a boundary
  double litTerm = 0;  // the light's (diffuse) share of the colour: > 0 where analytically lit
  bool skip = false;   // not compared (the case says why)
};

struct ExpectedImage {
  int width = 0, height = 0;
  std::vector<Expected> px;
  ExpectedImage(int w, int h) : width(w), height(h), px(size_t(w) * h) {}
  Expected& at(int x, int y) { return px[size_t(y) * width + x]; }
  const Expected& at(int x, int y) const { return px[size_t(y) * width + x]; }
};

struct Figures {
  long pixels = 0, nonFinite = 0, compared = 0, skipped = 0;
  long mismatched = 0;  // differ from the analytic colour
  long edge = 0;        // ... within a pixel of a decision boundary
  long errors = 0;      // ... anywhere else: holes, leaks, acne, wrong shading
  double maxEdgePixels = 0;  // the farthest edge pixel from its boundary (the silhouette error)
  double maxAbsError = 0;    // over the pixels that match
  double closestPixels = INFINITY;  // the nearest any compared pixel came to a boundary
  long lit = 0, acne = 0;    // analytically lit pixels, and those rendered (nearly) unlit
  bool pass() const { return nonFinite == 0 && errors == 0 && acne == 0 && maxEdgePixels <= 1.0; }
};

// Channels within absTol + relTol * |expected| count as equal.
Figures evaluate(const ExpectedImage& want, const Image& got, double absTol, double relTol);

// NaN or infinite channels of the float image (before any quantisation).
long countNonFinite(const Image& image);
// Pixels whose channels are not bit-identical.
long countDifferent(const Image& a, const Image& b);
double maxAbsDifference(const Image& a, const Image& b);

}  // namespace pvrt::hard
