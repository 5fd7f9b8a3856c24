// POV-Ray 3.7's colour arithmetic where it lights a surface: RGBColour holds floats, so
// each product and sum of ComputeLightedTexture and ComputeDiffuseColour is a float (a float
// times a double is formed in double and then rounded). pvrt forms the same terms in the
// same order in floats, so that a value near the edge between two output levels falls on
// POV-Ray's side (docs/fidelity.md: light_point). The terms stay floats until the last sum:
// converting each back to a double would be the double(float(x)) that GCC 12's vectoriser
// drops (core/single.h).
//
// With AVX a colour is one register of four float lanes (r, g, b, 0) and its double form one
// of four double lanes: a rounding is one conversion instruction for the three channels, and
// the compiler sees intrinsics, not a double(float(x)) it could drop. Every lane does the
// IEEE operation the scalar form does, so both give the same bits (tests/unit/pov_colour_test.cpp).
#pragma once

#include <algorithm>
#include <cmath>

#include "core/color.h"

#if defined(__AVX__) && !defined(PVRT_LANES_SCALAR)
#include <immintrin.h>
#define PVRT_POV_COLOUR_LANES 1
#endif

namespace pvrt::povcolour {

#if defined(PVRT_POV_COLOUR_LANES)

struct FloatColour {
  __m128 v = _mm_setzero_ps();
  FloatColour() = default;
  explicit FloatColour(__m128 x) : v(x) {}
  FloatColour(float r, float g, float b) : v(_mm_setr_ps(r, g, b, 0)) {}
};
// A FloatColour widened to doubles (exact), kept where one colour is scaled many times.
struct WideColour {
  __m256d v;
};
// c rounded to floats (a pigment that a pattern blended in double, a light after its
// attenuation); exact for a colour stored rounded (core/single.h).
inline FloatColour rounded(const Color& c) { return FloatColour(_mm256_cvtpd_ps(_mm256_setr_pd(c.r, c.g, c.b, 0))); }
inline WideColour widened(const FloatColour& c) { return {_mm256_cvtps_pd(c.v)}; }
inline Color toColor(const FloatColour& c) {
  alignas(32) double d[4];
  _mm256_store_pd(d, _mm256_cvtps_pd(c.v));
  return {d[0], d[1], d[2]};
}
inline FloatColour operator+(const FloatColour& a, const FloatColour& b) { return FloatColour(_mm_add_ps(a.v, b.v)); }
inline FloatColour operator-(const FloatColour& a, const FloatColour& b) { return FloatColour(_mm_sub_ps(a.v, b.v)); }
inline FloatColour operator*(const FloatColour& a, const FloatColour& b) { return FloatColour(_mm_mul_ps(a.v, b.v)); }
// RGBColour * DBL: each product in double, then rounded.
inline FloatColour scaled(const WideColour& c, double k) {
  return FloatColour(_mm256_cvtpd_ps(_mm256_mul_pd(c.v, _mm256_set1_pd(k))));
}
// RGBColour / DBL: each quotient in double, then rounded.
inline FloatColour divided(const FloatColour& c, double k) {
  return FloatColour(_mm256_cvtpd_ps(_mm256_div_pd(_mm256_cvtps_pd(c.v), _mm256_set1_pd(k))));
}
// Each channel times its own double factor (RGBColour::red() *= DBL), then rounded.
inline FloatColour scaled(const FloatColour& c, const Color& k) {
  return FloatColour(_mm256_cvtpd_ps(_mm256_mul_pd(_mm256_cvtps_pd(c.v), _mm256_setr_pd(k.r, k.g, k.b, 0))));
}

#else

struct FloatColour {
  float r = 0, g = 0, b = 0;
};
struct WideColour {
  double r, g, b;
};
inline FloatColour rounded(const Color& c) { return {float(c.r), float(c.g), float(c.b)}; }
inline WideColour widened(const FloatColour& c) { return {c.r, c.g, c.b}; }
inline Color toColor(const FloatColour& c) { return {c.r, c.g, c.b}; }
inline FloatColour operator+(const FloatColour& a, const FloatColour& b) { return {a.r + b.r, a.g + b.g, a.b + b.b}; }
inline FloatColour operator-(const FloatColour& a, const FloatColour& b) { return {a.r - b.r, a.g - b.g, a.b - b.b}; }
inline FloatColour operator*(const FloatColour& a, const FloatColour& b) { return {a.r * b.r, a.g * b.g, a.b * b.b}; }
inline FloatColour scaled(const WideColour& c, double k) { return {float(c.r * k), float(c.g * k), float(c.b * k)}; }
inline FloatColour divided(const FloatColour& c, double k) {
  return {float(double(c.r) / k), float(double(c.g) / k), float(double(c.b) / k)};
}
inline FloatColour scaled(const FloatColour& c, const Color& k) {
  return {float(double(c.r) * k.r), float(double(c.g) * k.g), float(double(c.b) * k.b)};
}

#endif

inline FloatColour scaled(const FloatColour& c, double k) { return scaled(widened(c), k); }

// The surface's own light: pigment x ambient x ambient_light x opacity, plus pigment x
// emission x opacity.
inline FloatColour ambient(const Color& pigment, const Color& ambient, const Color& ambientLight,
                           const Color& emission, double opacity) {
  const FloatColour p = rounded(pigment);
  return scaled(p * rounded(ambient) * rounded(ambientLight), opacity) + scaled(p * rounded(emission), opacity);
}

// ComputeDiffuseColour: intensity = cos^brilliance x (diffuse x attenuation) in double (the
// caller's, so that the inner product is formed once for all lights), then (intensity x
// pigment) x light colour. The pigment comes widened, once per hit point for all its lights.
inline FloatColour diffuse(const WideColour& pigment, double intensity, const FloatColour& light) {
  return scaled(pigment, intensity) * light;
}

// ComputePhongColour, ComputeSpecularColour: intensity x light colour.
inline FloatColour highlight(const WideColour& light, double intensity) { return scaled(light, intensity); }

// The Fresnel-like curve POV-Ray tints metallic highlights and reflections with, from the
// cosine between the normal and the light or view direction: an acos outside [-1, 1] is NaN,
// which max(0, F) turns into 0, as POV-Ray's min/max do.
inline double metallicFresnel(double cosAngle) {
  const double x = std::fabs(std::acos(cosAngle)) / 1.57079632679489661923;  // M_PI_2
  const double f = 0.014567225 / ((x - 1.12) * (x - 1.12)) - 0.011612903;
  return std::min(1.0, std::max(0.0, f));
}

// The same with a metallic tint (Metallic > 0): intensity x (light x (1 + m(1 - F) x
// (pigment - 1))), the tint formed in float colours; F from the cosine nl between normal and
// light.
inline FloatColour metallicHighlight(const FloatColour& light, double intensity, double metallic, double nl,
                                     const FloatColour& pigment) {
  const double f = metallicFresnel(nl);
  const FloatColour one{1.0f, 1.0f, 1.0f};
  return scaled(light * (one + scaled(pigment - one, metallic * (1.0 - f))), intensity);
}

}  // namespace pvrt::povcolour
