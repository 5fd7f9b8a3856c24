#include "render/vista.h"

#include <algorithm>
#include <bit>
#include <cmath>

#include "accel/bvh.h"
#include "render/camera.h"

namespace pvrt {

namespace {

// A box whose projection covers at most this many pixels is marked whole rather than
// walked into: it bounds the walk's cost by the work item's area, not the scene's size.
constexpr double kStopArea = 16;

// A point is clearly in front of the camera when its t is above this share of |row 0| |q|
// (an angle of about 1e-6 radians off the camera's plane): far above rounding, so that
// every point of a box found in front is in front.
constexpr double kInFront = 1e-6;

double absDot(const Vec3& a, const Vec3& b) {
  return std::fabs(a.x) * std::fabs(b.x) + std::fabs(a.y) * std::fabs(b.y) + std::fabs(a.z) * std::fabs(b.z);
}

// Where a box (its centre and half-extents from the eye) lies from the camera's plane, by
// the least and the most t of its points (t is linear, so they are at corners). A camera
// ray's points all have t > 0 (row 0 times direction + u right + v up is 1), so a box
// wholly behind can never be met.
enum class Side { Front, Behind, Across };
Side sideOf(const Vec3& row0, const Vec3& centre, const Vec3& half, double& tLo, double& tHi) {
  const double tc = dot(row0, centre), te = absDot(row0, half);
  tLo = tc - te, tHi = tc + te;
  const double clearly = kInFront * length(row0) * (length(centre) + length(half));
  return tLo > clearly ? Side::Front : tHi < -clearly ? Side::Behind : Side::Across;
}

}  // namespace

Vista::Vista(const Camera& camera, const Bvh& bvh) {
  eye_ = camera.location();
  const Vec3& d = camera.direction();
  const Vec3& r = camera.right();
  const Vec3& u = camera.up();
  const double det = dot(d, cross(r, u));
  if (!(std::fabs(det) > 1e-9 * length(d) * length(r) * length(u))) return;
  inverse_[0] = cross(r, u) * (1.0 / det);
  inverse_[1] = cross(u, d) * (1.0 / det);
  inverse_[2] = cross(d, r) * (1.0 / det);
  for (uint32_t i = bvh.boundedCount(); i < bvh.size(); ++i) {
    const PlaneShape* p = bvh.plane(i);
    if (!p) return;  // an unbounded shape other than a plane
    const double n = dot(p->normal, eye_), s = p->distance - n;
    if (!(std::fabs(s) > 1e-9 * (std::fabs(p->distance) + std::fabs(n)))) return;  // the camera is on it
    planes_.push_back({dot(p->normal, d), dot(p->normal, r), dot(p->normal, u), s > 0 ? 1.0 : -1.0});
  }
  // No leaf's box across the camera's plane: a node wholly in front or behind needs no
  // look inside; one across it is looked into, down to the leaves.
  const std::vector<BvhNode>& nodes = bvh.nodes();
  if (nodes.empty()) {
    usable_ = bvh.boundedCount() == 0;
    return;
  }
  std::vector<uint32_t> stack{0};
  while (!stack.empty()) {
    const BvhNode& n = nodes[stack.back()];
    stack.pop_back();
    for (int c = 0; c < n.used; ++c) {
      const Bounds b = n.childBounds(c);
      if (b.empty()) continue;
      const Vec3 centre = (b.lo + b.hi) * 0.5 - eye_, half = (b.hi - b.lo) * 0.5;
      double tLo, tHi;
      if (sideOf(inverse_[0], centre, half, tLo, tHi) != Side::Across) continue;
      if (n.count[c] > 0) return;  // a leaf across the camera's plane
      stack.push_back(n.child[c]);
    }
  }
  usable_ = true;
}

VistaMask::VistaMask(const Vista& vista, const Bvh& bvh, const WorkItem& rect, int width, int height,
                     const std::vector<SubSample>& offsets)
    : rect_(rect) {
  if (!vista.usable() || offsets.empty() || rect.pixels() <= 0) return;
  double dxLo = offsets[0].dx, dxHi = dxLo, dyLo = offsets[0].dy, dyHi = dyLo;
  for (const SubSample& s : offsets) {
    dxLo = std::min(dxLo, s.dx), dxHi = std::max(dxHi, s.dx);
    dyLo = std::min(dyLo, s.dy), dyHi = std::max(dyHi, s.dy);
  }
  const int rw = rect.x1 - rect.x0;
  words_ = size_t(rw + 63) / 64;
  bits_.assign(words_ * size_t(rect.y1 - rect.y0), 0);

  // The planes: a pixel may meet one unless every ray of it heads away from it. The sign of
  // n.(direction + u right + v up) is linear in (u, v), so its most the plane's way over
  // the pixel's samples is at a corner of their (u, v) rectangle.
  for (const Vista::PlaneView& p : vista.planes()) {
    const double margin = 1e-6 * (std::fabs(p.g0) + std::fabs(p.gu) + std::fabs(p.gv));
    for (int y = rect.y0; y < rect.y1 && !full(); ++y) {
      const double va = Camera::planeV(y, dyLo, height), vb = Camera::planeV(y, dyHi, height);
      const double rowMost = p.side * p.g0 + std::max(p.side * p.gv * va, p.side * p.gv * vb);
      int run = -1;  // the first column of a run of pixels that may meet it
      for (int x = rect.x0; x <= rect.x1; ++x) {
        bool meets = false;
        if (x < rect.x1) {
          const double ua = Camera::planeU(x, dxLo, width), ub = Camera::planeU(x, dxHi, width);
          meets = rowMost + std::max(p.side * p.gu * ua, p.side * p.gu * ub) >= -margin;
        }
        if (meets && run < 0) run = x;
        if (!meets && run >= 0) {
          mark(run, x, y, y + 1);
          run = -1;
        }
      }
    }
  }

  // The boxes: the tree walked within the work item, a box's projection bounded by its
  // centre's and half-extents' t, u and v (a superset of its corners' hull).
  const std::vector<BvhNode>& nodes = bvh.nodes();
  const Vec3& r0 = vista.row(0);
  const Vec3& r1 = vista.row(1);
  const Vec3& r2 = vista.row(2);
  // A node's children are in front when it is (Vista's walk tells the same nodes apart).
  struct Entry {
    uint32_t node;
    bool inFront;
  };
  std::vector<Entry> stack;
  if (!nodes.empty()) stack.push_back({0, false});
  while (!stack.empty() && !full()) {
    const Entry e = stack.back();
    stack.pop_back();
    const BvhNode& n = nodes[e.node];
    for (int c = 0; c < n.used && !full(); ++c) {
      const Bounds b = n.childBounds(c);
      if (b.empty()) continue;
      const Vec3 centre = (b.lo + b.hi) * 0.5 - vista.eye(), half = (b.hi - b.lo) * 0.5;
      double tLo, tHi;
      const Side side = sideOf(r0, centre, half, tLo, tHi);
      if (!e.inFront && side == Side::Behind) continue;
      if (!e.inFront && side == Side::Across) {
        // Across the camera's plane: an interior node is looked into; a leaf cannot be one
        // (Vista found none), but would make every pixel of the item one that may hit.
        if (n.count[c] == 0) {
          stack.push_back({n.child[c], false});
        } else {
          mark(rect.x0, rect.x1, rect.y0, rect.y1);
        }
        continue;
      }
      const double ac = dot(r1, centre), ae = absDot(r1, half), bc = dot(r2, centre), be = absDot(r2, half);
      const double uLo = std::min((ac - ae) / tLo, (ac - ae) / tHi), uHi = std::max((ac + ae) / tLo, (ac + ae) / tHi);
      const double vLo = std::min((bc - be) / tLo, (bc - be) / tHi), vHi = std::max((bc + be) / tLo, (bc + be) / tHi);
      // Screen columns grow with u, rows fall with v (Camera::planeU, planeV).
      const double xLo = (uLo + 0.5) * width - 0.5, xHi = (uHi + 0.5) * width - 0.5;
      const double yLo = 0.5 * height - 0.5 - vHi * height, yHi = 0.5 * height - 0.5 - vLo * height;
      // The pixels whose samples come within the margin, as doubles first (they may be huge).
      const double pxLo = std::ceil(xLo - kVistaMargin - dxHi), pxHi = std::floor(xHi + kVistaMargin - dxLo);
      const double pyLo = std::ceil(yLo - kVistaMargin - dyHi), pyHi = std::floor(yHi + kVistaMargin - dyLo);
      if (!(pxHi >= rect.x0 && pxLo < rect.x1 && pyHi >= rect.y0 && pyLo < rect.y1)) continue;
      const bool small = (pxHi - pxLo + 1) * (pyHi - pyLo + 1) <= kStopArea;
      if (n.count[c] > 0 || small) {
        mark(int(std::max(pxLo, double(rect.x0))), int(std::min(pxHi + 1, double(rect.x1))),
             int(std::max(pyLo, double(rect.y0))), int(std::min(pyHi + 1, double(rect.y1))));
      } else {
        stack.push_back({n.child[c], true});
      }
    }
  }
  any_ = !full();
}

void VistaMask::mark(int x0, int x1, int y0, int y1) {
  for (int y = y0; y < y1; ++y) {
    uint64_t* row = bits_.data() + size_t(y - rect_.y0) * words_;
    for (int x = x0; x < x1;) {
      const int cx = x - rect_.x0, w = cx >> 6, first = cx & 63;
      const int n = std::min(64 - first, x1 - x);
      const uint64_t bits = (n == 64 ? ~uint64_t(0) : ((uint64_t(1) << n) - 1)) << first;
      marked_ += uint64_t(std::popcount(bits & ~row[w]));
      row[w] |= bits;
      x += n;
    }
  }
}

}  // namespace pvrt
