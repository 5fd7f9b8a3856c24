// Affine transforms in POV-Ray's convention: transforms apply in the order written,
// each new one after the previous ones; rotations are in degrees, x then y then z,
// left-handed (rotate y*90 takes +x to -z). Stored with its inverse so that objects
// can be intersected in their own space.
#pragma once

#include <array>
#include <memory>
#include <optional>

#include "core/vec3.h"

namespace pvrt {

// Column-vector affine map p' = m * p + t.
struct Affine {
  std::array<std::array<double, 3>, 3> m{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  Vec3 t;

  Vec3 applyPoint(const Vec3& p) const { return applyVector(p) + t; }
  Vec3 applyVector(const Vec3& v) const {
    return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z,
            m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
            m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
  }
  // Multiplies by the transpose: with the inverse map this transforms normals.
  Vec3 applyTransposed(const Vec3& v) const {
    return {m[0][0] * v.x + m[1][0] * v.y + m[2][0] * v.z,
            m[0][1] * v.x + m[1][1] * v.y + m[2][1] * v.z,
            m[0][2] * v.x + m[1][2] * v.y + m[2][2] * v.z};
  }
  double determinant() const;
  // The map that applies *this first and then `next`.
  Affine then(const Affine& next) const;
  // Nullopt when the matrix is singular (or nearly so relative to its scale).
  std::optional<Affine> inverse() const;
  bool isIdentity() const;
  bool operator==(const Affine&) const = default;

  static Affine scale(const Vec3& s);
  static Affine translate(const Vec3& d);
  static Affine rotate(const Vec3& degrees);
  // POV-Ray's matrix <a,b,c, d,e,f, g,h,i, j,k,l> in row-vector form:
  // x' = x*a + y*d + z*g + j, and so on.
  static Affine povMatrix(const std::array<double, 12>& v);
};

// A forward map with its precomputed inverse.
struct Transform {
  Affine toWorld;
  Affine toObject;

  static std::optional<Transform> from(const Affine& a) {
    auto inv = a.inverse();
    if (!inv) return std::nullopt;
    return Transform{a, *inv};
  }
  // Made unit as POV-Ray's VNormalize does, times 1 / length (its shapes all carry their
  // normals out this way, MTransNormal then VNormalize).
  Vec3 normalToWorld(const Vec3& n) const {
    const Vec3 w = toObject.applyTransposed(n);
    return w * (1.0 / length(w));
  }
};

// A transform held by pointer: a Primitive carries one only when its shape is not in world
// space, and 192 bytes inline in every one would double the memory of a million spheres.
using SharedTransform = std::shared_ptr<const Transform>;
inline SharedTransform share(const std::optional<Transform>& t) {
  return t ? std::make_shared<const Transform>(*t) : nullptr;
}

}  // namespace pvrt
