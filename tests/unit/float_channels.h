// Checks of POV-Ray's float colour arithmetic (render/pov_colour.h, render/pov_secondary.h):
// the reference results are written one channel at a time through volatile floats, which no
// optimiser can fold, so a lane form that dropped a rounding or changed an order differs.
#pragma once

#include <gtest/gtest.h>

#include "render/pov_colour.h"

namespace pvrt::povcolour {

inline float roundedOnce(double v) {
  volatile float f = float(v);
  return f;
}

// RGBColour * DBL, one channel: the float widened, times k in double, rounded (a channel that
// is a float already rounds to itself first).
inline float scaledChannel(double c, double k) { return roundedOnce(double(roundedOnce(c)) * k); }

inline void expectChannels(const FloatColour& got, float r, float g, float b) {
  const Color c = toColor(got);
  EXPECT_EQ(c.r, double(r));
  EXPECT_EQ(c.g, double(g));
  EXPECT_EQ(c.b, double(b));
}

}  // namespace pvrt::povcolour
