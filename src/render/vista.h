// Which camera rays surely meet nothing: the pixels of the image that no box of the tree
// and no plane can reach, found from the camera's projection of the boxes (after POV-Ray
// 3.6's vista buffer). The kernel gives those pixels the background without making their
// rays or walking the tree; in a scene that is mostly sky that is most of the render.
//
// The answer is conservative and a function of the pixel alone (not of the work item it
// lies in), so that every schedule skips the same rays and counts the same work: a pixel is
// clear when its samples' screen positions lie more than kVistaMargin pixels from every
// projected box that the walk below stops at, and every plane lies behind all of its rays.
// A ray that hits a primitive passes through the primitive's box, so no hit is lost; what
// the skipped rays would have counted (their plane tests, and the tests of any leaf their
// float box tests would have entered) is not counted.
#pragma once

#include <cstdint>
#include <vector>

#include "core/vec3.h"
#include "parallel/schedule.h"
#include "render/sampler.h"

namespace pvrt {

class Bvh;
class Camera;

// How far, in pixels, a pixel's samples must stay from a box's projection to be clear:
// far above the rounding of the rays (Camera::rayAt) and of the projection itself (about
// 1e-16 relative). A hit lies inside its primitive's box, so only the exact ray matters,
// not the tree's float box test (which may enter a box a ray misses by 2^-18 of its length).
inline constexpr double kVistaMargin = 2.0;

// What the scene allows, found once when the scene is built.
class Vista {
 public:
  Vista() = default;
  // Usable when no bounded primitive's box lies across the camera's plane (each is wholly in
  // front, where its projection is bounded, or wholly behind, where no camera ray goes),
  // every unbounded primitive is a plane the camera is not on, and the camera's three
  // vectors span space.
  Vista(const Camera& camera, const Bvh& bvh);
  bool usable() const { return usable_; }

  const Vec3& eye() const { return eye_; }
  // Rows of the inverse of [direction right up]: p - eye = t (direction + u right + v up)
  // for t = row[0].(p - eye), u = row[1].(p - eye) / t, v = row[2].(p - eye) / t.
  const Vec3& row(int i) const { return inverse_[i]; }
  // n.direction, n.right and n.up of each plane, with which side of it the camera is on.
  struct PlaneView {
    double g0, gu, gv;  // n.(direction + u right + v up) = g0 + u gu + v gv
    double side;        // +1: the camera is on the side the normal leaves from, -1 the other
  };
  const std::vector<PlaneView>& planes() const { return planes_; }

 private:
  bool usable_ = false;
  Vec3 eye_;
  Vec3 inverse_[3];
  std::vector<PlaneView> planes_;
};

// The clear pixels of one work item.
class VistaMask {
 public:
  // For the pixels of `rect` of a width x height image whose samples take `offsets` (the
  // same for every pixel); nothing is clear when the vista is not usable.
  VistaMask(const Vista& vista, const Bvh& bvh, const WorkItem& rect, int width, int height,
            const std::vector<SubSample>& offsets);
  // Whether any pixel is clear: when not, clear() is false everywhere.
  bool any() const { return any_; }
  // Every camera ray of pixel (x, y) of the work item meets no box of the tree and no plane.
  bool clear(int x, int y) const {
    const int cx = x - rect_.x0, cy = y - rect_.y0;
    return any_ && (bits_[size_t(cy) * words_ + size_t(cx >> 6)] >> (cx & 63) & 1u) == 0;
  }

 private:
  void mark(int x0, int x1, int y0, int y1);  // may hit: columns [x0, x1), rows [y0, y1)
  bool full() const { return marked_ == uint64_t(rect_.pixels()); }

  WorkItem rect_;
  size_t words_ = 0;
  std::vector<uint64_t> bits_;  // a bit set per pixel that may hit something
  uint64_t marked_ = 0;
  bool any_ = false;
};

}  // namespace pvrt
