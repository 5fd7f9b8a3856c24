// POV-Ray 3.7's colour arithmetic where it lights a surface: RGBColour holds floats, so
// each product and sum of ComputeLightedTexture and ComputeDiffuseColour is a float (a float
// times a double is formed in double and then rounded). pvrt forms the same terms in the
// same order in floats, so that a value near the edge between two output levels falls on
// POV-Ray's side (docs/fidelity.md: light_point). The terms stay floats until the last sum:
// converting each back to a double would be the double(float(x)) that GCC 12's vectoriser
// drops (core/single.h).
#pragma once

#include "core/color.h"

namespace pvrt::povcolour {

struct FloatColour {
  float r = 0, g = 0, b = 0;
};
// A colour whose channels are floats already (pigments, finishes and lights are rounded at
// load, core/single.h): exact.
inline FloatColour fromStored(const Color& c) { return {float(c.r), float(c.g), float(c.b)}; }
inline Color toColor(const FloatColour& c) { return {c.r, c.g, c.b}; }

inline FloatColour operator+(const FloatColour& a, const FloatColour& b) { return {a.r + b.r, a.g + b.g, a.b + b.b}; }
inline FloatColour operator*(const FloatColour& a, const FloatColour& b) { return {a.r * b.r, a.g * b.g, a.b * b.b}; }
// RGBColour * DBL: each product in double, then rounded.
inline FloatColour scaled(const FloatColour& c, double k) {
  return {float(double(c.r) * k), float(double(c.g) * k), float(double(c.b) * k)};
}

// The surface's own light: pigment x ambient x ambient_light x opacity, plus pigment x
// emission x opacity.
inline FloatColour ambient(const Color& pigment, const Color& ambient, const Color& ambientLight,
                           const Color& emission, double opacity) {
  const FloatColour p = fromStored(pigment);
  return scaled(p * fromStored(ambient) * fromStored(ambientLight), opacity) +
         scaled(p * fromStored(emission), opacity);
}

// ComputeDiffuseColour: intensity = cos^brilliance times (diffuse x attenuation) in double,
// then (intensity x pigment) x light colour.
inline FloatColour diffuse(const Color& pigment, double cosPower, double diffuse, double attenuation,
                           const Color& light) {
  return scaled(fromStored(pigment), cosPower * (diffuse * attenuation)) * fromStored(light);
}

// ComputePhongColour, ComputeSpecularColour: intensity x light colour.
inline FloatColour highlight(const Color& light, double intensity) {
  return scaled(fromStored(light), intensity);
}

}  // namespace pvrt::povcolour
