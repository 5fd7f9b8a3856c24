// Double-precision 3-vector: points, directions and normals share one value type.
#pragma once

#include <cmath>

namespace pvrt {

struct Vec3 {
  double x = 0, y = 0, z = 0;

  constexpr Vec3() = default;
  constexpr Vec3(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}
  constexpr explicit Vec3(double s) : x(s), y(s), z(s) {}

  constexpr double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  constexpr double& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }

  constexpr Vec3 operator-() const { return {-x, -y, -z}; }
  constexpr Vec3& operator+=(const Vec3& o) { x += o.x; y += o.y; z += o.z; return *this; }
  constexpr Vec3& operator-=(const Vec3& o) { x -= o.x; y -= o.y; z -= o.z; return *this; }
  constexpr Vec3& operator*=(double s) { x *= s; y *= s; z *= s; return *this; }
  constexpr bool operator==(const Vec3&) const = default;
};

constexpr Vec3 operator+(Vec3 a, const Vec3& b) { return a += b; }
constexpr Vec3 operator-(Vec3 a, const Vec3& b) { return a -= b; }
constexpr Vec3 operator*(Vec3 a, double s) { return a *= s; }
constexpr Vec3 operator*(double s, Vec3 a) { return a *= s; }
constexpr Vec3 operator/(const Vec3& a, double s) { return {a.x / s, a.y / s, a.z / s}; }
constexpr Vec3 mul(const Vec3& a, const Vec3& b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }

constexpr double dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double length(const Vec3& a) { return std::sqrt(dot(a, a)); }
inline Vec3 normalize(const Vec3& a) { return a / length(a); }
// a times the power of two (exact) that brings its largest component to [1, 2): its
// squared length can then neither underflow nor overflow. Zero and non-finite a unchanged.
inline Vec3 rescaled(const Vec3& a) {
  const double m = std::fmax(std::fabs(a.x), std::fmax(std::fabs(a.y), std::fabs(a.z)));
  if (!(m > 0) || !std::isfinite(m)) return a;
  const int e = std::ilogb(m);
  return {std::scalbn(a.x, -e), std::scalbn(a.y, -e), std::scalbn(a.z, -e)};
}
// a / |a| for any finite non-zero a, however short or long; where normalize(a) neither
// underflows nor overflows, the same bits. For the vectors of a scene (normals, the
// camera's and a spotlight's directions), not per ray.
inline Vec3 unitDirection(const Vec3& a) { return normalize(rescaled(a)); }
// Component-wise min and max that, like std::fmin/fmax, ignore a NaN operand, but are
// inlined (std::fmin/fmax are library calls unless NaNs are ruled out).
inline double fminInline(double a, double b) { return b < a || a != a ? b : a; }
inline double fmaxInline(double a, double b) { return b > a || a != a ? b : a; }
inline Vec3 vmin(const Vec3& a, const Vec3& b) {
  return {fminInline(a.x, b.x), fminInline(a.y, b.y), fminInline(a.z, b.z)};
}
inline Vec3 vmax(const Vec3& a, const Vec3& b) {
  return {fmaxInline(a.x, b.x), fmaxInline(a.y, b.y), fmaxInline(a.z, b.z)};
}
inline bool isFinite(const Vec3& a) {
  return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z);
}

}  // namespace pvrt
