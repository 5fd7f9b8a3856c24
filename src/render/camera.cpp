#include "render/camera.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/lanes.h"

namespace pvrt {

namespace {
constexpr double kCameraEpsilon = 1e-10;  // POV-Ray's EPSILON in its look_at code
constexpr double kPi360 = 0.00872664625997164788;  // POV-Ray's M_PI_360 (configbase.h)

// POV-Ray's VNormalize: times the reciprocal of the length, which rounds differently
// from a division (the last bit decides a checker cell seen edge-on).
Vec3 povNormalize(const Vec3& a) {
  // Rescaled first by a power of two (core/vec3.h): the same bits where the plain product
  // neither underflows nor overflows, and a unit vector where it would.
  const Vec3 s = rescaled(a);
  return s * (1.0 / length(s));
}
}  // namespace

Camera::Camera(const CameraDesc& desc) {
  // POV-Ray applies the modifiers in a fixed order: right, direction, angle, up, sky,
  // location, look_at, then the camera's transforms.
  Vec3 right = desc.right, direction = desc.direction, up = desc.up;
  if (desc.angle) {
    // Parse_Camera: Right_Length / tan(Angle * M_PI_360) / 2.0, in that order.
    direction = povNormalize(direction) * (length(right) / std::tan(*desc.angle * kPi360) / 2.0);
  }
  Vec3 location = desc.location;
  if (desc.lookAt) {
    const double ld = length(direction), lu = length(up), lr = length(right);
    const double handed = dot(cross(up, direction), right) > 0 ? 1.0 : -1.0;
    const Vec3 d = povNormalize(*desc.lookAt - location);
    Vec3 r = cross(desc.sky, d);
    // Sky parallel to the view (looking straight down): POV-Ray keeps the old right
    // vector but still turns direction and up towards look_at.
    if (std::fabs(r.x) < kCameraEpsilon && std::fabs(r.y) < kCameraEpsilon && std::fabs(r.z) < kCameraEpsilon)
      r = right;
    r = povNormalize(r);
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

// POV-Ray's TracePixel::CreateCameraRay, operation for operation: the sample's position
// is (x + dx, y + dy) in pixels, moved to the pixel centre by x + 0.5 and y - 0.5, and
// the row counted from the bottom as ((height - 1) - y) / height.
Ray Camera::ray(int x, int y, double dx, double dy, int width, int height) const {
  return rayAt(planeU(x, dx, width), planeV(y, dy, height));
}

Ray Camera::rayAt(double u, double v) const {
  const Vec3 d = direction_ + right_ * u + up_ * v;
  return {location_, d * (1.0 / length(d))};
}

void Camera::rays(int x, int y, const SubSample* offsets, int count, int width, int height, Ray* out) const {
  using namespace lanes;
  int k = 0;
  // Lane by lane the operations of ray(), in its order.
  const Double4 cx = splat(double(x)), cy = splat(double(y)), w = splat(width), h = splat(height), half = splat(0.5);
  const Double4 bottom = splat(double(height - 1)), one = splat(1.0);
  for (; k + 4 <= count; k += 4) {
    const SubSample* s = offsets + k;
    const Double4 u = ((cx + set(s[0].dx, s[1].dx, s[2].dx, s[3].dx)) + half) / w - half;
    const Double4 v = (bottom - ((cy + set(s[0].dy, s[1].dy, s[2].dy, s[3].dy)) - half)) / h - half;
    Double4 d[3];
    for (int a = 0; a < 3; ++a) d[a] = splat(direction_[a]) + splat(right_[a]) * u + splat(up_[a]) * v;
    const Double4 inv = one / lanes::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    double dir[3][4];
    for (int a = 0; a < 3; ++a) store(dir[a], d[a] * inv);
    for (int i = 0; i < 4; ++i) out[k + i] = {location_, {dir[0][i], dir[1][i], dir[2][i]}};
  }
  for (; k < count; ++k) out[k] = ray(x, y, offsets[k].dx, offsets[k].dy, width, height);
}

void Camera::raysAt(const double* u, const double* v, int count, Ray* out) const {
  using namespace lanes;
  const Double4 one = splat(1.0);
  // Lane by lane rayAt()'s operations, in its order; the last one to three rays go as a
  // group of four padded with copies of the last, so no ray takes the scalar path's
  // serial square root and division.
  for (int k = 0; k < count; k += 4) {
    const int live = std::min(4, count - k);
    Double4 lu, lv;
    if (live == 4) {
      lu = load(u + k), lv = load(v + k);
    } else {
      const int last = k + live - 1;
      lu = set(u[k], u[std::min(k + 1, last)], u[std::min(k + 2, last)], u[last]);
      lv = set(v[k], v[std::min(k + 1, last)], v[std::min(k + 2, last)], v[last]);
    }
    Double4 d[3];
    for (int a = 0; a < 3; ++a) d[a] = splat(direction_[a]) + splat(right_[a]) * lu + splat(up_[a]) * lv;
    const Double4 inv = one / lanes::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    double dir[3][4];
    for (int a = 0; a < 3; ++a) store(dir[a], d[a] * inv);
    for (int i = 0; i < live; ++i) out[k + i] = {location_, {dir[0][i], dir[1][i], dir[2][i]}};
  }
}

}  // namespace pvrt
