// How a pixel's value is formed from its rays' colours, the same way on every path:
// POV-Ray's float sum, a NaN channel written as 0 and overflow clamped to a float, as
// POV-Ray writes them.
#pragma once

#include <cmath>
#include <cstddef>
#include <limits>

#include "core/color.h"
#include "image/image.h"
#include "render/stats.h"

namespace pvrt {

// The NaN census. A camera sample whose colour is not finite (NaN or infinite: arithmetic
// past the range of a float, or a negative colour raised to a fractional reflection
// exponent, which POV-Ray computes too) is counted, and `pvrt render` warns. It is summed
// as POV-Ray sums it, channel by channel in float (PixelSum), and its pixel is written as
// POV-Ray writes it: a channel whose sum is NaN as 0 (IntEncode's float-to-integer
// conversion of a NaN gives 0: a pixel of green glass whose red is NaN stays green), one
// beyond the image's float as +-FLT_MAX (white where positive). So no NaN or infinity
// reaches the image, and the pixel's other channels keep the sample's finite values.
inline bool finiteSamples(const Color* colors, size_t count, RenderStats& stats) {
  bool all = true;
  for (size_t k = 0; k < count; ++k) {
    const Color& c = colors[k];
    if (std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b)) continue;
    ++stats.nonFiniteSamples;
    all = false;
  }
  return all;
}
inline void setPixel(Image& image, int x, int y, Color c, bool finite, RenderStats& stats) {
  constexpr double kMax = std::numeric_limits<float>::max();
  for (double* v : {&c.r, &c.g, &c.b}) {
    if (std::isnan(*v)) {
      *v = 0.0;
      finite = false;
    } else if (!(std::fabs(*v) <= kMax)) {
      *v = std::copysign(kMax, *v);
      finite = false;
    }
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
