// Binned SAH build (centroids sorted into bins per axis, the cheapest split kept) and
// an iterative, front-to-back closest-hit traversal over the flattened tree.
#include "accel/bvh.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>

namespace pvrt {

namespace {

constexpr uint32_t kNone = ~0u;
constexpr int kBins = 16;
constexpr int kMaxLeafSize = 4;
constexpr int kMaxSahDepth = 48;  // beyond it, median splits bound the depth (stack of 64)
constexpr double kTraversalCost = 1.0;    // relative to one primitive test
constexpr double kIntersectionCost = 1.0;

struct BuildItem {
  Bounds bounds;
  Vec3 centroid;
  uint32_t index;
};

class Builder {
 public:
  Builder(std::vector<BuildItem>& items, std::vector<BvhNode>& nodes, BvhStats& stats)
      : items_(items), nodes_(nodes), stats_(stats) {}

  void build(uint32_t begin, uint32_t end, int depth) {
    stats_.maxDepth = std::max(stats_.maxDepth, depth);
    const uint32_t self = uint32_t(nodes_.size());
    nodes_.emplace_back();
    Bounds bounds, centroids;
    for (uint32_t i = begin; i < end; ++i) {
      bounds.extend(items_[i].bounds);
      centroids.extend(items_[i].centroid);
    }
    nodes_[self].setBounds(bounds);
    const uint32_t count = end - begin;
    uint32_t mid = count <= 1 ? end
                 : depth < kMaxSahDepth ? split(begin, end, bounds, centroids)
                                        : median(begin, end, centroids);
    if (mid == end) {  // a leaf
      nodes_[self].rightOrFirst = begin;
      nodes_[self].count = uint16_t(count);
      ++stats_.leaves;
      return;
    }
    nodes_[self].axis = uint8_t(splitAxis_);
    build(begin, mid, depth + 1);
    nodes_[self].rightOrFirst = uint32_t(nodes_.size());
    build(mid, end, depth + 1);
  }

 private:
  uint32_t median(uint32_t begin, uint32_t end, const Bounds& centroids) {
    if (end - begin <= kMaxLeafSize) return end;
    splitAxis_ = centroids.longestAxis();
    const uint32_t mid = begin + (end - begin) / 2;
    std::nth_element(items_.begin() + begin, items_.begin() + mid, items_.begin() + end,
                     [&](const BuildItem& a, const BuildItem& b) {
                       return a.centroid[splitAxis_] < b.centroid[splitAxis_];
                     });
    return mid;
  }

  // Partitions [begin, end) and returns the split point, or `end` to make a leaf.
  uint32_t split(uint32_t begin, uint32_t end, const Bounds& bounds, const Bounds& centroids) {
    const uint32_t count = end - begin;
    const double leafCost = kIntersectionCost * count;
    double bestCost = INFINITY;
    int bestAxis = -1, bestBin = 0;
    for (int axis = 0; axis < 3; ++axis) {
      const double lo = centroids.lo[axis], extent = centroids.hi[axis] - lo;
      if (!(extent > 0)) continue;
      std::array<Bounds, kBins> binBounds;
      std::array<uint32_t, kBins> binCount{};
      const double scale = kBins / extent;
      for (uint32_t i = begin; i < end; ++i) {
        const int b = std::min(kBins - 1, int((items_[i].centroid[axis] - lo) * scale));
        binBounds[size_t(b)].extend(items_[i].bounds);
        ++binCount[size_t(b)];
      }
      // Sweep from the right to get the cost of every right side, then from the left.
      std::array<double, kBins> rightArea{};
      std::array<uint32_t, kBins> rightCount{};
      Bounds acc;
      uint32_t n = 0;
      for (int b = kBins - 1; b > 0; --b) {
        acc.extend(binBounds[size_t(b)]);
        n += binCount[size_t(b)];
        rightArea[size_t(b)] = acc.surfaceArea();
        rightCount[size_t(b)] = n;
      }
      acc = Bounds{};
      n = 0;
      for (int b = 0; b < kBins - 1; ++b) {
        acc.extend(binBounds[size_t(b)]);
        n += binCount[size_t(b)];
        const uint32_t right = rightCount[size_t(b + 1)];
        if (n == 0 || right == 0) continue;
        const double cost = acc.surfaceArea() * n + rightArea[size_t(b + 1)] * right;
        if (cost < bestCost) {
          bestCost = cost;
          bestAxis = axis;
          bestBin = b;
        }
      }
    }
    const double area = bounds.surfaceArea();
    const double splitCost = kTraversalCost + (area > 0 ? kIntersectionCost * bestCost / area : INFINITY);
    if (bestAxis < 0) {
      // All centroids coincide: split in the middle if the leaf would be too big.
      if (count <= kMaxLeafSize) return end;
      splitAxis_ = bounds.longestAxis();
      return begin + count / 2;
    }
    if (count <= kMaxLeafSize && splitCost >= leafCost) return end;
    const double lo = centroids.lo[bestAxis];
    const double scale = kBins / (centroids.hi[bestAxis] - lo);
    auto middle = std::partition(items_.begin() + begin, items_.begin() + end, [&](const BuildItem& it) {
      return std::min(kBins - 1, int((it.centroid[bestAxis] - lo) * scale)) <= bestBin;
    });
    splitAxis_ = bestAxis;
    const uint32_t mid = uint32_t(middle - items_.begin());
    if (mid == begin || mid == end) return begin + count / 2;
    return mid;
  }

  std::vector<BuildItem>& items_;
  std::vector<BvhNode>& nodes_;
  BvhStats& stats_;
  int splitAxis_ = 0;
};

// Slab test: does the ray enter the box before `tMax` (and leave it after `tMin`)?
inline bool hitsBox(const Bounds& b, const Vec3& origin, const Vec3& inv, double tMin, double tMax) {
  for (int a = 0; a < 3; ++a) {
    double t0 = (b.lo[a] - origin[a]) * inv[a];
    double t1 = (b.hi[a] - origin[a]) * inv[a];
    if (t0 > t1) std::swap(t0, t1);
    // NaN (0 * inf on a slab boundary) must not reject: a comparison with NaN is false,
    // so the bound is kept. (Written out because std::fmin/fmax are library calls.)
    tMin = t0 > tMin ? t0 : tMin;
    t1 *= 1 + 4e-16;  // a few ulps of slack so boundary hits are kept
    tMax = t1 < tMax ? t1 : tMax;
    if (tMin > tMax) return false;
  }
  return true;
}

}  // namespace

namespace {
// The nearest float at or below / above v (NaN stays NaN, which every box test treats as
// "may hit"; beyond the float range the bound becomes infinite, still conservative).
float floatDown(double v) {
  float f = float(v);
  if (double(f) > v) f = std::nextafter(f, -INFINITY);
  return f;
}
float floatUp(double v) {
  float f = float(v);
  if (double(f) < v) f = std::nextafter(f, INFINITY);
  return f;
}
}  // namespace

void BvhNode::setBounds(const Bounds& b) {
  for (int a = 0; a < 3; ++a) {
    lo[a] = floatDown(b.lo[a]);
    hi[a] = floatUp(b.hi[a]);
  }
}

Bvh::Bvh(std::vector<Primitive> primitives) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<BuildItem> items;
  std::vector<Primitive> unbounded;
  items.reserve(primitives.size());
  for (uint32_t i = 0; i < primitives.size(); ++i) {
    const Bounds b = primitives[i].bounds();
    if (b.empty()) continue;
    items.push_back({b, b.centroid(), i});
  }
  if (!items.empty()) {
    nodes_.reserve(2 * items.size());
    Builder(items, nodes_, stats_).build(0, uint32_t(items.size()), 1);
  }
  prims_.reserve(primitives.size());
  std::vector<bool> placed(primitives.size(), false);
  for (const BuildItem& it : items) {
    prims_.push_back(std::move(primitives[it.index]));
    placed[it.index] = true;
  }
  boundedCount_ = uint32_t(prims_.size());
  for (size_t i = 0; i < primitives.size(); ++i)
    if (!placed[i]) prims_.push_back(std::move(primitives[i]));
  items_.reserve(prims_.size());
  for (const Primitive& p : prims_) {
    LeafItem it;
    const SphereShape* sphere = p.transform ? nullptr : std::get_if<SphereShape>(&p.shape);
    if (sphere) it.sphere = *sphere;
    it.isSphere = sphere != nullptr;
    it.unit = p.unit;
    it.noShadow = p.noShadow;
    it.opaque = p.opaque;
    items_.push_back(it);
  }
  stats_.nodes = nodes_.size();
  stats_.bytes = nodes_.size() * sizeof(BvhNode) + prims_.size() * (sizeof(Primitive) + sizeof(LeafItem));
  stats_.buildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Visits the leaves whose boxes the ray enters before `tMax` (which the visitor may
// shrink), nearer child first; `leaf(i)` returning true ends the walk. Then the
// unbounded primitives. Shared by the closest-hit and the occlusion queries.
template <class Visit>
void Bvh::traverse(const Ray& ray, double tMin, const double& tMax, Visit&& visit) const {
  if (!nodes_.empty()) {
    const Vec3 inv{1.0 / ray.dir.x, 1.0 / ray.dir.y, 1.0 / ray.dir.z};
    const bool negative[3] = {ray.dir.x < 0, ray.dir.y < 0, ray.dir.z < 0};
    uint32_t stack[64];
    int top = 0;
    uint32_t node = 0;
    for (;;) {
      const BvhNode& n = nodes_[node];
      if (hitsBox(n.bounds(), ray.origin, inv, tMin, tMax)) {
        if (n.count == 0) {
          // Visit the child on the ray's near side first so that far boxes are culled.
          const uint32_t left = node + 1, right = n.rightOrFirst;
          stack[top++] = negative[n.axis] ? left : right;
          node = negative[n.axis] ? right : left;
          continue;
        }
        for (uint32_t i = n.rightOrFirst; i < n.rightOrFirst + n.count; ++i)
          if (visit(i)) return;
      }
      if (top == 0) break;
      node = stack[--top];
    }
  }
  for (uint32_t i = boundedCount_; i < prims_.size(); ++i)
    if (visit(i)) return;
}

Occlusion Bvh::occlusion(const Ray& ray, double tMin, double tMax, uint64_t& tests, uint32_t& blocker) const {
  bool transparent = false, blocked = false;
  traverse(ray, tMin, tMax, [&](uint32_t i) {
    const LeafItem& p = items_[i];
    if (p.noShadow) return false;
    ++tests;
    if (!intersectItem(i, ray, tMin, tMax)) return false;
    if (!p.opaque) {
      transparent = true;
      return false;
    }
    blocker = i;
    return blocked = true;
  });
  return blocked ? Occlusion::Blocked : transparent ? Occlusion::Transparent : Occlusion::Clear;
}

std::optional<ClosestHit> Bvh::closest(const Ray& ray, double tMin, double tMax, uint64_t& tests,
                                       bool skipNoShadow) const {
  std::optional<ClosestHit> best;
  double bestT = tMax;
  traverse(ray, tMin, bestT, [&](uint32_t i) {
    if (skipNoShadow && items_[i].noShadow) return false;
    ++tests;
    if (auto h = intersectItem(i, ray, tMin, bestT)) {
      bestT = h->t;
      best = ClosestHit{*h, i};
    }
    return false;
  });
  return best;
}

// The packet version of traverse(): visits the leaves that at least one ray of the packet
// enters, nearer child first along the split axis when the packet's directions agree on
// it. A box is first tested against the whole cone (cheap, and enough for a coherent
// packet); one the cone may reach is then kept only if `enters(box)` finds a ray that
// really enters it, so an incoherent packet never walks more of the tree than its rays
// would one by one. `leaf(first, count, box)` returning true ends the walk.
template <class Enters, class Leaf>
void Bvh::traversePacket(const PacketCone& cone, const double& sHi, Enters&& enters, Leaf&& leaf) const {
  if (nodes_.empty()) return;
  uint32_t stack[64];
  int top = 0;
  uint32_t node = 0;
  for (;;) {
    const BvhNode& n = nodes_[node];
    const Bounds box = n.bounds();
    if (cone.mayHit(box, sHi) && enters(box)) {
      if (n.count == 0) {
        const uint32_t left = node + 1, right = n.rightOrFirst;
        const bool rightFirst = cone.sign(n.axis) < 0;
        stack[top++] = rightFirst ? left : right;
        node = rightFirst ? right : left;
        continue;
      }
      if (leaf(n.rightOrFirst, n.count, box)) return;
    }
    if (top == 0) return;
    node = stack[--top];
  }
}

void Bvh::closestPacket(const Ray* rays, int count, double tMin, double tMax, std::optional<ClosestHit>* out,
                        uint64_t& tests) const {
  double best[kMaxPacket];
  ShapeHit hits[kMaxPacket];
  int which[kMaxPacket];
  uint32_t owner[kMaxPacket];
  Vec3 inv[kMaxPacket];
  for (int k = 0; k < count; ++k) {
    best[k] = tMax;
    owner[k] = kNone;
    inv[k] = {1.0 / rays[k].dir.x, 1.0 / rays[k].dir.y, 1.0 / rays[k].dir.z};
  }
  // Unit directions from a common origin: the ray parameter t is the cone's s.
  const PacketCone cone(rays[0].origin, [&](int k) { return rays[k].dir; }, count, tMin);
  double farthest = tMax;  // the largest best[k]: beyond it no ray needs anything
  // Tests the rays which[0..n) against primitive i.
  auto intersect = [&](uint32_t i, int n) {
    tests += uint64_t(n);
    for (int j = 0; j < n; ++j) {
      const int k = which[j];
      if (const auto h = intersectItem(i, rays[k], tMin, best[k])) {
        best[k] = h->t;
        hits[k] = *h;
        owner[k] = i;
      }
    }
  };
  auto enters = [&](const Bounds& box) {
    for (int k = 0; k < count; ++k)
      if (hitsBox(box, rays[k].origin, inv[k], tMin, best[k])) return true;
    return false;
  };
  traversePacket(cone, farthest, enters, [&](uint32_t first, uint32_t n, const Bounds& box) {
    // Only the rays that enter the leaf's box (for a leaf of one primitive the box test
    // would cost about what the primitive's own test does: all of them).
    int m = 0;
    for (int k = 0; k < count; ++k)
      if (n == 1 || hitsBox(box, rays[k].origin, inv[k], tMin, best[k])) which[m++] = k;
    for (uint32_t i = first; i < first + n; ++i) intersect(i, m);
    farthest = *std::max_element(best, best + count);
    return false;
  });
  for (int k = 0; k < count; ++k) which[k] = k;
  for (uint32_t i = boundedCount_; i < prims_.size(); ++i) intersect(i, count);
  for (int k = 0; k < count; ++k) {
    if (owner[k] == kNone) out[k].reset();
    else out[k] = ClosestHit{hits[k], owner[k]};
  }
}

namespace {

// Can the plane lie between the apex and any segment start? Not when all of them are on
// one side of it with a margin far above rounding (then every segment's parameter at the
// plane falls outside the segment, as the exact test would find).
bool planeSeparates(const Primitive& p, const Vec3& apex, const Ray* segments, const int* live, int n) {
  const PlaneShape* plane = p.transform ? nullptr : std::get_if<PlaneShape>(&p.shape);
  if (!plane) return false;
  auto side = [&](const Vec3& x) {
    const double a = dot(plane->normal, x), margin = 1e-9 * (std::fabs(a) + std::fabs(plane->distance));
    const double d = a - plane->distance;
    return d > margin ? 1 : d < -margin ? -1 : 0;
  };
  const int s = side(apex);
  if (s == 0) return false;
  for (int i = 0; i < n; ++i)
    if (side(segments[live[i]].origin) != s) return false;
  return true;
}

}  // namespace

void Bvh::occlusionPacket(const Vec3& apex, const Ray* segments, const double* tMax, int count, double tMin,
                          Occlusion* out, uint32_t* blocker, uint64_t& tests) const {
  int live[kMaxPacket], inBox[kMaxPacket];
  Vec3 inv[kMaxPacket];
  int n = count;
  for (int k = 0; k < count; ++k) {
    out[k] = Occlusion::Clear;
    live[k] = k;
    inv[k] = {1.0 / segments[k].dir.x, 1.0 / segments[k].dir.y, 1.0 / segments[k].dir.z};
  }
  // The cone runs from the light back to each segment's start: s in [0, 1].
  const PacketCone cone(apex, [&](int k) { return segments[k].origin - apex; }, count, 0.0);
  const double sHi = 1.0;
  // Tests the segments rays[0..m) against primitive i; an opaque hit retires the
  // segment (from `live`, which is compacted once the leaf is done).
  auto test = [&](uint32_t i, const int* rays, int m) {
    const LeafItem& p = items_[i];
    if (p.noShadow) return;
    tests += uint64_t(m);
    for (int j = 0; j < m; ++j) {
      const int k = rays[j];
      if (out[k] == Occlusion::Blocked || !intersectItem(i, segments[k], tMin, tMax[k])) continue;
      if (p.opaque) {
        out[k] = Occlusion::Blocked;
        blocker[k] = i;
      } else {
        out[k] = Occlusion::Transparent;
      }
    }
  };
  auto compact = [&] {
    int kept = 0;
    for (int j = 0; j < n; ++j)
      if (out[live[j]] != Occlusion::Blocked) live[kept++] = live[j];
    n = kept;
  };
  auto enters = [&](const Bounds& box) {
    for (int j = 0; j < n; ++j)
      if (hitsBox(box, segments[live[j]].origin, inv[live[j]], tMin, tMax[live[j]])) return true;
    return false;
  };
  traversePacket(cone, sHi, enters, [&](uint32_t first, uint32_t count, const Bounds& box) {
    int m = 0;
    for (int j = 0; j < n; ++j)
      if (count == 1 || hitsBox(box, segments[live[j]].origin, inv[live[j]], tMin, tMax[live[j]]))
        inBox[m++] = live[j];
    for (uint32_t i = first; i < first + count; ++i) test(i, inBox, m);
    compact();
    return n == 0;
  });
  for (uint32_t i = boundedCount_; i < prims_.size() && n > 0; ++i) {
    if (planeSeparates(prims_[i], apex, segments, live, n)) continue;
    test(i, live, n);
    compact();
  }
}

}  // namespace pvrt
