// A linear-light float RGB image (row 0 at the top), the renderer's film.
#pragma once

#include <cstddef>
#include <memory>
#include <new>
#include <utility>
#include <vector>

#include "core/color.h"

namespace pvrt {

// Allocates like std::allocator but leaves new elements of trivial types uninitialised
// (resize and the sized constructor without a value do not write them).
template <class T>
struct UninitialisedAllocator : std::allocator<T> {
  template <class U>
  struct rebind {
    using other = UninitialisedAllocator<U>;
  };
  UninitialisedAllocator() = default;
  template <class U>
  UninitialisedAllocator(const UninitialisedAllocator<U>&) {}
  template <class U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

class Image {
 public:
  using Pixels = std::vector<float, UninitialisedAllocator<float>>;

  Image() = default;
  Image(int width, int height) : w_(width), h_(height), px_(size_t(width) * height * 3, 0.0f) {}
  // A film whose pixels are left unset, for renderers whose work items cover every pixel
  // (or that read back only those they wrote): each page is first touched by the thread
  // that renders into it, instead of being zeroed beforehand by one thread (12 MB at
  // 1280x800, a serial stage inside the render's time).
  static Image unfilled(int width, int height) {
    Image image;
    image.w_ = width;
    image.h_ = height;
    image.px_.resize(size_t(width) * height * 3);
    return image;
  }

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
  const Pixels& data() const { return px_; }
  Pixels& data() { return px_; }

 private:
  int w_ = 0, h_ = 0;
  Pixels px_;
};

}  // namespace pvrt
