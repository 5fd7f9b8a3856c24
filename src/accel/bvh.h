// Bounding volume hierarchy over the bounded primitives of a scene: a binned-SAH binary
// tree collapsed into a wide one (kBvhWidth children a node).
// Built once, then immutable: shared read-only by every thread. Unbounded primitives
// (planes) are kept aside and tested on every ray.
#pragma once

#include <cmath>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "accel/light_buffer.h"
#include "accel/packet.h"
#include "accel/packet_rays.h"
#include "accel/tie_order.h"
#include "geometry/primitive.h"
#include "geometry/primitive_store.h"

namespace pvrt {

// The most primitives a leaf of the SAH tree holds, and of a cheaper tree (Bvh's leafSize).
inline constexpr uint32_t kBvhLeafSize = 4;
inline constexpr uint32_t kBvhMaxLeafSize = 255;  // BvhNode::count

struct BvhStats {
  uint64_t nodes = 0;   // wide nodes
  uint32_t leafSize = kBvhLeafSize;  // what it was built with
  uint64_t leaves = 0;  // leaf children (runs of at most four primitives)
  int maxDepth = 0;     // in wide nodes, counting a leaf as a level
  uint64_t bytes = 0;
  double buildSeconds = 0;
};

// A node of the wide tree: the boxes of up to kBvhWidth children side by side, in groups of
// four ("quads", one array per axis and side), so that one ray tests four children with a
// handful of vector operations and a tree of N primitives is about log8(N) deep. The bounds
// are floats rounded outward: a box never shrinks, so every answer stays exactly the one the
// double-precision box would give. An unused slot holds an empty box.
inline constexpr int kBvhWidth = 8;
inline constexpr int kBvhQuads = kBvhWidth / 4;
struct alignas(64) BvhNode {
  struct Quad {
    float lo[3][4];  // [axis][child]
    float hi[3][4];
  };
  Quad quad[kBvhQuads];  // children 4q .. 4q+3
  // Interior child: its node index. Leaf child: its first primitive.
  uint32_t child[kBvhWidth] = {};
  uint8_t count[kBvhWidth] = {};  // primitives of a leaf child; 0 for an interior one
  uint8_t used = 0;               // children in slots [0, used)

  BvhNode();
  void setChild(int slot, const Bounds& b, uint32_t index, uint8_t leafCount);
  Bounds childBounds(int slot) const {
    const Quad& q = quad[slot / 4];
    const int c = slot % 4;
    return {{double(q.lo[0][c]), double(q.lo[1][c]), double(q.lo[2][c])},
            {double(q.hi[0][c]), double(q.hi[1][c]), double(q.hi[2][c])}};
  }
  int quads() const { return (used + 3) / 4; }
};
static_assert(sizeof(BvhNode) % 64 == 0);

struct ClosestHit {
  ShapeHit hit;
  uint32_t primitive = 0;
};

// What a shadow segment meets, in no particular order.
enum class Occlusion { Clear, Blocked, Transparent };

// The packet shadow queries' note of each segment's nearest see-through hit. A segment
// answered Transparent has had every primitive it can meet tested over its whole interval,
// so this is the first step of its see-through walk (closest(..., skipNoShadow = true) over
// the same interval), found without walking the tree again: an unbounded primitive wins a
// tie, as traverse() visits those first. Only the Transparent lanes' entries mean anything.
struct PacketNearest {
  double t[kMaxPacket];
  ClosestHit hit[kMaxPacket];
};

class Bvh {
 public:
  Bvh() = default;
  // Takes the primitives and reorders them for locality. The build uses up to
  // `buildThreads` threads (0: threadBudget()); the tree is the same whatever the number.
  // `leafSize` above kBvhLeafSize (up to kBvhMaxLeafSize) makes a cheaper tree: every node of
  // that many primitives or fewer is a leaf, so there are far fewer nodes (for a memory
  // limit the SAH's tree does not fit in), and rays test more primitives.
  explicit Bvh(PrimitiveStore primitives, unsigned buildThreads = 0, uint32_t leafSize = kBvhLeafSize);
  explicit Bvh(std::vector<Primitive> primitives, unsigned buildThreads = 0, uint32_t leafSize = kBvhLeafSize)
      : Bvh(PrimitiveStore(std::move(primitives)), buildThreads, leafSize) {}

  // The primitives, bounded ones first in the leaves' order, then the unbounded ones.
  size_t size() const { return items_.size(); }
  bool empty() const { return items_.empty(); }
  // The bounded primitives are [0, boundedCount()), the unbounded ones the rest.
  uint32_t boundedCount() const { return boundedCount_; }
  // Primitive i whole: a copy, made again from its record for a sphere or a plane (for
  // tests and tools; the queries below read the records).
  Primitive primitive(uint32_t i) const;
  const BvhStats& stats() const { return stats_; }
  // Gives the primitives back (in the tree's order), leaving this empty: to build again.
  PrimitiveStore release() &&;
  const std::vector<BvhNode>& nodes() const { return nodes_; }
  // How the closest-hit queries (closest, closestPacket, closestSpread) decide between two
  // objects met at exactly one depth, as POV-Ray does (accel/tie_order.h); by default the
  // hit found first is kept. The see-through walks of shadows keep the first found.
  void setTieRule(TieRule rule);
  TieRule tieRule() const { return tieRule_; }
  // How far from a hit at depth t the tie rule may still prefer another object's hit, for
  // one ray: at(t). Beyond it the nearer hit wins in both renderers. Made once per ray.
  struct TieReach {
    double scale = 0, base = 0;
    double at(double t) const { return scale * (t + base); }
  };
  TieReach tieReach(const Ray& ray) const;
  // Whether a hit on primitive `found` at depth tFound replaces the kept hit on primitive
  // `kept` at tKept, for hits within reach of each other (TieReach): at one depth, or where
  // POV-Ray's tree would test them in the other order or stop before the nearer one.
  bool replacesHit(uint32_t found, double tFound, uint32_t kept, double tKept, const Ray& ray) const;

  // What shading needs of primitive i (0 <= i < size()), read from its compact record where
  // that has it, so that a hit on one of a million spheres fetches 48 bytes: the same
  // answers as the Primitive's.
  uint32_t material(uint32_t i) const { return items_[i].material; }
  // Primitive i's shape when it is an untransformed sphere or plane (the shapes whose
  // shading queries the leaf records answer), else null.
  const SphereShape* sphere(uint32_t i) const {
    return items_[i].kind == PrimitiveRecord::Kind::Sphere ? &items_[i].sphere : nullptr;
  }
  const PlaneShape* plane(uint32_t i) const {
    return items_[i].kind == PrimitiveRecord::Kind::Plane ? &items_[i].plane : nullptr;
  }
  uint32_t object(uint32_t i) const { return items_[i].object; }
  // Whether the object primitive i belongs to is hit in [tMin, tMax): primitive i alone, or
  // every primitive of a mesh (POV-Ray's shadow cache tries its cached object so, and a mesh
  // is one object there). `tests` counts the intersection tests. As POV-Ray's
  // FindIntersection(object, ...) does, the object is tested alone: its own Intersect_BBox,
  // but none of the bounding tree's float slabs, which can turn away a ray that grazes an
  // edge the object's own test hits (blind14: a shadow ray through a box's edge).
  bool objectHit(uint32_t i, const Ray& ray, double tMin, double tMax, uint64_t& tests) const;
  std::optional<ShapeHit> intersect(uint32_t i, const Ray& ray, double tMin, double tMax) const {
    return intersectItem(i, ray, tMin, tMax);
  }
  SurfacePoint surfacePoint(uint32_t i, const Ray& ray, const ShapeHit& hit) const {
    const PrimitiveRecord& it = items_[i];
    switch (it.kind) {
      case PrimitiveRecord::Kind::Sphere: return sphereHitPoint(it.sphere, ray.at(hit.t));
      case PrimitiveRecord::Kind::Plane: return planeHitPoint(it.plane, ray.at(hit.t));
      case PrimitiveRecord::Kind::Other: break;
    }
    return others_[it.other].surfacePoint(ray, hit);
  }
  Vec3 normal(uint32_t i, const Ray& ray, const ShapeHit& hit) const {
    const PrimitiveRecord& it = items_[i];
    switch (it.kind) {
      case PrimitiveRecord::Kind::Sphere: return sphereNormal(it.sphere, ray.at(hit.t));
      case PrimitiveRecord::Kind::Plane: return it.plane.normal;
      case PrimitiveRecord::Kind::Other: break;
    }
    return others_[it.other].normal(ray, hit);
  }

  // Nearest hit in (tMin, tMax). `tests` is increased by the number of primitive
  // intersection tests performed; `skipNoShadow` ignores no_shadow objects.
  std::optional<ClosestHit> closest(const Ray& ray, double tMin, double tMax, uint64_t& tests,
                                    bool skipNoShadow = false) const;

  // The cheap query for shadow rays (no_shadow primitives ignored): Blocked as soon as
  // any opaque primitive is hit in (tMin, tMax), else Transparent when only see-through
  // ones are, else Clear. No nearest-hit ordering, so traversal stops early.
  // `blocker` receives the opaque primitive found.
  Occlusion occlusion(const Ray& ray, double tMin, double tMax, uint64_t& tests, uint32_t& blocker) const;

  // occlusion() for a segment that ends at `buffer`'s light, found from the buffer's cell
  // instead of the tree. Every point of the segment must lie within LightBuffer::kMargin
  // radians of the light's ray along -ray.dir, and no farther than `reach` from the light.
  Occlusion occlusionToLight(const LightBuffer& buffer, const Ray& ray, double tMin, double tMax, double reach,
                             uint64_t& tests, uint32_t& blocker) const;
  // The same from a cell found beforehand: `cell` is buffer.cellIndexOf(u) (not -1) for a
  // direction u such that every point of the segment lies within kMargin radians of the
  // light's ray along u (-ray.dir itself, or one a few ulps off it).
  Occlusion occlusionToLight(const LightBuffer& buffer, int cell, const Ray& ray, double tMin, double tMax,
                             double reach, uint64_t& tests, uint32_t& blocker) const;
  // The same, and when the answer is Transparent, the nearest see-through hit in `nearest`:
  // every candidate shadowCandidates would list for the segment has been tested, so this is
  // closestAmong's answer for it, the first step of its see-through walk, ties included
  // (unbounded primitives first, then the cell's list in order, then the everywhere ones).
  Occlusion occlusionToLight(const LightBuffer& buffer, int cell, const Ray& ray, double tMin, double tMax,
                             double reach, uint64_t& tests, uint32_t& blocker, ClosestHit& nearest) const;
  // The same, and, when the answer is Transparent, in `candidates` what shadowCandidates(buffer,
  // cell, ray, length, reach, drift, candidates) would list (read from the cell while the
  // query tests it, instead of in a second pass): the first step's candidates of the walk.
  Occlusion occlusionToLight(const LightBuffer& buffer, int cell, const Ray& ray, double tMin, double tMax,
                             double reach, uint64_t& tests, uint32_t& blocker, ClosestHit& nearest, double length,
                             double drift, std::vector<uint32_t>& candidates) const;
  // For a walk of shadow segments along one line toward `buffer`'s light (see-through
  // surfaces crossed one by one, each segment starting where the last one stopped): the
  // shadow-casting primitives any of them may meet. Each segment must meet
  // occlusionToLight's conditions (`reach` included), start within `drift` of `ray`'s line
  // and be no longer than `length`. They are the cell's listed primitives but the spheres
  // that the line passes by so far that no such segment could reach them, then the ones
  // tested everywhere. False when the direction has no cell.
  bool shadowCandidates(const LightBuffer& buffer, const Ray& ray, double length, double reach, double drift,
                        std::vector<uint32_t>& out) const;
  // The same from a cell found beforehand, as occlusionToLight's overload takes it.
  void shadowCandidates(const LightBuffer& buffer, int cell, const Ray& ray, double length, double reach,
                        double drift, std::vector<uint32_t>& out) const;
  // closest(..., skipNoShadow = true) among `candidates` and the unbounded primitives: for a
  // segment of the walk above, the same nearest hit (but for a hit at exactly the distance
  // of another, which may be the other one).
  std::optional<ClosestHit> closestAmong(std::span<const uint32_t> candidates, const Ray& ray, double tMin,
                                         double tMax, uint64_t& tests) const;
  // The bounded primitives as light buffers see them, in the order of primitive(i): their
  // boxes, and the balls of untransformed spheres.
  std::vector<LightBuffer::Occluder> occluders() const;

  // closest() for each of `count` (<= kMaxPacket) unit-direction rays that all start at
  // the same point. Gives for every ray the same answer as closest() would.
  void closestPacket(const Ray* rays, int count, double tMin, double tMax, std::optional<ClosestHit>* out,
                     uint64_t& tests) const;
  // closest() for the rays of `rays` with a bit in `live`, each from its own origin (the
  // reflected or refracted rays of a packet's hits): one walk of the tree for them all,
  // a node's child entered where one live ray's own slab test enters it, a leaf's spheres
  // and planes tested four rays at a time. out[k] is set for the live rays only, each to
  // closest()'s answer (but for a hit at exactly the distance of another, which may be
  // the other one).
  void closestSpread(const PacketRays& rays, uint64_t live, double tMin, double tMax,
                     std::optional<ClosestHit>* out, uint64_t& tests) const;
  // occlusion() for each of `count` (<= kMaxPacket) segments that all end at `apex` (a
  // light): segment k runs from segments[k].origin along its unit direction over
  // (tMin, tMax[k]), with segments[k].origin + dir * (tMax[k] + tMin) = apex.
  void occlusionPacket(const Vec3& apex, const Ray* segments, const double* tMax, int count, double tMin,
                       Occlusion* out, uint32_t* blocker, uint64_t& tests) const;
  // The same for segments given a component per array; tMax has a lane for each of
  // segments.groups * 4, and -infinity in the padding ones. Only the segments with a bit
  // in `live` are tested (the others come out Clear); the others' origins must be NaN,
  // as the padding's are, so that the packet's bounds leave them out.
  void occlusionPacket(const Vec3& apex, const PacketRays& segments, const double* tMax, double tMin,
                       uint64_t live, Occlusion* out, uint32_t* blocker, uint64_t& tests,
                       PacketNearest* nearest = nullptr) const;
  // occlusion() for segments that all start at one point (the area-light samples of a hit
  // point, whose ends differ): segment k runs from that origin (every live lane's) along its
  // unit direction over (tMin, tMax[k]). Live lanes and padding as above. `nearest`, when
  // given, receives the Transparent segments' nearest see-through hits (for all three).
  void occlusionPacketFromPoint(const PacketRays& segments, const double* tMax, double tMin, uint64_t live,
                                Occlusion* out, uint32_t* blocker, uint64_t& tests,
                                PacketNearest* nearest = nullptr) const;
  // The same for live segments that all lie in one cell of the light's buffer, `cell`
  // (each meeting occlusionToLight's conditions, `reach` the largest of theirs): the cell's
  // list is tested against the packet instead of the tree walked.
  void occlusionPacketInCell(const LightBuffer& buffer, int cell, double reach, const PacketRays& segments,
                             const double* tMax, double tMin, uint64_t live, Occlusion* out, uint32_t* blocker,
                             uint64_t& tests, PacketNearest* nearest = nullptr) const;

 private:
  // What shadowCandidates' walks need of a query's cell: the line's length and drift, and
  // where the candidates go.
  struct Listing {
    double length, drift;
    std::vector<uint32_t>* out;
  };
  template <bool kNoteNearest>
  Occlusion occlusionInCell(const LightBuffer& buffer, int cell, const Ray& ray, double tMin, double tMax, double reach,
                            uint64_t& tests, uint32_t& blocker, ClosestHit* nearest,
                            const Listing* listing = nullptr) const;
  // Whether shadowCandidates lists primitive i for a walk along `ray`'s line: not a
  // no_shadow one, nor a sphere that the line passes by so far that no step can reach it.
  bool candidate(uint32_t i, const Ray& ray, double length, double drift) const;
  template <class Enters, class Leaf>
  void traversePacket(const PacketCone& cone, const double& sHi, Enters&& enters, Leaf&& leaf) const;
  // The shadow queries' test of primitive i: true when it is opaque and hit in (tMin, tMax)
  // (then `blocker` is i); a see-through hit sets `transparent`; no_shadow ones are skipped.
  bool blocks(uint32_t i, const Ray& ray, double tMin, double tMax, uint64_t& tests, bool& transparent,
              uint32_t& blocker) const;
  // The packet shadow queries' test of primitive i (no_shadow ones skipped) against the
  // segments in `live`, four at a time for a sphere or a plane: a segment that meets i is
  // Blocked by it, and leaves `live`, when i is opaque, else Transparent.
  // A see-through hit nearer than a lane's note in `nearest` (when given) replaces it.
  void occludeLive(uint32_t i, const PacketRays& segments, const double* tMax, double tMin, uint64_t& live,
                   Occlusion* out, uint32_t* blocker, uint64_t& tests, PacketNearest* nearest) const;
  // The bounded primitives' part of the packet shadow queries: the walk of the tree within
  // `cone` (up to its parameter sHi), each node entered where a live segment's box test
  // enters it, each leaf's primitives tested against every live segment.
  void occludeLiveInTree(const PacketCone& cone, double sHi, const PacketRays& segments, const double* tMax,
                         double tMin, uint64_t& live, Occlusion* out, uint32_t* blocker, uint64_t& tests,
                         PacketNearest* nearest) const;
  // The unbounded primitives' part of the packet shadow queries.
  void occludeLiveByUnbounded(const Vec3& apex, const PacketRays& segments, const double* tMax, double tMin,
                              uint64_t& live, Occlusion* out, uint32_t* blocker, uint64_t& tests,
                              PacketNearest* nearest) const;
  // Puts others_ in the order of the records that point to them (the build's last step).
  void followRecords(int threads);
  // Sets sharesObject on the records of objects made of several primitives.
  void markSharedObjects();
  // Makes the povTie* members below (the build's last step).
  void makePovTieRoot();
  template <class Visit>
  void traverse(const Ray& ray, double tMin, const double& tMax, Visit&& visit) const;

  std::optional<ShapeHit> intersectItem(uint32_t i, const Ray& ray, double tMin, double tMax,
                                        Primitive::Reach reach = Primitive::Reach::ThroughTree) const {
    const PrimitiveRecord& it = items_[i];
    switch (it.kind) {
      case PrimitiveRecord::Kind::Sphere: return intersectWorldSphere(it.sphere, it.unit, ray, tMin, tMax);
      case PrimitiveRecord::Kind::Plane: return detail::hitPlane(it.plane, ray, tMin, tMax, it.unit);
      case PrimitiveRecord::Kind::Other: break;
    }
    std::optional<ShapeHit> hit = others_[it.other].intersect(ray, tMin, tMax, reach);
    if (hit && reach == Primitive::Reach::ThroughTree && i < povAbove_.size() && !povPassesNodesAbove(i, ray))
      return std::nullopt;
    return hit;
  }

  std::vector<PrimitiveRecord> items_;  // one per primitive: bounded ones first, then unbounded
  std::vector<Primitive> others_;       // the Kind::Other ones' shapes, in the order of their records
  uint32_t boundedCount_ = 0;
  std::vector<BvhNode> nodes_;
  BvhStats stats_;
  TieRule tieRule_ = TieRule::FirstFound;
  double tieExtent_ = 0;  // the largest coordinate of the bounded primitives' boxes (for tieReach)
  // POV-Ray's bounding-tree root, for hits at one depth with equal keys (replacesHit), known
  // for scenes of at most 1024 bounded primitives, one an object, whose POV-Ray boxes pvrt has.
  bool povTieKnown_ = false;
  bool povTieRootHoldsObjects_ = false;   // no node among the root's entries
  std::vector<uint32_t> povTieObjects_;   // the finite objects, in declaration order
  std::vector<PovBBox> povTieRootBoxes_;  // the root's entries' boxes
  std::vector<int> povTieRootEntries_;    // and what each is: an index into povTieObjects_, or -1 for a node
  // For each bounded primitive kept whole (Kind::Other), the float boxes of the nodes above its
  // object in POV-Ray's tree, which a ray must pass too (povBBoxTree); empty where the tree is
  // not known or not built (setTieRule).
  std::vector<std::vector<PovBBox>> povAbove_;
  bool povPassesNodesAbove(uint32_t i, const Ray& ray) const;
};

}  // namespace pvrt
