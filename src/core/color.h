// Linear RGB colour. POV-Ray keeps colours in float32; pvrt keeps them in double so
// that its rounding error sits far below POV-Ray's (see docs/povray-differences.md).
#pragma once

#include <algorithm>
#include <cmath>

namespace pvrt {

struct Color {
  double r = 0, g = 0, b = 0;

  constexpr Color() = default;
  constexpr Color(double r_, double g_, double b_) : r(r_), g(g_), b(b_) {}
  constexpr explicit Color(double s) : r(s), g(s), b(s) {}

  constexpr Color& operator+=(const Color& o) { r += o.r; g += o.g; b += o.b; return *this; }
  constexpr Color& operator*=(const Color& o) { r *= o.r; g *= o.g; b *= o.b; return *this; }
  constexpr Color& operator*=(double s) { r *= s; g *= s; b *= s; return *this; }
  constexpr bool operator==(const Color&) const = default;

  constexpr double maxComponent() const { return std::max(r, std::max(g, b)); }
  constexpr bool isBlack() const { return r == 0 && g == 0 && b == 0; }
};

constexpr Color operator+(Color a, const Color& b) { return a += b; }
constexpr Color operator-(const Color& a, const Color& b) { return {a.r - b.r, a.g - b.g, a.b - b.b}; }
constexpr Color operator*(Color a, const Color& b) { return a *= b; }
constexpr Color operator*(Color a, double s) { return a *= s; }
constexpr Color operator*(double s, Color a) { return a *= s; }

// A pigment colour: RGB plus POV-Ray's filter (tinted transparency) and transmit
// (untinted transparency).
struct FilterColor {
  Color rgb;
  double filter = 0;
  double transmit = 0;
  constexpr bool operator==(const FilterColor&) const = default;
};

}  // namespace pvrt
