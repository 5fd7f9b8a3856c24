// How a pixel's value is formed from its rays' colours, the same way on every path:
// non-finite samples as black, POV-Ray's float sum, overflow clamped to a float.
#pragma once

#include <cmath>
#include <cstddef>
#include <limits>

#include "core/color.h"
#include "image/image.h"
#include "render/stats.h"

namespace pvrt {

// The NaN census. A camera sample whose colour is not finite (NaN or infinite: a bug, or
// arithmetic past the range of a double) is counted and counts as black: one bad ray must
// neither poison its pixel nor reach the image, and black is what no light looks like. A
// pixel whose value overflows the image's float is written as +-FLT_MAX (the brightest
// value the image can hold) and counted too. Either way `pvrt render` warns.
inline bool finiteSamples(Color* colors, size_t count, RenderStats& stats) {
  bool all = true;
  for (size_t k = 0; k < count; ++k) {
    Color& c = colors[k];
    if (std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b)) continue;
    c = Color();
    ++stats.nonFiniteSamples;
    all = false;
  }
  return all;
}
inline void setPixel(Image& image, int x, int y, Color c, bool finite, RenderStats& stats) {
  constexpr double kMax = std::numeric_limits<float>::max();
  for (double* v : {&c.r, &c.g, &c.b})
    if (!(std::fabs(*v) <= kMax)) {
      *v = std::copysign(kMax, *v);
      finite = false;
    }
  if (!finite) ++stats.nonFinitePixels;
  image.set(x, y, c);
}

// A pixel's rays' colours summed as POV-Ray sums them (TraceTask::SupersampleOnePixel):
// each a float colour, added in sample order in float, the sum divided by the count in
// double and stored as a float. Summed in double, a channel within a hair of a level's
// edge lands on the other side of it.
struct PixelSum {
  float r = 0, g = 0, b = 0;
  void add(const Color& c) {
    r += float(c.r);
    g += float(c.g);
    b += float(c.b);
  }
  Color mean(size_t count) const {
    const double n = double(count);
    return {double(r) / n, double(g) / n, double(b) / n};
  }
};

}  // namespace pvrt
