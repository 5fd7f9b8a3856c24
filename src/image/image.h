// A linear-light float RGB image (row 0 at the top), the renderer's film.
#pragma once

#include <cstddef>
#include <vector>

#include "core/color.h"

namespace pvrt {

class Image {
 public:
  Image() = default;
  Image(int width, int height) : w_(width), h_(height), px_(size_t(width) * height * 3, 0.0f) {}

  int width() const { return w_; }
  int height() const { return h_; }
  float* row(int y) { return px_.data() + size_t(y) * w_ * 3; }
  const float* row(int y) const { return px_.data() + size_t(y) * w_ * 3; }
  void set(int x, int y, const Color& c) {
    float* p = row(y) + size_t(x) * 3;
    p[0] = float(c.r);
    p[1] = float(c.g);
    p[2] = float(c.b);
  }
  const std::vector<float>& data() const { return px_; }
  std::vector<float>& data() { return px_; }

 private:
  int w_ = 0, h_ = 0;
  std::vector<float> px_;
};

}  // namespace pvrt
