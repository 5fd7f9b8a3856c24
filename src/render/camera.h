// POV-Ray's perspective camera (shared/povray-semantics.md section 1): the image plane
// is |right| wide and |up| tall whatever the pixel counts, and rays go through pixel
// centres, rows from the top.
#pragma once

#include "core/ray.h"
#include "render/sampler.h"
#include "scene/scene_desc.h"

namespace pvrt {

class Camera {
 public:
  Camera() = default;
  explicit Camera(const CameraDesc& desc);

  // Ray through column x + dx, row y + dy (offsets in pixels from the pixel centre,
  // dy positive downward) of a width x height image. Direction is unit length.
  Ray ray(int x, int y, double dx, double dy, int width, int height) const;
  // ray() for `count` offsets of one pixel, four at a time: the same bits as calling
  // ray() for each.
  void rays(int x, int y, const SubSample* offsets, int count, int width, int height, Ray* out) const;

  // The two quotients of ray(): the image-plane coordinate u of column x + dx and v of
  // row y + dy. They depend on the column or the row alone, so a kernel whose pixels all
  // take the same offsets can make them once per column and once per row (CameraGrid).
  static double planeU(int x, double dx, int width) { return ((double(x) + dx) + 0.5) / width - 0.5; }
  static double planeV(int y, double dy, int height) {
    return (double(height - 1) - ((double(y) + dy) - 0.5)) / height - 0.5;
  }
  // The ray through plane coordinates (u, v), and rayAt() for `count` of them four at a
  // time: ray() is rayAt(planeU(..), planeV(..)), bit for bit.
  Ray rayAt(double u, double v) const;
  void raysAt(const double* u, const double* v, int count, Ray* out) const;

  const Vec3& location() const { return location_; }
  const Vec3& direction() const { return direction_; }
  const Vec3& right() const { return right_; }
  const Vec3& up() const { return up_; }

 private:
  Vec3 location_, direction_{0, 0, 1}, right_{1.33, 0, 0}, up_{0, 1, 0};
};

}  // namespace pvrt
