// POV-Ray 3.7's TRANSFORM (source/backend/math/matrices.cpp): a 4 x 4 matrix for row
// vectors (p' = p M) kept with its inverse, each composed in POV-Ray's order, for the
// shapes whose pixels depend on POV-Ray's own rounding of their transform (cylinders and
// cones, docs/fidelity.md). pvrt's Affine holds the same map but builds its inverse by
// another route, which rounds differently.
#pragma once

#include <array>

#include "core/transform.h"
#include "core/vec3.h"

namespace pvrt {

struct PovTransform {
  using Matrix = std::array<std::array<double, 4>, 4>;
  Matrix matrix;   // object -> world
  Matrix inverse;  // world -> object

  static PovTransform identity();
  static PovTransform scaling(const Vec3& s);       // Compute_Scaling_Transform
  static PovTransform translation(const Vec3& d);   // Compute_Translation_Transform
  static PovTransform rotation(const Vec3& degrees);  // Compute_Rotation_Transform: x, then y, then z
  // Compute_Axis_Rotation_Transform: `radians` about `axis` (made unit here).
  static PovTransform axisRotation(const Vec3& axis, double radians);
  // Compute_Matrix_Transform: a general affine map (`matrix <...>`), its inverse found by
  // cofactors as MInvers finds it. The map must not be singular (the loader refuses those).
  static PovTransform matrixOf(const Affine& toWorld);
  // Compute_Coordinate_Transform: the canonical shape (axis z, radius 1, height 1) scaled to
  // `radius` and `length`, turned from z onto the unit `up` and moved to `origin`.
  static PovTransform coordinate(const Vec3& origin, Vec3 up, double radius, double length);

  // Compose_Transforms: `next` applied after this one.
  void then(const PovTransform& next);
  // The same maps as pvrt's Transform. Its applyPoint, applyVector and applyTransposed sum
  // the terms in the order of POV-Ray's MTransPoint, MInvTransPoint, MInvTransDirection and
  // MTransNormal, so every use gives POV-Ray's bits.
  Transform toTransform() const;
};

}  // namespace pvrt
