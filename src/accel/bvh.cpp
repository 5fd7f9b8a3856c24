// Binned SAH build (centroids sorted into bins per axis, the cheapest split kept) of a
// binary tree, collapsed into a wide one; iterative, front-to-back traversals of it.
#include "accel/bvh.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <future>
#include <thread>

#include "accel/packet_rays.h"
#include "accel/slabs.h"
#include "core/lanes.h"
#include "parallel/threads.h"

namespace pvrt {

namespace {

constexpr uint32_t kNone = ~0u;
constexpr int kBins = 16;
constexpr int kMaxLeafSize = 4;
constexpr int kMaxSahDepth = 48;  // beyond it, median splits bound the depth (stack of 64)
constexpr uint32_t kParallelItems = 20000;  // below it, a subtree is built on the thread that got it
constexpr double kTraversalCost = 1.0;    // relative to one primitive test
constexpr double kIntersectionCost = 1.0;

// A node of the binary tree the build makes before it is collapsed.
struct BuildNode {
  Bounds bounds;
  uint32_t rightOrFirst = 0;  // interior: right child (the left one is next); leaf: first primitive
  uint32_t count = 0;         // 0 for interior nodes
};

struct BuildItem {
  Bounds bounds;
  Vec3 centroid;
  uint32_t index;
};

// Bounds.extend() a vector at a time, for the build's passes over millions of items: the
// min and max of all three axes in one operation each. A NaN in an item leaves the box as
// it was, as Bounds.extend() does, so the tree is the same. Loads four doubles from each
// Vec3 of a BuildItem (the fourth, the next field, is ignored).
struct BuildBox {
  lanes::Double4 lo = lanes::splat(INFINITY), hi = lanes::splat(-INFINITY);
  void extend(const Vec3& lo3, const Vec3& hi3) {
    lo = lanes::minOr(lanes::load(&lo3.x), lo);
    hi = lanes::maxOr(lanes::load(&hi3.x), hi);
  }
  Bounds bounds() const {
    double l[4], h[4];
    lanes::store(l, lo);
    lanes::store(h, hi);
    return {{l[0], l[1], l[2]}, {h[0], h[1], h[2]}};
  }
};
static_assert(offsetof(BuildItem, centroid) >= offsetof(BuildItem, bounds) + sizeof(Bounds) &&
                  sizeof(BuildItem) >= offsetof(BuildItem, centroid) + 4 * sizeof(double),
              "BuildBox reads four doubles from each Vec3 of a BuildItem");

class Builder {
 public:
  Builder(std::vector<BuildItem>& items, std::vector<BuildNode>& nodes) : items_(items), nodes_(nodes) {}

  // `spawn` more levels may build their right subtree on a thread of its own (into a
  // vector of its own, appended afterwards), which gives the same tree as building
  // everything on one thread: the node order is depth-first either way.
  void build(uint32_t begin, uint32_t end, int depth, int spawn = 0) {
    const uint32_t self = uint32_t(nodes_.size());
    nodes_.emplace_back();
    BuildBox box, centroidBox;
    for (uint32_t i = begin; i < end; ++i) {
      box.extend(items_[i].bounds.lo, items_[i].bounds.hi);
      centroidBox.extend(items_[i].centroid, items_[i].centroid);
    }
    const Bounds bounds = box.bounds(), centroids = centroidBox.bounds();
    nodes_[self].bounds = bounds;
    const uint32_t count = end - begin;
    uint32_t mid = count <= 1 ? end
                 : depth < kMaxSahDepth ? split(begin, end, bounds, centroids)
                                        : median(begin, end, centroids);
    if (mid == end) {  // a leaf
      nodes_[self].rightOrFirst = begin;
      nodes_[self].count = count;
      return;
    }
    if (spawn > 0 && end - begin >= kParallelItems) {
      std::vector<BuildNode> right;
      right.reserve(2 * size_t(end - mid));
      Builder other(items_, right);
      auto task = std::async(std::launch::async, [&] { other.build(mid, end, depth + 1, spawn - 1); });
      build(begin, mid, depth + 1, spawn - 1);
      task.get();
      const uint32_t offset = uint32_t(nodes_.size());
      nodes_[self].rightOrFirst = offset;
      for (BuildNode n : right) {
        if (n.count == 0) n.rightOrFirst += offset;  // an interior node's right child, in `right`
        nodes_.push_back(n);
      }
      return;
    }
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
    // Every axis's bins in one pass over the items (a pass an axis read them three times).
    bool binned[3];
    double lo[3], scale[3];
    for (int axis = 0; axis < 3; ++axis) {
      lo[axis] = centroids.lo[axis];
      const double extent = centroids.hi[axis] - lo[axis];
      binned[axis] = extent > 0;
      scale[axis] = binned[axis] ? kBins / extent : 0;
    }
    std::array<std::array<BuildBox, kBins>, 3> binBoxes;
    std::array<std::array<uint32_t, kBins>, 3> binCount{};
    for (uint32_t i = begin; i < end; ++i) {
      const BuildItem& it = items_[i];
      for (int axis = 0; axis < 3; ++axis) {
        if (!binned[axis]) continue;
        const int b = std::min(kBins - 1, int((it.centroid[axis] - lo[axis]) * scale[axis]));
        binBoxes[size_t(axis)][size_t(b)].extend(it.bounds.lo, it.bounds.hi);
        ++binCount[size_t(axis)][size_t(b)];
      }
    }
    for (int axis = 0; axis < 3; ++axis) {
      if (!binned[axis]) continue;
      std::array<Bounds, kBins> binBounds;
      for (int b = 0; b < kBins; ++b) binBounds[size_t(b)] = binBoxes[size_t(axis)][size_t(b)].bounds();
      // Sweep from the right to get the cost of every right side, then from the left.
      std::array<double, kBins> rightArea{};
      std::array<uint32_t, kBins> rightCount{};
      Bounds acc;
      uint32_t n = 0;
      for (int b = kBins - 1; b > 0; --b) {
        acc.extend(binBounds[size_t(b)]);
        n += binCount[size_t(axis)][size_t(b)];
        rightArea[size_t(b)] = acc.surfaceArea();
        rightCount[size_t(b)] = n;
      }
      acc = Bounds{};
      n = 0;
      for (int b = 0; b < kBins - 1; ++b) {
        acc.extend(binBounds[size_t(b)]);
        n += binCount[size_t(axis)][size_t(b)];
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
    auto middle = std::partition(items_.begin() + begin, items_.begin() + end, [&](const BuildItem& it) {
      return std::min(kBins - 1, int((it.centroid[bestAxis] - lo[bestAxis]) * scale[bestAxis])) <= bestBin;
    });
    splitAxis_ = bestAxis;
    const uint32_t mid = uint32_t(middle - items_.begin());
    if (mid == begin || mid == end) return begin + count / 2;
    return mid;
  }

  std::vector<BuildItem>& items_;
  std::vector<BuildNode>& nodes_;
  int splitAxis_ = 0;
};

// Turns the binary tree into the wide one: each wide node takes the children of a binary
// node, then keeps opening its largest interior child until it has kBvhWidth.
class Collapser {
 public:
  Collapser(const std::vector<BuildNode>& binary, std::vector<BvhNode>& wide, BvhStats& stats)
      : binary_(binary), wide_(wide), stats_(stats) {}

  void collapseRoot() {
    if (binary_[0].count > 0) {  // the whole tree is one leaf
      wide_.emplace_back();
      wide_[0].setChild(0, binary_[0].bounds, binary_[0].rightOrFirst, uint8_t(binary_[0].count));
      stats_.leaves = 1;
      stats_.maxDepth = 1;
      return;
    }
    collapse(0, 1);
  }

 private:
  uint32_t collapse(uint32_t b, int depth) {
    stats_.maxDepth = std::max(stats_.maxDepth, depth);
    const uint32_t self = uint32_t(wide_.size());
    wide_.emplace_back();
    uint32_t kids[kBvhWidth] = {b + 1, binary_[b].rightOrFirst};
    int n = 2;
    while (n < kBvhWidth) {
      int open = -1;
      double largest = -1;
      for (int i = 0; i < n; ++i) {
        const BuildNode& k = binary_[kids[i]];
        if (k.count == 0 && k.bounds.surfaceArea() > largest) {
          largest = k.bounds.surfaceArea();
          open = i;
        }
      }
      if (open < 0) break;
      const uint32_t k = kids[open];
      kids[open] = k + 1;
      kids[n++] = binary_[k].rightOrFirst;
    }
    for (int i = 0; i < n; ++i) {
      const BuildNode& k = binary_[kids[i]];
      if (k.count > 0) {
        ++stats_.leaves;
        stats_.maxDepth = std::max(stats_.maxDepth, depth + 1);
        wide_[self].setChild(i, k.bounds, k.rightOrFirst, uint8_t(k.count));
      } else {
        const uint32_t child = collapse(kids[i], depth + 1);
        wide_[self].setChild(i, k.bounds, child, 0);
      }
    }
    return self;
  }

  const std::vector<BuildNode>& binary_;
  std::vector<BvhNode>& wide_;
  BvhStats& stats_;
};

// Deep enough for any tree the build makes: the binary tree is at most about 80 levels
// deep (48 of SAH splits, then median halving), and a wide level pushes at most
// kBvhWidth - 1.
constexpr int kStackSize = 80 * (kBvhWidth - 1);

// The RaySlabs of a packet's rays, each made the first time it is asked for: many rays
// of a coherent packet are never tested against a box on their own (the cone answers
// for them), and making one costs three divisions.
class LazySlabs {
 public:
  explicit LazySlabs(const PacketRays& rays) : rays_(rays) {}
  const RaySlabs& operator[](int k) {
    if (!(made_ >> k & 1u)) {
      slabs_[k] = RaySlabs(rays_.ray(k));
      made_ |= uint64_t(1) << k;
    }
    return slabs_[k];
  }

 private:
  static_assert(kMaxPacket <= 64, "one bit per ray in made_");
  const PacketRays& rays_;
  uint64_t made_ = 0;
  RaySlabs slabs_[kMaxPacket];
};

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

BvhNode::BvhNode() {
  for (Quad& q : quad) {
    for (int a = 0; a < 3; ++a) {
      for (int c = 0; c < 4; ++c) {
        q.lo[a][c] = INFINITY;
        q.hi[a][c] = -INFINITY;
      }
    }
  }
}

void BvhNode::setChild(int slot, const Bounds& b, uint32_t index, uint8_t leafCount) {
  Quad& q = quad[slot / 4];
  for (int a = 0; a < 3; ++a) {
    q.lo[a][slot % 4] = floatDown(b.lo[a]);
    q.hi[a][slot % 4] = floatUp(b.hi[a]);
  }
  child[slot] = index;
  count[slot] = leafCount;
  used = uint8_t(std::max(int(used), slot + 1));
}

Bvh::Bvh(std::vector<Primitive> primitives, unsigned buildThreads) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<BuildItem> items;
  items.reserve(primitives.size());
  for (uint32_t i = 0; i < primitives.size(); ++i) {
    const Bounds b = primitives[i].bounds();
    if (b.empty()) continue;
    items.push_back({b, b.centroid(), i});
  }
  if (!items.empty()) {
    std::vector<BuildNode> binary;
    binary.reserve(2 * items.size());
    // Each level that may spawn doubles the threads: enough levels for buildThreads.
    int spawn = 0;
    const unsigned threads = buildThreads > 0 ? buildThreads : unsigned(threadBudget());
    for (unsigned n = threads; n > 1; n = (n + 1) / 2) ++spawn;
    Builder(items, binary).build(0, uint32_t(items.size()), 1, spawn);
    nodes_.reserve(binary.size() / 2 + 1);
    Collapser(binary, nodes_, stats_).collapseRoot();
  }
  // The order the primitives take: the bounded ones as the leaves have them, then the
  // others. Applied in place, a cycle at a time, so that a big scene does not need a second
  // copy of its primitives.
  std::vector<uint32_t> order;
  order.reserve(primitives.size());
  std::vector<bool> placed(primitives.size(), false);
  for (const BuildItem& it : items) {
    order.push_back(it.index);
    placed[it.index] = true;
  }
  boundedCount_ = uint32_t(order.size());
  items = {};
  for (uint32_t i = 0; i < primitives.size(); ++i)
    if (!placed[i]) order.push_back(i);
  std::vector<bool> done(primitives.size(), false);
  for (size_t i = 0; i < order.size(); ++i) {
    if (done[i]) continue;
    // Slot j receives the primitive at order[j], which is the next slot of the cycle and
    // still holds its own; the cycle closes with the one taken out of slot i.
    Primitive first = std::move(primitives[i]);
    for (size_t j = i;;) {
      done[j] = true;
      const size_t from = order[j];
      if (from == i) {
        primitives[j] = std::move(first);
        break;
      }
      primitives[j] = std::move(primitives[from]);
      j = from;
    }
  }
  prims_ = std::move(primitives);
  items_.reserve(prims_.size());
  for (const Primitive& p : prims_) {
    LeafItem it;
    if (const SphereShape* sphere = p.transform ? nullptr : std::get_if<SphereShape>(&p.shape)) {
      it.sphere = *sphere;
      it.kind = LeafItem::Kind::Sphere;
    } else if (const PlaneShape* plane = p.transform ? nullptr : std::get_if<PlaneShape>(&p.shape)) {
      it.plane = *plane;
      it.kind = LeafItem::Kind::Plane;
    }
    it.material = p.material;
    it.object = p.object;
    it.unit = p.unit;
    it.noShadow = p.noShadow;
    it.opaque = p.opaque;
    items_.push_back(it);
  }
  stats_.nodes = nodes_.size();
  stats_.bytes = nodes_.size() * sizeof(BvhNode) + prims_.size() * (sizeof(Primitive) + sizeof(LeafItem));
  for (const Primitive& p : prims_)
    if (p.transform) stats_.bytes += sizeof(Transform);  // an upper bound: primitives may share one
  stats_.buildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Visits the leaves whose boxes the ray enters before `tMax` (which the visitor may
// shrink), nearer child first; `leaf(i)` returning true ends the walk. Then the
// unbounded primitives. Shared by the closest-hit and the occlusion queries.
template <class Visit>
void Bvh::traverse(const Ray& ray, double tMin, const double& tMax, Visit&& visit) const {
  if (!nodes_.empty()) {
    const FloatRaySlabs slabs(ray);
    const float tMinF = float(tMin);
    struct Entry {
      uint32_t index, count;  // a node, or (count > 0) a leaf's primitives
      float enter;            // where the ray may enter its box (FloatRaySlabs' bound)
    };
    Entry stack[kStackSize];
    int top = 0;
    Entry at{0, 0, tMinF};
    for (;;) {
      if (at.count > 0) {
        for (uint32_t i = at.index; i < at.index + at.count; ++i)
          if (visit(i)) return;
      } else {
        const BvhNode& n = nodes_[at.index];
        float enter[kBvhWidth];
        unsigned mask = hitsNode(n, slabs, tMinF, float(tMax), enter);
        if (mask != 0) {
          // One child or two, the common cases deep in a big tree, without a loop or a
          // sort, whose branches a processor cannot predict.
          const int first = __builtin_ctz(mask);
          const unsigned rest = mask & (mask - 1);
          if (rest == 0) {
            at = {n.child[first], n.count[first], enter[first]};
            continue;
          }
          if ((rest & (rest - 1)) == 0) {
            const int second = __builtin_ctz(rest);
            const Entry a{n.child[first], n.count[first], enter[first]};
            const Entry b{n.child[second], n.count[second], enter[second]};
            // The nearer one now, the other stacked (the second slot when they tie, as with
            // the sort below).
            const bool aFirst = a.enter < b.enter;
            const Entry later = aFirst ? b : a;
            stack[top++] = later;
            at = aFirst ? a : b;
            if (later.count == 0) {
              for (size_t line = 0; line < sizeof(BvhNode); line += 64)
                __builtin_prefetch(reinterpret_cast<const char*>(&nodes_[later.index]) + line);
            }
            continue;
          }
          // The children the ray enters, nearest last: it is visited now, the others
          // stacked so that the nearer ones come off first.
          Entry hit[kBvhWidth];
          int m = 0;
          for (; mask != 0; mask &= mask - 1) {
            const int c = __builtin_ctz(mask);
            hit[m++] = {n.child[c], n.count[c], enter[c]};
            // Start fetching every child the ray enters now, so that in a tree far bigger
            // than the caches their misses overlap instead of coming one after another.
            if (n.count[c] == 0) {
              for (size_t line = 0; line < sizeof(BvhNode); line += 64)
                __builtin_prefetch(reinterpret_cast<const char*>(&nodes_[n.child[c]]) + line);
            } else {
              __builtin_prefetch(&items_[n.child[c]]);
            }
          }
          for (int i = 1; i < m; ++i)
            for (int j = i; j > 0 && hit[j - 1].enter < hit[j].enter; --j) std::swap(hit[j - 1], hit[j]);
          for (int i = 0; i + 1 < m; ++i) stack[top++] = hit[i];
          at = hit[m - 1];
          continue;
        }
      }
      // The next stacked child that the ray still enters before tMax (which may have
      // shrunk since it was stacked).
      const float limit = FloatRaySlabs::limit(float(tMax));
      while (top > 0 && stack[top - 1].enter > limit) --top;
      if (top == 0) break;
      at = stack[--top];
    }
  }
  for (uint32_t i = boundedCount_; i < prims_.size(); ++i)
    if (visit(i)) return;
}

bool Bvh::blocks(uint32_t i, const Ray& ray, double tMin, double tMax, uint64_t& tests, bool& transparent,
                 uint32_t& blocker) const {
  const LeafItem& p = items_[i];
  if (p.noShadow) return false;
  ++tests;
  if (!intersectItem(i, ray, tMin, tMax)) return false;
  if (!p.opaque) {
    transparent = true;
    return false;
  }
  blocker = i;
  return true;
}

Occlusion Bvh::occlusion(const Ray& ray, double tMin, double tMax, uint64_t& tests, uint32_t& blocker) const {
  bool transparent = false, blocked = false;
  traverse(ray, tMin, tMax,
           [&](uint32_t i) { return blocked = blocks(i, ray, tMin, tMax, tests, transparent, blocker); });
  return blocked ? Occlusion::Blocked : transparent ? Occlusion::Transparent : Occlusion::Clear;
}

Occlusion Bvh::occlusionToLight(const LightBuffer& buffer, const Ray& ray, double tMin, double tMax, double reach,
                                uint64_t& tests, uint32_t& blocker) const {
  const int index = buffer.cellIndexOf(-ray.dir);
  if (index < 0) return occlusion(ray, tMin, tMax, tests, blocker);
  return occlusionToLight(buffer, index, ray, tMin, tMax, reach, tests, blocker);
}

Occlusion Bvh::occlusionToLight(const LightBuffer& buffer, int index, const Ray& ray, double tMin, double tMax,
                                double reach, uint64_t& tests, uint32_t& blocker) const {
  const std::span<const LightBuffer::Entry> cell = buffer.list(index);
  bool transparent = false;
  // In a big scene the leaf records of a list's entries lie far apart in memory: each is
  // fetched kAhead entries before its test, so that several fetches are under way at once
  // instead of one after another. Entries past `reach` are never tested, nor fetched.
  constexpr size_t kAhead = 8;
  auto fetch = [&](size_t k) {
    if (k < cell.size() && cell[k].near <= reach) __builtin_prefetch(&items_[cell[k].primitive]);
  };
  for (size_t k = 0; k < kAhead; ++k) fetch(k);
  for (size_t k = 0; k < cell.size(); ++k) {
    const LightBuffer::Entry& e = cell[k];
    if (e.near > reach) break;
    fetch(k + kAhead);
    if (blocks(e.primitive, ray, tMin, tMax, tests, transparent, blocker)) return Occlusion::Blocked;
  }
  for (uint32_t i : buffer.everywhere())
    if (blocks(i, ray, tMin, tMax, tests, transparent, blocker)) return Occlusion::Blocked;
  for (uint32_t i = boundedCount_; i < prims_.size(); ++i)
    if (blocks(i, ray, tMin, tMax, tests, transparent, blocker)) return Occlusion::Blocked;
  return transparent ? Occlusion::Transparent : Occlusion::Clear;
}

bool Bvh::shadowCandidates(const LightBuffer& buffer, const Ray& ray, double length, double reach, double drift,
                           std::vector<uint32_t>& out) const {
  out.clear();
  const int index = buffer.cellIndexOf(-ray.dir);
  if (index < 0) return false;
  shadowCandidates(buffer, index, ray, length, reach, drift, out);
  return true;
}

void Bvh::shadowCandidates(const LightBuffer& buffer, int index, const Ray& ray, double length, double reach,
                           double drift, std::vector<uint32_t>& out) const {
  out.clear();
  for (const LightBuffer::Entry& e : buffer.list(index)) {
    if (e.near > reach) break;
    const LeafItem& it = items_[e.primitive];
    if (it.noShadow) continue;
    if (it.kind == LeafItem::Kind::Sphere) {
      // The sphere test's squared half chord, r^2 - |perp|^2, for this line. A segment
      // starting within `drift` of it changes |perp|^2 by at most 2 x drift + drift^2, and
      // rounding by some 1e-15 (x^2 + r^2): a chord this far below zero stays a miss.
      const Vec3 oc = it.sphere.center - ray.origin;
      const Vec3 perp = oc - ray.dir * dot(oc, ray.dir);
      const double r2 = it.sphere.radius * it.sphere.radius;
      const double x = pvrt::length(oc) + length;
      if (r2 - dot(perp, perp) < -(1e-9 * (x * x + r2) + 4 * x * drift)) continue;
    }
    out.push_back(e.primitive);
  }
  for (uint32_t i : buffer.everywhere())
    if (!items_[i].noShadow) out.push_back(i);
}

std::optional<ClosestHit> Bvh::closestAmong(std::span<const uint32_t> candidates, const Ray& ray, double tMin,
                                            double tMax, uint64_t& tests) const {
  std::optional<ClosestHit> best;
  double bestT = tMax;
  auto test = [&](uint32_t i) {
    ++tests;
    if (auto h = intersectItem(i, ray, tMin, bestT)) {
      bestT = h->t;
      best = ClosestHit{*h, i};
    }
  };
  for (uint32_t i : candidates) test(i);
  for (uint32_t i = boundedCount_; i < prims_.size(); ++i)
    if (!items_[i].noShadow) test(i);
  return best;
}

std::vector<LightBuffer::Occluder> Bvh::occluders() const {
  std::vector<LightBuffer::Occluder> out(boundedCount_);
  for (uint32_t i = 0; i < boundedCount_; ++i) {
    out[i].box = prims_[i].bounds();
    if (items_[i].kind == LeafItem::Kind::Sphere) {
      out[i].center = items_[i].sphere.center;
      out[i].radius = std::fabs(items_[i].sphere.radius);
    }
  }
  return out;
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
// enters, nearer child first as far as the packet's cone can tell. A node's child boxes
// are first tested against the whole cone (cheap, and enough for a coherent
// packet); those the cone may reach are then kept only if `enters(node, candidates)`
// finds a ray that really enters them, so an incoherent packet never walks more of the
// tree than its rays would one by one. `leaf(first, count, parent, slot)` returning true
// ends the walk.
template <class Enters, class Leaf>
void Bvh::traversePacket(const PacketCone& cone, const double& sHi, Enters&& enters, Leaf&& leaf) const {
  if (nodes_.empty()) return;
  struct Entry {
    uint32_t node, slot;  // child `slot` of node `node`
    double enter;         // where the cone may first reach its box
  };
  Entry stack[kStackSize];
  int top = 0;
  uint32_t node = 0;
  for (;;) {
    const BvhNode& n = nodes_[node];
    double enter[kBvhWidth];
    unsigned mask = 0;
    for (int q = 0; q < n.quads(); ++q)
      mask |= cone.entries(n.quad[q].lo, n.quad[q].hi, sHi, enter + 4 * q) << (4 * q);
    mask &= (1u << n.used) - 1;
    if (mask != 0) mask = enters(n, mask);
    Entry hit[kBvhWidth];
    int m = 0;
    for (; mask != 0; mask &= mask - 1) {
      const uint32_t c = uint32_t(__builtin_ctz(mask));
      hit[m++] = {node, c, enter[c]};
    }
    for (int i = 1; i < m; ++i)
      for (int j = i; j > 0 && hit[j - 1].enter < hit[j].enter; --j) std::swap(hit[j - 1], hit[j]);
    for (int i = 0; i < m; ++i) stack[top++] = hit[i];
    // Leaves come off the stack to be visited; the first interior node is descended into.
    for (;;) {
      if (top == 0) return;
      const Entry e = stack[--top];
      const BvhNode& parent = nodes_[e.node];
      if (parent.count[e.slot] == 0) {
        node = parent.child[e.slot];
        break;
      }
      if (leaf(parent.child[e.slot], parent.count[e.slot], parent, int(e.slot))) return;
    }
  }
}

void Bvh::closestPacket(const Ray* rays, int count, double tMin, double tMax, std::optional<ClosestHit>* out,
                        uint64_t& tests) const {
  PacketRays lanes;
  lanes.set(rays, count);
  // Plain arrays, not value-initialised: a packet sets what it reads. The hits are kept
  // a field per array until the end (assigning std::optionals in the loop costs more).
  alignas(32) double best[kMaxPacket];
  double hitU[kMaxPacket], hitV[kMaxPacket];
  int hitPart[kMaxPacket];
  uint32_t owner[kMaxPacket];
  for (int k = 0; k < lanes.groups * 4; ++k) best[k] = k < count ? tMax : -INFINITY;
  for (int k = 0; k < count; ++k) owner[k] = kNone;
  LazySlabs slabs(lanes);
  // Unit directions from a common origin: the ray parameter t is the cone's s.
  Vec3 lo, hi;
  lanes.directionRange(lo, hi);
  const PacketCone cone(rays[0].origin, lo, hi, tMin);
  double farthest = tMax;  // the largest best[k]: beyond it no ray needs anything
  // Tests every ray against primitive i, four at a time for a sphere or a plane.
  auto intersect = [&](uint32_t i) {
    tests += uint64_t(count);
    const LeafItem& p = items_[i];
    if (p.kind == LeafItem::Kind::Other) {
      for (int k = 0; k < count; ++k) {
        if (const auto h = intersectItem(i, rays[k], tMin, best[k])) {
          best[k] = h->t;
          hitPart[k] = h->part;
          hitU[k] = h->u;
          hitV[k] = h->v;
          owner[k] = i;
        }
      }
      return;
    }
    double t[4];
    for (int g = 0; g < lanes.groups; ++g) {
      const unsigned real = count - 4 * g >= 4 ? 0xFu : (1u << (count - 4 * g)) - 1;
      unsigned hit = (p.kind == LeafItem::Kind::Sphere
                          ? intersectWorldSphere4(p.sphere, p.unit, lanes, 4 * g, tMin, best + 4 * g, t)
                          : hitPlane4(p.plane, p.unit, lanes, 4 * g, tMin, best + 4 * g, t)) &
                      real;
      for (; hit != 0; hit &= hit - 1) {
        const int c = __builtin_ctz(hit), k = 4 * g + c;
        best[k] = t[c];
        hitPart[k] = 0;
        hitU[k] = hitV[k] = 0;
        owner[k] = i;
      }
    }
  };
  double unused[kBvhWidth];
  auto enters = [&](const BvhNode& n, unsigned candidates) {
    unsigned found = 0;
    for (int k = 0; k < count && found != candidates; ++k)
      found |= hitsChildren(n, slabs[k], tMin, best[k], unused) & candidates;
    return found;
  };
  // A leaf's primitives are tested against every ray: four rays cost one vector test,
  // about what one ray's box test would cost to rule them out.
  traversePacket(cone, farthest, enters, [&](uint32_t first, uint32_t n, const BvhNode&, int) {
    for (uint32_t i = first; i < first + n; ++i) intersect(i);
    farthest = *std::max_element(best, best + count);
    return false;
  });
  for (uint32_t i = boundedCount_; i < prims_.size(); ++i) intersect(i);
  for (int k = 0; k < count; ++k) {
    if (owner[k] == kNone) out[k].reset();
    else out[k] = ClosestHit{ShapeHit{best[k], hitPart[k], hitU[k], hitV[k]}, owner[k]};
  }
}

namespace {

// The segments of `live` that a plane surely does not meet, four lanes at a time: those that
// start on the apex's side of it with a margin far above rounding (every point of such a
// segment is on that side, so its parameter at the plane falls outside it, as the exact test
// would find), and those that start exactly on it as hitPlane4 computes (their distance to
// it is zero, so their hit parameter is not above tMin: hitPlane4 gives no hit).
uint64_t planeMisses(const PlaneShape& plane, const Vec3& apex, const PacketRays& lanes, uint64_t live) {
  using namespace lanes;
  const double a = dot(plane.normal, apex), d = a - plane.distance;
  const double margin = 1e-9 * (std::fabs(a) + std::fabs(plane.distance));
  const int apexSide = d > margin ? 1 : d < -margin ? -1 : 0;
  const Double4 nx = splat(plane.normal.x), ny = splat(plane.normal.y), nz = splat(plane.normal.z);
  const Double4 distance = splat(plane.distance), scale = splat(1e-9), absDistance = splat(std::fabs(plane.distance));
  uint64_t misses = 0;
  for (int g = 0; g < lanes.groups; ++g) {
    if ((live >> (4 * g) & 0xFu) == 0) continue;
    const int k = 4 * g;
    // In hitPlane4's order, which is also dot()'s.
    const Double4 at = nx * load(lanes.ox + k) + ny * load(lanes.oy + k) + nz * load(lanes.oz + k);
    const Double4 off = at - distance, slack = scale * (abs(at) + absDistance);
    unsigned miss = equal(at, distance);
    if (apexSide > 0) miss |= less(slack, off);
    if (apexSide < 0) miss |= less(off, splat(0.0) - slack);
    misses |= uint64_t(miss) << k;
  }
  return misses & live;
}

}  // namespace

void Bvh::occlusionPacket(const Vec3& apex, const Ray* segments, const double* tMax, int count, double tMin,
                          Occlusion* out, uint32_t* blocker, uint64_t& tests) const {
  PacketRays lanes;
  lanes.set(segments, count);
  alignas(32) double hi[kMaxPacket];
  for (int k = 0; k < lanes.groups * 4; ++k) hi[k] = k < count ? tMax[k] : -INFINITY;
  static_assert(kMaxPacket <= 64, "one bit per segment");
  occlusionPacket(apex, lanes, hi, tMin, count == 64 ? ~uint64_t(0) : (uint64_t(1) << count) - 1, out, blocker,
                  tests);
}

void Bvh::occludeLive(uint32_t i, const PacketRays& lanes, const double* tMax, double tMin, uint64_t& live,
                      Occlusion* out, uint32_t* blocker, uint64_t& tests) const {
  const LeafItem& p = items_[i];
  if (p.noShadow) return;
  tests += uint64_t(__builtin_popcountll(live));
  auto record = [&](int k) {
    if (p.opaque) {
      out[k] = Occlusion::Blocked;
      blocker[k] = i;
      live &= ~(uint64_t(1) << k);
    } else {
      out[k] = Occlusion::Transparent;
    }
  };
  if (p.kind != LeafItem::Kind::Other) {
    double t[4];
    for (int g = 0; g < lanes.groups; ++g) {
      const unsigned group = unsigned(live >> (4 * g)) & 0xFu;
      if (group == 0) continue;
      unsigned hit = (p.kind == LeafItem::Kind::Sphere
                          ? intersectWorldSphere4(p.sphere, p.unit, lanes, 4 * g, tMin, tMax + 4 * g, t)
                          : hitPlane4(p.plane, p.unit, lanes, 4 * g, tMin, tMax + 4 * g, t)) &
                     group;
      for (; hit != 0; hit &= hit - 1) record(4 * g + __builtin_ctz(hit));
    }
    return;
  }
  for (uint64_t m = live; m != 0; m &= m - 1) {
    const int k = __builtin_ctzll(m);
    if (intersectItem(i, lanes.ray(k), tMin, tMax[k])) record(k);
  }
}

void Bvh::occludeLiveByUnbounded(const Vec3& apex, const PacketRays& lanes, const double* tMax, double tMin,
                                 uint64_t& live, Occlusion* out, uint32_t* blocker, uint64_t& tests) const {
  for (uint32_t i = boundedCount_; i < prims_.size() && live != 0; ++i) {
    const LeafItem& it = items_[i];
    const bool plane = it.kind == LeafItem::Kind::Plane && !it.noShadow;
    const uint64_t missed = plane ? planeMisses(it.plane, apex, lanes, live) : 0;
    uint64_t tested = live & ~missed;
    if (tested == 0) continue;
    occludeLive(i, lanes, tMax, tMin, tested, out, blocker, tests);
    live = tested | missed;
  }
}

void Bvh::occlusionPacket(const Vec3& apex, const PacketRays& lanes, const double* tMax, double tMin,
                          uint64_t live, Occlusion* out, uint32_t* blocker, uint64_t& tests) const {
  // From here on `live` holds the segments not yet blocked.
  std::fill(out, out + lanes.count, Occlusion::Clear);
  if (live == 0) return;
  LazySlabs slabs(lanes);
  // The cone runs from the light back to each segment's start: s in [0, 1].
  Vec3 lo, hi;
  lanes.originRange(apex, lo, hi);
  const PacketCone cone(apex, lo, hi, 0.0);
  const double sHi = 1.0;
  double unused[kBvhWidth];
  auto enters = [&](const BvhNode& node, unsigned candidates) {
    unsigned found = 0;
    for (uint64_t m = live; m != 0 && found != candidates; m &= m - 1) {
      const int k = __builtin_ctzll(m);
      found |= hitsChildren(node, slabs[k], tMin, tMax[k], unused) & candidates;
    }
    return found;
  };
  // A leaf's primitives are tested against every live segment: four segments cost one
  // vector test, about what one segment's box test would cost to rule them out.
  traversePacket(cone, sHi, enters, [&](uint32_t first, uint32_t n, const BvhNode&, int) {
    for (uint32_t i = first; i < first + n && live != 0; ++i)
      occludeLive(i, lanes, tMax, tMin, live, out, blocker, tests);
    return live == 0;
  });
  occludeLiveByUnbounded(apex, lanes, tMax, tMin, live, out, blocker, tests);
}

void Bvh::occlusionPacketInCell(const LightBuffer& buffer, int cell, double reach, const PacketRays& lanes,
                                const double* tMax, double tMin, uint64_t live, Occlusion* out, uint32_t* blocker,
                                uint64_t& tests) const {
  std::fill(out, out + lanes.count, Occlusion::Clear);
  for (const LightBuffer::Entry& e : buffer.list(cell)) {
    if (e.near > reach || live == 0) break;
    occludeLive(e.primitive, lanes, tMax, tMin, live, out, blocker, tests);
  }
  for (uint32_t i : buffer.everywhere())
    if (live != 0) occludeLive(i, lanes, tMax, tMin, live, out, blocker, tests);
  occludeLiveByUnbounded(buffer.light(), lanes, tMax, tMin, live, out, blocker, tests);
}

}  // namespace pvrt
