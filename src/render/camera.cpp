#include "render/camera.h"

#include <cmath>
#include <numbers>

namespace pvrt {

namespace {
constexpr double kCameraEpsilon = 1e-10;  // POV-Ray's EPSILON in its look_at code
}  // namespace

Camera::Camera(const CameraDesc& desc) {
  // POV-Ray applies the modifiers in a fixed order: right, direction, angle, up, sky,
  // location, look_at, then the camera's transforms.
  Vec3 right = desc.right, direction = desc.direction, up = desc.up;
  if (desc.angle) {
    const double half = *desc.angle * std::numbers::pi / 360.0;
    direction = normalize(direction) * (length(right) / (2.0 * std::tan(half)));
  }
  Vec3 location = desc.location;
  if (desc.lookAt) {
    const double ld = length(direction), lu = length(up), lr = length(right);
    const double handed = dot(cross(up, direction), right) > 0 ? 1.0 : -1.0;
    const Vec3 d = normalize(*desc.lookAt - location);
    Vec3 r = cross(desc.sky, d);
    // Sky parallel to the view (looking straight down): POV-Ray keeps the old right
    // vector but still turns direction and up towards look_at.
    if (std::fabs(r.x) < kCameraEpsilon && std::fabs(r.y) < kCameraEpsilon && std::fabs(r.z) < kCameraEpsilon)
      r = right;
    r = normalize(r);
    direction = d * ld;
    up = cross(d, r) * lu;
    right = r * (handed * lr);
  }
  const Affine t = desc.transforms.combined();
  location_ = t.applyPoint(location);
  direction_ = t.applyVector(direction);
  right_ = t.applyVector(right);
  up_ = t.applyVector(up);
}

Ray Camera::ray(int x, int y, double dx, double dy, int width, int height) const {
  const double u = (x + 0.5 + dx) / width - 0.5;
  const double v = 0.5 - (y + 0.5 + dy) / height;
  return {location_, normalize(direction_ + right_ * u + up_ * v)};
}

}  // namespace pvrt
