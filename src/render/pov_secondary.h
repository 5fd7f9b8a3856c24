// POV-Ray 3.7's float colour arithmetic for the light a surface passes on: its reflectivity
// (ComputeReflectivity and the reflection's metallic tint in ComputeLightedTexture), the
// filter its pigment puts on transmitted light and the fade of the interior behind it. Each
// is an RGBColour there, so every product and sum is a float (render/pov_colour.h); near 0
// the sign of a reflected channel, and so whether a reflection exponent gives NaN, depends
// on it (docs/fidelity.md: finish_every_field).
#pragma once

#include <algorithm>
#include <cmath>

#include "core/color.h"
#include "render/pov_colour.h"
#include "scene/scene_desc.h"

namespace pvrt::povcolour {

// Reflectivity at incidence cosI (ray-facing normal) before any metallic tint, and the
// factor the reflected ray's weight is scaled by. `relIor` is ComputeRelativeIOR's ratio
// (used with fresnel only).
struct Reflectivity {
  FloatColour colour;
  double weightFactor;
};
inline Reflectivity reflectivity(const ReflectionDesc& r, double cosI, double relIor) {
  constexpr double kEpsilon = 1e-10;  // POV-Ray's EPSILON
  const FloatColour max = rounded(r.max), min = rounded(r.min);
  if (!r.fresnel) {
    const double frac = std::fabs(r.falloff - 1.0) > kEpsilon ? std::pow(1.0 - cosI, r.falloff) : 1.0 - cosI;
    const double weightFactor = std::max(r.max.maxComponent(), r.min.maxComponent());
    if (std::fabs(frac) < kEpsilon) return {min, weightFactor};
    if (std::fabs(frac - 1.0) < kEpsilon) return {max, weightFactor};
    // Formed even where min = max: the two float products need not add up to max.
    return {scaled(max, frac) + scaled(min, 1.0 - frac), weightFactor};
  }
  FloatColour rho = max;
  const double sqx = relIor * relIor + cosI * cosI - 1.0;
  if (sqx > 0.0) {
    const double g = std::sqrt(sqx);
    const double a = g - cosI, b = g + cosI;
    const double c = cosI * (g + cosI) - 1.0, d = cosI * (g - cosI) + 1.0;
    double f = 0.5 * ((a * a) / (b * b));
    f = f * (1.0 + (c * c) / (d * d));
    f = std::min(1.0, std::max(0.0, f));
    rho = scaled(max, f) + scaled(min, 1.0 - f);
  }
  const Color wide = toColor(rho);
  return {rho, wide.maxComponent()};
}

// The reflection's metallic tint: each channel times 1 + m(1 - F)(pigment - 1), F the same
// Fresnel-like curve as the highlights' (metallicFresnel). `pigment` holds floats.
inline FloatColour metallicReflection(const FloatColour& rho, double metallic, double cosI, const Color& pigment) {
  const double k = metallic * (1.0 - metallicFresnel(cosI));
  return scaled(rho, Color(1.0 + k * (pigment.r - 1.0), 1.0 + k * (pigment.g - 1.0), 1.0 + k * (pigment.b - 1.0)));
}

// GenericColour::rgbTransm: pigment x filter + transmit, in float.
inline FloatColour transmittedFilter(const FilterColor& pig) {
  const float filter = float(pig.filter), transmit = float(pig.transmit);
  return rounded(pig.rgb) * FloatColour{filter, filter, filter} + FloatColour{transmit, transmit, transmit};
}

// conserve_energy: the filter times min(1, 1 - reflectivity), each factor rounded to float.
inline FloatColour conserved(const FloatColour& filter, const FloatColour& rho) {
  const Color r = toColor(rho);
  return filter * rounded(Color(std::min(1.0, 1.0 - r.r), std::min(1.0, 1.0 - r.g), std::min(1.0, 1.0 - r.b)));
}

// RGBColour::greyscale: weighted in double, returned as a float.
inline double greyscale(const FloatColour& c) {
  const Color w = toColor(c);
  return double(float(0.297 * w.r + 0.589 * w.g + 0.114 * w.b));
}

// The fade of light that crossed an interior for `depth` (ComputeLightedTexture's attCol).
inline FloatColour interiorFade(const InteriorDesc& in, double depth) {
  const FloatColour fade = rounded(in.fadeColor), one{1.0f, 1.0f, 1.0f};
  if (in.fadePower >= 1000) {
    // exp(-(1 - fade) x depth): the float overload of exp, as <math.h> declares it in C++.
    const Color e = toColor(scaled(FloatColour{} - (one - fade), depth / in.fadeDistance));
    return {std::exp(float(e.r)), std::exp(float(e.g)), std::exp(float(e.b))};
  }
  const double att = 1.0 + std::pow(depth / in.fadeDistance, in.fadePower);
  return fade + divided(one - fade, att);
}

}  // namespace pvrt::povcolour
