// The camera rays of a rectangle of pixels that all take the same sub-pixel offsets (the
// pov and grid samplers). Camera::ray divides twice per ray, for the image-plane
// coordinates u and v; u depends only on the column and the offset, v only on the row and
// the offset, so here they are made once per column of the rectangle and once per row,
// and the rays four at a time from them (Camera::raysAt): the same bits as Camera::ray.
#pragma once

#include <algorithm>
#include <vector>

#include "render/camera.h"

namespace pvrt {

class CameraGrid {
 public:
  // Every pixel's offsets; the rectangle's columns [x0, x1) of a width x height image.
  CameraGrid(const Camera& camera, const std::vector<SubSample>& offsets, int x0, int x1, int width, int height)
      : camera_(camera), offsets_(offsets), n_(int(offsets.size())), x0_(x0), height_(height) {
    u_.resize(size_t(x1 - x0) * size_t(n_));
    for (int x = x0; x < x1; ++x)
      for (int k = 0; k < n_; ++k) u_[size_t(x - x0) * size_t(n_) + size_t(k)] = Camera::planeU(x, offsets_[size_t(k)].dx, width);
    v_.resize(size_t(n_) * kMaxPixels);
  }

  // The row whose rays come next.
  void setRow(int y) {
    for (int k = 0; k < n_; ++k) v_[size_t(k)] = Camera::planeV(y, offsets_[size_t(k)].dy, height_);
    for (size_t i = 1; i < kMaxPixels; ++i) std::copy_n(v_.begin(), n_, v_.begin() + ptrdiff_t(i) * n_);
  }

  // Ray k of pixel x of the row.
  Ray ray(int x, int k) const { return camera_.rayAt(u_[size_t(x - x0_) * size_t(n_) + size_t(k)], v_[size_t(k)]); }

  // Every ray of the pixels x .. x + pixels - 1 of the row (at most kMaxPixels), pixel
  // after pixel, into out. The coordinates are read where they lie, stored well before:
  // copied into a buffer just before, their vector loads waited on the copies' stores.
  void rays(int x, int pixels, Ray* out) const {
    camera_.raysAt(u_.data() + size_t(x - x0_) * size_t(n_), v_.data(), pixels * n_, out);
  }
  // Rays [from, from + count) of pixel x of the row.
  void rays(int x, int from, int count, Ray* out) const {
    camera_.raysAt(u_.data() + size_t(x - x0_) * size_t(n_) + size_t(from), v_.data() + from, count, out);
  }

  static constexpr size_t kMaxPixels = 8;  // the most pixels one call of rays() may take

 private:
  const Camera& camera_;
  std::vector<SubSample> offsets_;
  int n_, x0_, height_;
  // u of column x0 + i, offset k at i * n + k; v of offset k in the row at k, repeated
  // for kMaxPixels pixels (so that v_[i * n + k] lines up with u's pixel i).
  std::vector<double> u_, v_;
};

}  // namespace pvrt
