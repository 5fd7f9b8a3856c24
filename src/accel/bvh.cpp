// Iterative, front-to-back traversals of the BVH (built in bvh_build.cpp).
#include "accel/bvh.h"

#include "geometry/pov_bbox.h"

#include <algorithm>
#include <cmath>
#include <new>

#include "accel/packet_rays.h"
#include "accel/pov_heap_order.h"
#include "accel/slabs.h"
#include "core/lanes.h"
#include "core/prefault.h"
#include "geometry/pov_bbox.h"
#include "parallel/parallel_for.h"

namespace pvrt {

namespace {

constexpr uint32_t kNone = ~0u;

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

// Visits the unbounded primitives, then the leaves whose boxes the ray enters before
// `tMax` (which the visitor may shrink), nearer child first; `leaf(i)` returning true ends
// the walk. Shared by the closest-hit and the occlusion queries. The unbounded ones come
// first as in POV-Ray (its infinite objects head the bounding tree's queue): with a later
// hit kept only when strictly nearer, a plane wins a tie with a face lying on it or an
// edge meeting it (docs/fidelity.md).
template <class Visit>
void Bvh::traverse(const Ray& ray, double tMin, const double& tMax, Visit&& visit) const {
  for (uint32_t i = boundedCount_; i < items_.size(); ++i)
    if (visit(i)) return;
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
}

bool Bvh::blocks(uint32_t i, const Ray& ray, double tMin, double tMax, uint64_t& tests, bool& transparent,
                 uint32_t& blocker) const {
  const PrimitiveRecord& p = items_[i];
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

bool Bvh::objectHit(uint32_t i, const Ray& ray, double tMin, double tMax, uint64_t& tests) const {
  ++tests;
  if (!items_[i].sharesObject) return intersectItem(i, ray, tMin, tMax, false).has_value();
  // A mesh: any of its triangles, found by a walk that tests no other object's primitives.
  const uint32_t object = items_[i].object;
  bool hit = intersectItem(i, ray, tMin, tMax, false).has_value();  // the cached triangle first
  if (!hit)
    traverse(ray, tMin, tMax, [&](uint32_t j) {
      if (j == i || items_[j].object != object) return false;
      ++tests;
      return hit = intersectItem(j, ray, tMin, tMax, false).has_value();
    });
  return hit;
}

Occlusion Bvh::occlusionToLight(const LightBuffer& buffer, const Ray& ray, double tMin, double tMax, double reach,
                                uint64_t& tests, uint32_t& blocker) const {
  const int index = buffer.cellIndexOf(-ray.dir);
  if (index < 0) return occlusion(ray, tMin, tMax, tests, blocker);
  return occlusionToLight(buffer, index, ray, tMin, tMax, reach, tests, blocker);
}

Occlusion Bvh::occlusionToLight(const LightBuffer& buffer, int index, const Ray& ray, double tMin, double tMax,
                                double reach, uint64_t& tests, uint32_t& blocker) const {
  return occlusionInCell<false>(buffer, index, ray, tMin, tMax, reach, tests, blocker, nullptr);
}

Occlusion Bvh::occlusionToLight(const LightBuffer& buffer, int index, const Ray& ray, double tMin, double tMax,
                                double reach, uint64_t& tests, uint32_t& blocker, ClosestHit& nearest) const {
  return occlusionInCell<true>(buffer, index, ray, tMin, tMax, reach, tests, blocker, &nearest);
}

Occlusion Bvh::occlusionToLight(const LightBuffer& buffer, int index, const Ray& ray, double tMin, double tMax,
                                double reach, uint64_t& tests, uint32_t& blocker, ClosestHit& nearest, double length,
                                double drift, std::vector<uint32_t>& candidates) const {
  const Listing listing{length, drift, &candidates};
  return occlusionInCell<true>(buffer, index, ray, tMin, tMax, reach, tests, blocker, &nearest, &listing);
}

template <bool kNoteNearest>
Occlusion Bvh::occlusionInCell(const LightBuffer& buffer, int index, const Ray& ray, double tMin, double tMax,
                               double reach, uint64_t& tests, uint32_t& blocker, ClosestHit* nearest,
                               const Listing* listing) const {
  const std::span<const LightBuffer::Entry> cell = buffer.list(index);
  if (listing) listing->out->clear();
  bool transparent = false;
  // The nearest see-through hit (kNoteNearest): the first of equals in the order closestAmong
  // tests them, which puts the unbounded primitives first, so theirs is kept apart.
  double bestT = INFINITY, unboundedT = INFINITY;
  ClosestHit best, unbounded;
  auto test = [&](uint32_t i, double& nearestT, ClosestHit& hit) {
    if constexpr (!kNoteNearest) {
      return blocks(i, ray, tMin, tMax, tests, transparent, blocker);
    } else {
      const PrimitiveRecord& p = items_[i];
      if (p.noShadow) return false;
      ++tests;
      const std::optional<ShapeHit> h = intersectItem(i, ray, tMin, tMax);
      if (!h) return false;
      if (p.opaque) {
        blocker = i;
        return true;
      }
      transparent = true;
      if (h->t < nearestT) nearestT = h->t, hit = {*h, i};
      return false;
    }
  };
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
    if (test(e.primitive, bestT, best)) return Occlusion::Blocked;
    if (listing && candidate(e.primitive, ray, listing->length, listing->drift)) listing->out->push_back(e.primitive);
  }
  for (uint32_t i : buffer.everywhere()) {
    if (test(i, bestT, best)) return Occlusion::Blocked;
    if (listing && !items_[i].noShadow) listing->out->push_back(i);
  }
  for (uint32_t i = boundedCount_; i < items_.size(); ++i)
    if (test(i, unboundedT, unbounded)) return Occlusion::Blocked;
  if constexpr (kNoteNearest) {
    if (transparent) *nearest = unboundedT <= bestT ? unbounded : best;
  }
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
    if (candidate(e.primitive, ray, length, drift)) out.push_back(e.primitive);
  }
  for (uint32_t i : buffer.everywhere())
    if (!items_[i].noShadow) out.push_back(i);
}

bool Bvh::candidate(uint32_t i, const Ray& ray, double length, double drift) const {
  const PrimitiveRecord& it = items_[i];
  if (it.noShadow) return false;
  if (it.kind != PrimitiveRecord::Kind::Sphere) return true;
  // The sphere test's squared half chord, r^2 - |perp|^2, for this line. A segment
  // starting within `drift` of it changes |perp|^2 by at most 2 x drift + drift^2, and
  // rounding by some 1e-15 (x^2 + r^2): a chord this far below zero stays a miss.
  const Vec3 oc = it.sphere.center - ray.origin;
  const Vec3 perp = oc - ray.dir * dot(oc, ray.dir);
  const double r2 = it.sphere.radius * it.sphere.radius;
  const double chord = r2 - dot(perp, perp);
  if (!(chord < 0)) return true;  // kept below whatever x is
  // x = |oc| + length, the bound below grows with x, and the 1-norm is at least |oc| (widened
  // past any rounding of either): a chord below the bound for that larger x is below it for x
  // itself, found with no square root.
  const double wide = (std::fabs(oc.x) + std::fabs(oc.y) + std::fabs(oc.z)) * (1 + 1e-12) + length;
  if (chord < -(1e-9 * (wide * wide + r2) + 4 * wide * drift)) return false;
  const double x = pvrt::length(oc) + length;
  return !(chord < -(1e-9 * (x * x + r2) + 4 * x * drift));
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
  for (uint32_t i = boundedCount_; i < items_.size(); ++i)  // first, as in traverse()
    if (!items_[i].noShadow) test(i);
  for (uint32_t i : candidates) test(i);
  return best;
}

Primitive Bvh::primitive(uint32_t i) const { return primitiveOf(items_[i], others_); }

std::vector<LightBuffer::Occluder> Bvh::occluders() const {
  std::vector<LightBuffer::Occluder> out;
  resizePrefaulted(out, boundedCount_, 0);
  parallelBlocks(Blocks(boundedCount_, 0, 4096), 0, [&](size_t, size_t lo, size_t hi) {
    for (size_t i = lo; i < hi; ++i) {
      out[i].box = boundsOf(items_[i], others_);
      if (items_[i].kind == PrimitiveRecord::Kind::Sphere) {
        out[i].center = items_[i].sphere.center;
        out[i].radius = std::fabs(items_[i].sphere.radius);
      }
    }
  });
  return out;
}

void Bvh::setTieRule(TieRule rule) {
  tieRule_ = rule;
  if (rule != TieRule::BoxEntry) povAbove_.clear();
  // The rule says whether POV-Ray builds its bounding tree (accel/tie_order.h), whose
  // leaves' boxes a ray must pass first (Primitive::povTreeLeaf).
  for (Primitive& p : others_) p.povTreeLeaf = rule == TieRule::BoxEntry;
  tieExtent_ = 0;
  if (!nodes_.empty())
    for (int c = 0; c < nodes_[0].used; ++c) {
      const Bounds b = nodes_[0].childBounds(c);
      tieExtent_ = std::max({tieExtent_, std::fabs(b.lo.x), std::fabs(b.lo.y), std::fabs(b.lo.z), std::fabs(b.hi.x),
                             std::fabs(b.hi.y), std::fabs(b.hi.z)});
    }
  if (!std::isfinite(tieExtent_)) tieExtent_ = 0;
  // Beyond kPovFloatReach pvrt keeps the nearer hit (geometry/pov_bbox.h).
  if (tieRule_ == TieRule::BoxEntry && tieExtent_ >= kPovFloatReach) tieRule_ = TieRule::FirstFound;
}

bool Bvh::povPassesNodesAbove(uint32_t i, const Ray& ray) const {
  // Within kPovFloatReach only, as Primitive::intersect's tests (the boxes are, by tieExtent_).
  if (tieRule_ != TieRule::BoxEntry ||
      std::fabs(ray.origin.x) + std::fabs(ray.origin.y) + std::fabs(ray.origin.z) >= kPovFloatReach)
    return true;
  if (povAbove_[i].empty()) return true;
  const PovRayInfo info(ray);
  for (const PovBBox& box : povAbove_[i])
    if (!std::isfinite(povBBoxKey(box, info))) return false;
  return true;
}

// A key is a few float roundings (relative 2^-24 each) of (box corner - origin) / direction
// along one axis, so its error is below 2^-22 times the corner's and the origin's size over
// that direction component (the corners are within tieExtent_). The declaration rule looks
// only at exact ties.
Bvh::TieReach Bvh::tieReach(const Ray& ray) const {
  if (tieRule_ != TieRule::BoxEntry) return {};
  const double from = std::fabs(ray.origin.x) + std::fabs(ray.origin.y) + std::fabs(ray.origin.z);
  if (from >= kPovFloatReach) return {};  // exact ties only (setTieRule)
  double least = 1.0;  // the smallest direction component that can give a key
  for (double d : {ray.dir.x, ray.dir.y, ray.dir.z})
    if (d != 0) least = std::min(least, std::fabs(d));
  return {1e-6 / std::max(least, 1e-3), from + tieExtent_};
}

bool Bvh::replacesHit(uint32_t found, double tFound, uint32_t kept, double tKept, const Ray& ray) const {
  const uint32_t a = items_[found].object, b = items_[kept].object;
  switch (tieRule_) {
    case TieRule::FirstFound: return tFound < tKept;
    case TieRule::Declaration: return tFound < tKept || (tFound == tKept && a < b && a != b);
    case TieRule::BoxEntry: break;
  }
  if (a == b) return tFound < tKept;
  // Near a tie: POV-Ray pops the two objects' boxes in order of their keys (a box's entry
  // depth in floats; an unbounded object first), tests the first, and tests the second only
  // if its key is not beyond the first one's depth, keeping it only if strictly nearer.
  // Worked out only here, so the boxes are made again from the primitives.
  auto keyOf = [this, &ray](uint32_t i) -> std::optional<double> {
    const PrimitiveRecord& it = items_[i];
    switch (it.kind) {
      case PrimitiveRecord::Kind::Sphere: return povBBoxKey(povSphereBBox(it.sphere.center, it.sphere.radius), ray);
      case PrimitiveRecord::Kind::Plane: return -INFINITY;
      case PrimitiveRecord::Kind::Other: break;
    }
    if (others_[it.other].bounds().empty()) return -INFINITY;
    const std::optional<PovBBox> box = others_[it.other].povBBox();
    if (!box) return std::nullopt;
    return povBBoxKey(*box, ray);
  };
  const std::optional<double> mine = keyOf(found), theirs = keyOf(kept);
  if (!mine || !theirs) return tFound < tKept;  // a box pvrt does not know: the nearer hit
  // Equal keys (two planes, or two objects whose boxes the ray enters at one float depth) fall
  // to POV-Ray's heap (accel/pov_heap_order.h), which depends on its tree's root, made once by
  // the build (makePovTieRoot). Where pvrt could not make it, the one found first is kept.
  if (tFound == tKept && *mine == *theirs) {
    if (!povTieKnown_) return false;
    const int planes = int(items_.size() - boundedCount_);
    if (*mine == -INFINITY) {  // two planes: only how many root entries wait beside them matters
      int queued = 0;
      for (const PovBBox& box : povTieRootBoxes_) queued += std::isfinite(povBBoxKey(box, ray));
      const std::vector<int> order = povPlanePopOrder(queued, planes);
      auto rank = [&](uint32_t i) {
        return std::find(order.begin(), order.end(), int(i - boundedCount_)) - order.begin();
      };
      return rank(found) < rank(kept);
    }
    // Two finite objects: the walk pushes the root's entries (the planes' node first, key
    // -MAX_DISTANCE), pops the planes' node and pushes its planes, and pops on; the object
    // popped first is tested first and keeps the tie. Known where the root holds the objects
    // themselves; a root of nodes pushes and pops more, which pvrt does not follow.
    if (!povTieRootHoldsObjects_) return false;
    constexpr double kMaxDistance = 1e7;  // POV-Ray's MAX_DISTANCE
    constexpr int kPlanesNode = -2, kPlane = -3;
    PovQueue queue;
    if (planes > 0) queue.push({-kMaxDistance, kPlanesNode});
    for (size_t k = 0; k < povTieRootBoxes_.size(); ++k)
      if (const double key = povBBoxKey(povTieRootBoxes_[k], ray); std::isfinite(key))
        queue.push({key, povTieRootEntries_[k]});
    while (!queue.empty()) {
      const PovQueue::Entry e = queue.pop();
      if (e.id == kPlanesNode)
        for (int k = 0; k < planes; ++k) queue.push({-kMaxDistance, kPlane});
      if (e.id < 0) continue;
      if (povTieObjects_[size_t(e.id)] == a) return true;
      if (povTieObjects_[size_t(e.id)] == b) return false;
    }
    return false;
  }
  if (*mine < *theirs) return !(*theirs <= tFound && tKept < tFound);  // found's box first
  return *mine <= tKept && tFound < tKept;  // kept's box first (or equal keys: the one found first)
}

std::optional<ClosestHit> Bvh::closest(const Ray& ray, double tMin, double tMax, uint64_t& tests,
                                       bool skipNoShadow) const {
  std::optional<ClosestHit> best;
  // Shapes are asked for hits below `limit`: the best depth so far, or with a tie order the
  // next double above it, so that a hit at exactly that depth is seen and the order decides.
  double bestT = tMax, limit = tMax;
  const bool ordered = tieRule_ != TieRule::FirstFound && !skipNoShadow;
  const TieReach reach = ordered ? tieReach(ray) : TieReach{};
  traverse(ray, tMin, limit, [&](uint32_t i) {
    if (skipNoShadow && items_[i].noShadow) return false;
    ++tests;
    if (auto h = intersectItem(i, ray, tMin, limit)) {
      if (best && !(ordered ? h->t < bestT - reach.at(bestT) || replacesHit(i, h->t, best->primitive, bestT, ray)
                            : h->t < bestT))
        return false;
      bestT = h->t;
      limit = ordered ? std::max(nextUp(bestT), bestT + reach.at(bestT)) : bestT;
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

namespace {

// The closest hits of a packet's rays while closestPacket or closestSpread runs, a field
// per array until the end (assigning std::optionals in the loop costs more). Plain
// arrays, not value-initialised: a query sets what it reads.
struct LaneHits {
  alignas(32) double best[kMaxPacket];
  // What each lane's shapes are asked for hits below (closest()'s `limit`): best, or with a
  // tie order the next double above it once the lane has a hit.
  alignas(32) double limit[kMaxPacket];
  double u[kMaxPacket], v[kMaxPacket];
  int part[kMaxPacket];
  uint32_t owner[kMaxPacket];
  const Bvh& bvh;
  const bool ordered;  // the tree has a tie rule
  Bvh::TieReach reach[kMaxPacket];  // each live lane's, when ordered

  // A lane out of `live` (padding included) starts at -infinity, which no hit is nearer than.
  LaneHits(const PacketRays& lanes, uint64_t live, double tMax, const Bvh& tree)
      : bvh(tree), ordered(tree.tieRule() != TieRule::FirstFound) {
    for (int k = 0; k < lanes.groups * 4; ++k) {
      best[k] = limit[k] = (live >> k & 1u) ? tMax : -INFINITY;
      owner[k] = kNone;
    }
    if (ordered)
      for (uint64_t m = live; m != 0; m &= m - 1) reach[__builtin_ctzll(m)] = bvh.tieReach(lanes.ray(__builtin_ctzll(m)));
  }
  // Tests the rays of `among` against primitive i (record p), four at a time for a sphere
  // or a plane; another shape one ray at a time, by other(i, ray, tMin, tMax).
  template <class Other>
  void intersect(const PrimitiveRecord& p, uint32_t i, const PacketRays& lanes, uint64_t among, double tMin,
                 uint64_t& tests, Other&& other) {
    tests += uint64_t(__builtin_popcountll(among));
    if (p.kind == PrimitiveRecord::Kind::Other) {
      for (uint64_t m = among; m != 0; m &= m - 1) {
        const int k = __builtin_ctzll(m);
        if (const auto h = other(i, lanes.ray(k), tMin, limit[k])) note(k, h->t, h->part, h->u, h->v, i, lanes);
      }
      return;
    }
    double t[4];
    for (int g = 0; g < lanes.groups; ++g) {
      const unsigned in = unsigned(among >> (4 * g)) & 0xFu;
      if (in == 0) continue;
      unsigned hit = (p.kind == PrimitiveRecord::Kind::Sphere
                          ? intersectWorldSphere4(p.sphere, p.unit, lanes, 4 * g, tMin, limit + 4 * g, t)
                          : hitPlane4(p.plane, p.unit, lanes, 4 * g, tMin, limit + 4 * g, t)) &
                     in;
      for (; hit != 0; hit &= hit - 1) {
        const int c = __builtin_ctz(hit);
        note(4 * g + c, t[c], 0, 0, 0, i, lanes);
      }
    }
  }
  // A hit below the lane's limit: kept when nearer than its best, or at the best's depth when
  // the tie order gives it to this object.
  void note(int k, double t, int hitPart, double hitU, double hitV, uint32_t i, const PacketRays& lanes) {
    if (owner[k] != kNone &&
        !(ordered ? t < best[k] - reach[k].at(best[k]) || bvh.replacesHit(i, t, owner[k], best[k], lanes.ray(k))
                  : t < best[k]))
      return;
    best[k] = t;
    limit[k] = ordered ? std::max(nextUp(t), t + reach[k].at(t)) : t;
    part[k] = hitPart;
    u[k] = hitU;
    v[k] = hitV;
    owner[k] = i;
  }
  // The answers of the lanes of `live`.
  void write(uint64_t live, std::optional<ClosestHit>* out) const {
    for (uint64_t m = live; m != 0; m &= m - 1) {
      const int k = __builtin_ctzll(m);
      if (owner[k] == kNone) out[k].reset();
      else out[k] = ClosestHit{ShapeHit{best[k], part[k], u[k], v[k]}, owner[k]};
    }
  }
};

}  // namespace

void Bvh::closestPacket(const Ray* rays, int count, double tMin, double tMax, std::optional<ClosestHit>* out,
                        uint64_t& tests) const {
  PacketRays lanes;
  lanes.set(rays, count);
  const uint64_t all = count == 64 ? ~uint64_t(0) : (uint64_t(1) << count) - 1;
  LaneHits hits(lanes, all, tMax, *this);
  const double* best = hits.limit;  // what the walk prunes by
  auto other = [this](uint32_t i, const Ray& ray, double lo, double hi) { return intersectItem(i, ray, lo, hi); };
  LazySlabs slabs(lanes);
  // Unit directions from a common origin: the ray parameter t is the cone's s.
  Vec3 lo, hi;
  lanes.directionRange(lo, hi);
  const PacketCone cone(rays[0].origin, lo, hi, tMin);
  double farthest = tMax;  // the largest best[k]: beyond it no ray needs anything
  double unused[kBvhWidth];
  auto enters = [&](const BvhNode& n, unsigned candidates) {
    unsigned found = 0;
    for (int k = 0; k < count && found != candidates; ++k)
      found |= hitsChildren(n, slabs[k], tMin, best[k], unused) & candidates;
    return found;
  };
  // The unbounded primitives first, as in traverse().
  if (boundedCount_ < items_.size()) {
    for (uint32_t i = boundedCount_; i < items_.size(); ++i)
      hits.intersect(items_[i], i, lanes, all, tMin, tests, other);
    farthest = *std::max_element(best, best + count);
  }
  // A leaf's primitives are tested against every ray: four rays cost one vector test,
  // about what one ray's box test would cost to rule them out.
  traversePacket(cone, farthest, enters, [&](uint32_t first, uint32_t n, const BvhNode&, int) {
    for (uint32_t i = first; i < first + n; ++i) hits.intersect(items_[i], i, lanes, all, tMin, tests, other);
    farthest = *std::max_element(best, best + count);
    return false;
  });
  hits.write(all, out);
}

void Bvh::closestSpread(const PacketRays& lanes, uint64_t live, double tMin, double tMax,
                        std::optional<ClosestHit>* out, uint64_t& tests) const {
  LaneHits hits(lanes, live, tMax, *this);
  const double* best = hits.limit;  // what the walk prunes by
  auto other = [this](uint32_t i, const Ray& ray, double lo, double hi) { return intersectItem(i, ray, lo, hi); };
  // The unbounded primitives first, as in traverse().
  for (uint32_t i = boundedCount_; i < items_.size(); ++i)
    hits.intersect(items_[i], i, lanes, live, tMin, tests, other);
  if (!nodes_.empty() && live != 0) {
    // Each ray's own float slab test, as traverse() makes it: a node's child is entered
    // when one live ray enters it (the double test's boxes and more, never fewer).
    alignas(FloatRaySlabs) unsigned char storage[kMaxPacket * sizeof(FloatRaySlabs)];
    auto* slabs = reinterpret_cast<FloatRaySlabs*>(storage);  // only the live lanes' are made
    for (uint64_t m = live; m != 0; m &= m - 1) {
      const int k = __builtin_ctzll(m);
      new (&slabs[k]) FloatRaySlabs(lanes.ray(k));
    }
    const float tMinF = float(tMin);
    struct Entry {
      uint32_t index, count;  // a node, or (count > 0) a leaf's primitives
      float enter;            // the least of the rays' entries into its box
      uint64_t rays;          // the rays that enter its box (and every box above it)
    };
    Entry stack[kStackSize];
    int top = 0;
    Entry at{0, 0, tMinF, live};
    for (;;) {
      if (at.count > 0) {
        for (uint32_t i = at.index; i < at.index + at.count; ++i)
          hits.intersect(items_[i], i, lanes, at.rays, tMin, tests, other);
      } else {
        const BvhNode& n = nodes_[at.index];
        float enter[kBvhWidth];
        uint64_t entering[kBvhWidth] = {};
        std::fill(enter, enter + kBvhWidth, INFINITY);
        unsigned mask = 0;
        for (uint64_t m = at.rays; m != 0; m &= m - 1) {
          const int k = __builtin_ctzll(m);
          float e[kBvhWidth];
          const unsigned in = hitsNode(n, slabs[k], tMinF, float(best[k]), e);
          for (unsigned c = in; c != 0; c &= c - 1) {
            const int slot = __builtin_ctz(c);
            enter[slot] = std::min(enter[slot], e[slot]);
            entering[slot] |= uint64_t(1) << k;
          }
          mask |= in;
        }
        // The children entered, nearest on top of the stack.
        Entry hit[kBvhWidth];
        int h = 0;
        for (; mask != 0; mask &= mask - 1) {
          const int c = __builtin_ctz(mask);
          hit[h++] = {n.child[c], n.count[c], enter[c], entering[c]};
        }
        for (int i = 1; i < h; ++i)
          for (int j = i; j > 0 && hit[j - 1].enter < hit[j].enter; --j) std::swap(hit[j - 1], hit[j]);
        for (int i = 0; i < h; ++i) stack[top++] = hit[i];
      }
      // The next stacked child that some ray still enters before its best hit.
      float farthest = -INFINITY;
      for (uint64_t m = live; m != 0; m &= m - 1) farthest = std::max(farthest, float(best[__builtin_ctzll(m)]));
      const float limit = FloatRaySlabs::limit(farthest);
      while (top > 0 && stack[top - 1].enter > limit) --top;
      if (top == 0) break;
      at = stack[--top];
    }
  }
  hits.write(live, out);
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
                      Occlusion* out, uint32_t* blocker, uint64_t& tests, PacketNearest* nearest) const {
  const PrimitiveRecord& p = items_[i];
  if (p.noShadow) return;
  tests += uint64_t(__builtin_popcountll(live));
  const bool unbounded = i >= boundedCount_;
  auto record = [&](int k, const ShapeHit& h) {
    if (p.opaque) {
      out[k] = Occlusion::Blocked;
      blocker[k] = i;
      live &= ~(uint64_t(1) << k);
      return;
    }
    out[k] = Occlusion::Transparent;
    // Nearer, or as near and unbounded where the note is bounded (traverse() visits the
    // unbounded ones first, and keeps a later hit only when strictly nearer).
    if (nearest && (h.t < nearest->t[k] ||
                    (h.t == nearest->t[k] && unbounded && nearest->hit[k].primitive < boundedCount_))) {
      nearest->t[k] = h.t;
      nearest->hit[k] = {h, i};
    }
  };
  if (p.kind != PrimitiveRecord::Kind::Other) {
    double t[4];
    for (int g = 0; g < lanes.groups; ++g) {
      const unsigned group = unsigned(live >> (4 * g)) & 0xFu;
      if (group == 0) continue;
      unsigned hit = (p.kind == PrimitiveRecord::Kind::Sphere
                          ? intersectWorldSphere4(p.sphere, p.unit, lanes, 4 * g, tMin, tMax + 4 * g, t)
                          : hitPlane4(p.plane, p.unit, lanes, 4 * g, tMin, tMax + 4 * g, t)) &
                     group;
      for (; hit != 0; hit &= hit - 1) {
        const int c = __builtin_ctz(hit);
        record(4 * g + c, ShapeHit{t[c]});
      }
    }
    return;
  }
  for (uint64_t m = live; m != 0; m &= m - 1) {
    const int k = __builtin_ctzll(m);
    if (const auto h = intersectItem(i, lanes.ray(k), tMin, tMax[k])) record(k, *h);
  }
}

void Bvh::occludeLiveByUnbounded(const Vec3& apex, const PacketRays& lanes, const double* tMax, double tMin,
                                 uint64_t& live, Occlusion* out, uint32_t* blocker, uint64_t& tests,
                                 PacketNearest* nearest) const {
  for (uint32_t i = boundedCount_; i < items_.size() && live != 0; ++i) {
    const PrimitiveRecord& it = items_[i];
    const bool plane = it.kind == PrimitiveRecord::Kind::Plane && !it.noShadow;
    const uint64_t missed = plane ? planeMisses(it.plane, apex, lanes, live) : 0;
    uint64_t tested = live & ~missed;
    if (tested == 0) continue;
    occludeLive(i, lanes, tMax, tMin, tested, out, blocker, tests, nearest);
    live = tested | missed;
  }
}

void Bvh::occlusionPacket(const Vec3& apex, const PacketRays& lanes, const double* tMax, double tMin,
                          uint64_t live, Occlusion* out, uint32_t* blocker, uint64_t& tests,
                          PacketNearest* nearest) const {
  // From here on `live` holds the segments not yet blocked.
  std::fill(out, out + lanes.count, Occlusion::Clear);
  if (live == 0) return;
  if (nearest) std::fill(nearest->t, nearest->t + lanes.count, INFINITY);
  // The cone runs from the light back to each segment's start: s in [0, 1].
  Vec3 lo, hi;
  lanes.originRange(apex, lo, hi);
  occludeLiveInTree(PacketCone(apex, lo, hi, 0.0), 1.0, lanes, tMax, tMin, live, out, blocker, tests, nearest);
  occludeLiveByUnbounded(apex, lanes, tMax, tMin, live, out, blocker, tests, nearest);
}

void Bvh::occludeLiveInTree(const PacketCone& cone, double sHi, const PacketRays& lanes, const double* tMax,
                            double tMin, uint64_t& live, Occlusion* out, uint32_t* blocker, uint64_t& tests,
                            PacketNearest* nearest) const {
  LazySlabs slabs(lanes);
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
      occludeLive(i, lanes, tMax, tMin, live, out, blocker, tests, nearest);
    return live == 0;
  });
}

void Bvh::occlusionPacketFromPoint(const PacketRays& lanes, const double* tMax, double tMin, uint64_t live,
                                   Occlusion* out, uint32_t* blocker, uint64_t& tests,
                                   PacketNearest* nearest) const {
  std::fill(out, out + lanes.count, Occlusion::Clear);
  if (live == 0) return;
  if (nearest) std::fill(nearest->t, nearest->t + lanes.count, INFINITY);
  // The unbounded primitives first, as traverse() visits them (planeMisses needs a common
  // end, which these segments do not have).
  for (uint32_t i = boundedCount_; i < items_.size() && live != 0; ++i)
    occludeLive(i, lanes, tMax, tMin, live, out, blocker, tests, nearest);
  if (live == 0) return;
  // Unit directions from a common origin: the segments' parameter t is the cone's s.
  Vec3 lo, hi;
  lanes.directionRange(lo, hi);
  const int first = __builtin_ctzll(live);
  const PacketCone cone({lanes.ox[first], lanes.oy[first], lanes.oz[first]}, lo, hi, tMin);
  double sHi = -INFINITY;
  for (uint64_t m = live; m != 0; m &= m - 1) sHi = std::max(sHi, tMax[__builtin_ctzll(m)]);
  occludeLiveInTree(cone, sHi, lanes, tMax, tMin, live, out, blocker, tests, nearest);
}

void Bvh::occlusionPacketInCell(const LightBuffer& buffer, int cell, double reach, const PacketRays& lanes,
                                const double* tMax, double tMin, uint64_t live, Occlusion* out, uint32_t* blocker,
                                uint64_t& tests, PacketNearest* nearest) const {
  std::fill(out, out + lanes.count, Occlusion::Clear);
  if (nearest) std::fill(nearest->t, nearest->t + lanes.count, INFINITY);
  for (const LightBuffer::Entry& e : buffer.list(cell)) {
    if (e.near > reach || live == 0) break;
    occludeLive(e.primitive, lanes, tMax, tMin, live, out, blocker, tests, nearest);
  }
  for (uint32_t i : buffer.everywhere())
    if (live != 0) occludeLive(i, lanes, tMax, tMin, live, out, blocker, tests, nearest);
  occludeLiveByUnbounded(buffer.light(), lanes, tMax, tMin, live, out, blocker, tests, nearest);
}

}  // namespace pvrt
