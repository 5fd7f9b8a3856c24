// POV-Ray 3.7's colour arithmetic where it lights a surface: RGBColour holds floats, so
// each product and sum of ComputeLightedTexture and ComputeDiffuseColour is rounded to a
// float (a float times a double is formed in double and then rounded). pvrt forms the same
// terms in the same order with each step rounded (core/single.h), so that a value near the
// edge between two output levels falls on POV-Ray's side (docs/fidelity.md: light_point).
#pragma once

#include "core/color.h"
#include "core/single.h"

namespace pvrt::povcolour {

// a + b, RGBColour::operator+=.
inline Color add(const Color& a, const Color& b) { return {single(a.r + b.r), single(a.g + b.g), single(a.b + b.b)}; }
// c * k, RGBColour * DBL.
inline Color scaled(const Color& c, double k) { return {single(c.r * k), single(c.g * k), single(c.b * k)}; }
// a * b, RGBColour * RGBColour (floats: the product is exact in double, then rounded).
inline Color times(const Color& a, const Color& b) { return {single(a.r * b.r), single(a.g * b.g), single(a.b * b.b)}; }

// The surface's own light: pigment x ambient x ambient_light x opacity, plus pigment x
// emission x opacity, each a float operation, added to an empty colour in that order.
inline Color ambient(const Color& pigment, const Color& ambient, const Color& ambientLight, const Color& emission,
                     double opacity) {
  const Color a = scaled(times(times(pigment, ambient), ambientLight), opacity);
  return add(a, scaled(times(pigment, emission), opacity));
}

// ComputeDiffuseColour: intensity = cos^brilliance, times (diffuse x attenuation) in
// double, then (intensity x pigment) x light colour in float.
inline Color diffuse(const Color& pigment, double cosPower, double diffuse, double attenuation, const Color& light) {
  const double intensity = cosPower * (diffuse * attenuation);
  return times(scaled(pigment, intensity), light);
}

}  // namespace pvrt::povcolour
