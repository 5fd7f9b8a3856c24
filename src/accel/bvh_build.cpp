// The BVH's build: a binned-SAH binary tree (centroids sorted into bins per axis, the
// cheapest split kept), collapsed into the wide one.
//
// Every thread count builds the same tree, bit for bit. The nodes big enough to share (the
// top of the tree) are built a level at a time by all the threads together: each pass over
// their items (boxes, bins, partition) is cut into blocks whose results are combined in block
// order, and combine exactly (a box's min and max, a bin's count), so that they are what one
// pass over all the items gives. The subtrees below them are then built at the same time,
// each by one thread, into slots set aside for them, and collapsed at the same time.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <new>
#include <numeric>
#include <type_traits>

#include "accel/bvh.h"

#include "accel/pov_bbox_root.h"
#include "core/lanes.h"
#include "core/prefault.h"
#include "core/interrupt.h"
#include "parallel/parallel_for.h"
#include "parallel/permute.h"

namespace pvrt {

namespace {

constexpr int kBins = 16;
constexpr uint32_t kMaxLeafSize = kBvhLeafSize;  // the SAH's largest leaf
constexpr int kMaxSahDepth = 48;  // beyond it, median splits bound the depth (stack of 64)
constexpr double kTraversalCost = 1.0;  // relative to one primitive test
constexpr double kIntersectionCost = 1.0;
// A node of at least this many items, and at least 1/(8 x threads) of them all, is built by all
// threads together; below it a subtree is built by one thread.
constexpr uint32_t kSharedItems = 20000;
constexpr size_t kGrain = 4096;  // the fewest items of a block of a pass over a shared node

// n elements of T, left unwritten: the threads that fill them touch their pages first, rather
// than one thread initialising them all beforehand. T is a scalar or an aggregate with a
// trivial destructor (an implicit-lifetime type), so the storage holds T objects once allocated.
template <class T>
class RawArray {
  static_assert((std::is_scalar_v<T> || std::is_aggregate_v<T>) && std::is_trivially_destructible_v<T>);

 public:
  explicit RawArray(size_t n) : data_(static_cast<T*>(std::malloc(std::max<size_t>(n, 1) * sizeof(T)))), size_(n) {
    if (!data_) throw std::bad_alloc();
  }
  T& operator[](size_t i) { return data_.get()[i]; }
  const T& operator[](size_t i) const { return data_.get()[i]; }
  T* begin() { return data_.get(); }
  size_t size() const { return size_; }
  void shrink(size_t n) { size_ = std::min(size_, n); }  // keeps the first n

 private:
  struct Free {
    void operator()(T* p) const { std::free(p); }
  };
  std::unique_ptr<T, Free> data_;
  size_t size_;
};

// A node of the binary tree the build makes before it is collapsed.
struct BuildNode {
  Bounds bounds;
  uint32_t rightOrFirst = 0;  // interior: right child (the left one is next); leaf: first primitive
  uint32_t count = 0;         // 0 for interior nodes
};

// A primitive's box and centroid as the build sees them: with every -0 made +0, so that a
// box's min and max over any items are the same whatever order the items come in (the
// extremes' zeros would otherwise keep the sign of whichever came first).
struct BuildItem {
  Bounds bounds;
  Vec3 centroid;
  uint32_t index;
};

Vec3 positiveZero(const Vec3& v) { return {v.x + 0.0, v.y + 0.0, v.z + 0.0}; }

// Bounds.extend() a vector at a time, for the build's passes over millions of items: the
// min and max of all three axes in one operation each. A NaN in an item leaves the box as
// it was, as Bounds.extend() does, so the tree is the same. Loads four doubles from each
// Vec3 of a BuildItem (the fourth, the next field, is ignored).
//
// A bound changes only for a value below (above) it, never for an equal one (a zero of the
// other sign): the box holds the first of the items' extreme values, whichever way they are
// cut into blocks, as long as the blocks' boxes are merged in block order.
struct BuildBox {
  lanes::Double4 lo = lanes::splat(INFINITY), hi = lanes::splat(-INFINITY);
  void extend(const Vec3& lo3, const Vec3& hi3) {
    lo = lanes::minOr(lanes::load(&lo3.x), lo);
    hi = lanes::maxOr(lanes::load(&hi3.x), hi);
  }
  // `later`'s items follow this box's.
  void merge(const BuildBox& later) {
    lo = lanes::minOr(later.lo, lo);
    hi = lanes::maxOr(later.hi, hi);
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

// A node's box and the box of its items' centroids.
struct NodeBoxes {
  BuildBox box, centroids;
  void add(const BuildItem& it) {
    box.extend(it.bounds.lo, it.bounds.hi);
    centroids.extend(it.centroid, it.centroid);
  }
  void merge(const NodeBoxes& later) {
    box.merge(later.box);
    centroids.merge(later.centroids);
  }
};

// Where a node's items fall along each axis: kBins bins over its centroids' extent.
class Binning {
 public:
  explicit Binning(const Bounds& centroids) {
    for (int axis = 0; axis < 3; ++axis) {
      lo_[axis] = centroids.lo[axis];
      const double extent = centroids.hi[axis] - lo_[axis];
      binned_[axis] = extent > 0;
      scale_[axis] = binned_[axis] ? kBins / extent : 0;
    }
  }
  bool binned(int axis) const { return binned_[axis]; }
  int bin(const BuildItem& it, int axis) const {
    return std::min(kBins - 1, int((it.centroid[axis] - lo_[axis]) * scale_[axis]));
  }

 private:
  bool binned_[3];
  double lo_[3], scale_[3];
};

// Every axis's bins, filled in one pass over the items (a pass an axis read them three times).
// A bin's box is set up only when its first item comes (deep in the tree most bins stay
// empty, and setting up all 48 boxes of every node was a tenth of the build); an empty bin's
// box is never read.
struct Bins {
  std::array<std::array<uint32_t, kBins>, 3> count{};
  Bins() {}  // the boxes are left unset
  BuildBox& box(size_t axis, size_t b) { return boxes_[axis][b]; }
  const BuildBox& box(size_t axis, size_t b) const { return boxes_[axis][b]; }
  void add(const Binning& binning, const BuildItem& it) {
    for (int axis = 0; axis < 3; ++axis) {
      if (!binning.binned(axis)) continue;
      const size_t b = size_t(binning.bin(it, axis));
      if (count[size_t(axis)][b]++ == 0) boxes_[size_t(axis)][b] = BuildBox();
      boxes_[size_t(axis)][b].extend(it.bounds.lo, it.bounds.hi);
    }
  }
  void merge(const Bins& later) {
    for (size_t axis = 0; axis < 3; ++axis)
      for (size_t b = 0; b < kBins; ++b) {
        if (later.count[axis][b] == 0) continue;
        if (count[axis][b] == 0) boxes_[axis][b] = later.boxes_[axis][b];
        else boxes_[axis][b].merge(later.boxes_[axis][b]);
        count[axis][b] += later.count[axis][b];
      }
  }

 private:
  union {
    std::array<std::array<BuildBox, kBins>, 3> boxes_;  // valid where count > 0
  };
};

// The cheapest split between bins: axis -1 when no split leaves items on both sides.
struct BinSplit {
  int axis = -1, bin = 0;
  double cost = INFINITY;  // area x count summed over both sides
};

// Bounds::surfaceArea() of the box [lo, hi] (lanes 0-2), with the same operations.
double surfaceArea(lanes::Double4 lo, lanes::Double4 hi) {
  double l[4], h[4];
  lanes::store(l, lo);
  lanes::store(h, hi);
  if (l[0] > h[0] || l[1] > h[1] || l[2] > h[2]) return 0;
  const double ex = h[0] - l[0], ey = h[1] - l[1], ez = h[2] - l[2];
  return 2 * (ex * ey + ey * ez + ez * ex);
}

BinSplit cheapest(const Bins& bins, const Binning& binning) {
  BinSplit best;
  for (int axis = 0; axis < 3; ++axis) {
    if (!binning.binned(axis)) continue;
    const auto& binCount = bins.count[size_t(axis)];
    // Only the bins that hold items: an empty bin changes neither side's box nor its count,
    // so the split just after it costs exactly what the split before it costs, and never
    // wins (only a strictly cheaper split replaces the best). Deep in the tree most of a
    // node's bins are empty.
    std::array<int, kBins> used;
    int m = 0;
    for (int b = 0; b < kBins; ++b)
      if (binCount[size_t(b)] > 0) used[size_t(m++)] = b;
    if (m < 2) continue;
    // Sweep from the right to get the cost of every right side, then from the left. The
    // boxes grow a lane vector at a time, as Bounds::extend() would grow them (a bound
    // changes only for a value beyond it; no bin's box holds a NaN).
    std::array<double, kBins> rightArea;
    std::array<uint32_t, kBins> rightCount;
    BuildBox acc;
    uint32_t n = 0;
    for (int k = m - 1; k > 0; --k) {
      acc.merge(bins.box(size_t(axis), size_t(used[size_t(k)])));
      n += binCount[size_t(used[size_t(k)])];
      rightArea[size_t(k)] = surfaceArea(acc.lo, acc.hi);
      rightCount[size_t(k)] = n;
    }
    acc = BuildBox();
    n = 0;
    for (int k = 0; k < m - 1; ++k) {
      acc.merge(bins.box(size_t(axis), size_t(used[size_t(k)])));
      n += binCount[size_t(used[size_t(k)])];
      const double cost = surfaceArea(acc.lo, acc.hi) * n + rightArea[size_t(k + 1)] * rightCount[size_t(k + 1)];
      if (cost < best.cost) best = {axis, used[size_t(k)], cost};
    }
  }
  return best;
}

// The passes over a node's items, on the calling thread alone.
class SerialPasses {
 public:
  explicit SerialPasses(BuildItem* items) : items_(items) {}

  NodeBoxes boxes(uint32_t begin, uint32_t end) const {
    NodeBoxes b;
    for (uint32_t i = begin; i < end; ++i) b.add(items_[i]);
    return b;
  }
  Bins bins(uint32_t begin, uint32_t end, const Binning& binning) const {
    Bins bins;
    for (uint32_t i = begin; i < end; ++i) bins.add(binning, items_[i]);
    return bins;
  }
  // Moves the items for which `left` holds before the others and returns where those start;
  // adds each item to the boxes of its side as it goes (each once), so that the two halves'
  // boxes need no pass of their own. The order is std::partition's (libstdc++'s, as the tree
  // was first built): the first item out of place from the left is swapped with the first
  // from the right, and so on. The boxes are those of a pass over each half in order, since
  // no item holds a NaN-free -0 (BuildItem) and min and max are then indifferent to order.
  template <class Left>
  uint32_t partition(uint32_t begin, uint32_t end, Left&& left, NodeBoxes& lefts, NodeBoxes& rights) const {
    for (;;) {
      while (begin != end && left(items_[begin])) lefts.add(items_[begin++]);
      if (begin == end) return begin;
      --end;
      while (begin != end && !left(items_[end])) rights.add(items_[end--]);
      if (begin == end) {
        rights.add(items_[begin]);  // stopped the first loop: it goes right
        return begin;
      }
      std::swap(items_[begin], items_[end]);
      lefts.add(items_[begin++]);
      rights.add(items_[end]);
    }
  }

 private:
  BuildItem* items_;
};

}  // namespace

namespace {

// What becomes of a node: a leaf, two halves of its items as they lie, or its items
// partitioned at the cheapest split between bins (`best`).
enum class Cut { Leaf, Half, Partition };

Cut choose(const Bins& bins, const Binning& binning, const Bounds& bounds, uint32_t count, uint32_t leafSize,
           BinSplit& best) {
  // A cheaper tree (Bvh's leafSize above the SAH's): every node that small is a leaf.
  if (leafSize > kMaxLeafSize && count <= leafSize) return Cut::Leaf;
  best = cheapest(bins, binning);
  // All centroids coincide: split in the middle if the leaf would be too big.
  if (best.axis < 0) return count <= kMaxLeafSize ? Cut::Leaf : Cut::Half;
  const double area = bounds.surfaceArea();
  const double splitCost = kTraversalCost + (area > 0 ? kIntersectionCost * best.cost / area : INFINITY);
  if (count <= kMaxLeafSize && splitCost >= kIntersectionCost * count) return Cut::Leaf;
  return Cut::Partition;
}

// Where median splits cut a node at depth kMaxSahDepth or more (having reordered its items),
// or `end` to make it a leaf.
uint32_t median(BuildItem* items, uint32_t begin, uint32_t end, const Bounds& centroids, uint32_t leafSize) {
  if (end - begin <= std::max(leafSize, kMaxLeafSize)) return end;
  const int axis = centroids.longestAxis();
  const uint32_t mid = begin + (end - begin) / 2;
  std::nth_element(items + begin, items + mid, items + end,
                   [&](const BuildItem& a, const BuildItem& b) { return a.centroid[axis] < b.centroid[axis]; });
  return mid;
}

// The nodes of the tree's top: those of at least `shared` items, made a level at a time by
// all threads together. Each pass over a level (boxes, bins, partition) is one parallel loop
// over the blocks of all its nodes, at least kGrain items each; a node's results are combined
// in its blocks' order. The partition puts the items where SerialPasses::partition would:
// with m = begin + (items going left), the k-th item of [begin, m) that goes right (from the
// left) trades places with the k-th of [m, end) that goes left (from the right).
class TopLevels {
 public:
  struct Node {
    uint32_t begin, end;
    int depth;
    Bounds bounds;
    uint32_t mid = 0;             // where its items are cut in two; `end` for a leaf
    int32_t child[2] = {-1, -1};  // into nodes(); -1: a subtree of fewer than `shared` items
  };

  TopLevels(BuildItem* items, uint32_t count, uint32_t shared, int threads, uint32_t leafSize)
      : items_(items), shared_(shared), threads_(threads), leafSize_(leafSize), binOf_{RawArray<uint8_t>(count), RawArray<uint8_t>(count),
                                                                  RawArray<uint8_t>(count)},
        scratch_(count) {
    nodes_.push_back({0, count, 1, {}});
    for (std::vector<uint32_t> level{0}; !level.empty();) level = split(level);
  }
  const std::vector<Node>& nodes() const { return nodes_; }

 private:
  // A node's block of items.
  struct Piece {
    uint32_t node;  // its index in the level
    uint32_t lo, hi;
  };

  // Splits the level's nodes, and returns the next level's.
  std::vector<uint32_t> split(const std::vector<uint32_t>& level) {
    std::vector<Piece> pieces;
    std::vector<size_t> firstPiece{0};
    for (uint32_t k = 0; k < level.size(); ++k) {
      const Node& n = nodes_[level[k]];
      const Blocks blocks(n.end - n.begin, threads_, kGrain);
      for (size_t b = 0; b < blocks.count; ++b)
        pieces.push_back({k, n.begin + uint32_t(blocks.begin(b)), n.begin + uint32_t(blocks.end(b))});
      firstPiece.push_back(pieces.size());
    }
    const auto pieceRange = [&](uint32_t k) { return std::pair{firstPiece[k], firstPiece[k + 1]}; };

    std::vector<NodeBoxes> boxes(pieces.size());
    parallelIndices(pieces.size(), threads_, [&](size_t p) {
      boxes[p] = SerialPasses(items_).boxes(pieces[p].lo, pieces[p].hi);
    });
    std::vector<Binning> binnings;
    std::vector<Bounds> centroids;
    for (uint32_t k = 0; k < level.size(); ++k) {
      const auto [first, last] = pieceRange(k);
      for (size_t p = first + 1; p < last; ++p) boxes[first].merge(boxes[p]);
      nodes_[level[k]].bounds = boxes[first].box.bounds();
      centroids.push_back(boxes[first].centroids.bounds());
      binnings.emplace_back(centroids.back());
    }

    // Every node is binned (its count is far above 1) unless it is too deep for SAH splits.
    std::vector<Bins> bins(pieces.size());
    parallelIndices(pieces.size(), threads_, [&](size_t p) {
      const Piece& piece = pieces[p];
      if (nodes_[level[piece.node]].depth >= kMaxSahDepth) return;
      const Binning& binning = binnings[piece.node];
      for (uint32_t i = piece.lo; i < piece.hi; ++i) {
        bins[p].add(binning, items_[i]);
        for (int axis = 0; axis < 3; ++axis)
          if (binning.binned(axis)) binOf_[size_t(axis)][i] = uint8_t(binning.bin(items_[i], axis));
      }
    });
    // The cut of each node; for a partition, which side each item goes to (its bin along the
    // split axis, kept from binning) and each piece's count of items going left (its bins').
    std::vector<BinSplit> best(level.size());
    std::vector<Cut> cut(level.size());
    std::vector<uint32_t> lefts(pieces.size(), 0);
    for (uint32_t k = 0; k < level.size(); ++k) {
      Node& n = nodes_[level[k]];
      if (n.depth >= kMaxSahDepth) {
        n.mid = median(items_, n.begin, n.end, centroids[k], leafSize_);
        cut[k] = Cut::Leaf;  // decided already
        continue;
      }
      const auto [first, last] = pieceRange(k);
      Bins all = bins[first];
      for (size_t p = first + 1; p < last; ++p) all.merge(bins[p]);
      cut[k] = choose(all, binnings[k], n.bounds, n.end - n.begin, leafSize_, best[k]);
      if (cut[k] == Cut::Leaf) n.mid = n.end;
      if (cut[k] == Cut::Half) n.mid = n.begin + (n.end - n.begin) / 2;
      if (cut[k] != Cut::Partition) continue;
      uint32_t total = 0;
      for (size_t p = first; p < last; ++p) {
        for (int b = 0; b <= best[k].bin; ++b) lefts[p] += bins[p].count[size_t(best[k].axis)][size_t(b)];
        total += lefts[p];
      }
      n.mid = n.begin + total;
    }
    partition(level, pieces, firstPiece, cut, best, lefts);

    std::vector<uint32_t> next;
    for (uint32_t k = 0; k < level.size(); ++k) {
      Node& n = nodes_[level[k]];
      if (cut[k] == Cut::Partition && (n.mid == n.begin || n.mid == n.end)) n.mid = n.begin + (n.end - n.begin) / 2;
      if (n.mid == n.end) continue;  // a leaf
      const uint32_t sides[2][2] = {{n.begin, n.mid}, {n.mid, n.end}};
      for (int side = 0; side < 2; ++side) {
        if (sides[side][1] - sides[side][0] < shared_) continue;
        nodes_[level[k]].child[side] = int32_t(nodes_.size());
        next.push_back(uint32_t(nodes_.size()));
        nodes_.push_back({sides[side][0], sides[side][1], nodes_[level[k]].depth + 1, {}});
      }
    }
    return next;
  }

  void partition(const std::vector<uint32_t>& level, const std::vector<Piece>& pieces,
                 const std::vector<size_t>& firstPiece, const std::vector<Cut>& cut, const std::vector<BinSplit>& best,
                 const std::vector<uint32_t>& lefts) {
    const auto goesLeft = [&](uint32_t k, uint32_t i) {
      return binOf_[size_t(best[k].axis)][i] <= uint8_t(best[k].bin);
    };
    // Where each piece's misplaced items come in their node's two sequences: those going
    // right counted from the left, those going left from the right.
    std::vector<uint32_t> firstRight(pieces.size(), 0), firstLeft(pieces.size(), 0);
    std::vector<uint32_t> swaps(level.size(), 0);
    for (uint32_t k = 0; k < level.size(); ++k) {
      if (cut[k] != Cut::Partition) continue;
      const Node& n = nodes_[level[k]];
      uint32_t right = 0;
      for (size_t p = firstPiece[k]; p < firstPiece[k + 1]; ++p) {
        firstRight[p] = right;
        const Piece& piece = pieces[p];
        if (piece.hi <= n.mid) right += (piece.hi - piece.lo) - lefts[p];
        else
          for (uint32_t i = piece.lo; i < n.mid; ++i) right += !goesLeft(k, i);
      }
      swaps[k] = right;
      uint32_t left = 0;
      for (size_t p = firstPiece[k + 1]; p-- > firstPiece[k];) {
        firstLeft[p] = left;  // those of the pieces after p
        const Piece& piece = pieces[p];
        if (piece.lo >= n.mid) left += lefts[p];
        else
          for (uint32_t i = n.mid; i < piece.hi; ++i) left += goesLeft(k, i);
      }
    }
    // The positions, node by node in scratch_[begin, end): those going right from the
    // start, those going left from begin + (end - mid).
    parallelIndices(pieces.size(), threads_, [&](size_t p) {
      const Piece& piece = pieces[p];
      if (cut[piece.node] != Cut::Partition) return;
      const Node& n = nodes_[level[piece.node]];
      uint32_t* goingRight = scratch_.begin() + n.begin;
      uint32_t* goingLeft = goingRight + (n.end - n.mid);
      uint32_t at = firstRight[p];
      for (uint32_t i = piece.lo; i < std::min(piece.hi, n.mid); ++i)
        if (!goesLeft(piece.node, i)) goingRight[at++] = i;
      at = firstLeft[p];
      for (uint32_t i = piece.hi; i-- > std::max(piece.lo, n.mid);)
        if (goesLeft(piece.node, i)) goingLeft[at++] = i;
    });
    std::vector<Piece> trades;  // ranges of each node's pairs
    for (uint32_t k = 0; k < level.size(); ++k) {
      const Blocks blocks(swaps[k], threads_, kGrain);
      for (size_t b = 0; b < blocks.count && swaps[k] > 0; ++b)
        trades.push_back({k, uint32_t(blocks.begin(b)), uint32_t(blocks.end(b))});
    }
    parallelIndices(trades.size(), threads_, [&](size_t t) {
      const Node& n = nodes_[level[trades[t].node]];
      const uint32_t* goingRight = scratch_.begin() + n.begin;
      const uint32_t* goingLeft = goingRight + (n.end - n.mid);
      for (uint32_t k = trades[t].lo; k < trades[t].hi; ++k) std::swap(items_[goingRight[k]], items_[goingLeft[k]]);
    });
  }

  BuildItem* items_;
  uint32_t shared_;
  int threads_;
  uint32_t leafSize_;
  std::vector<Node> nodes_;
  RawArray<uint8_t> binOf_[3];  // item i's bin along each axis in its node's binning
  RawArray<uint32_t> scratch_;
};

// Builds the binary tree over `items`, reordering them as its leaves take them, into `nodes`
// (room for 2 x items - 1). Depth first, each node's left child next to it, as one thread would
// build it but for the slots that the shared nodes set aside for a subtree beyond those it
// takes (the collapse follows the children, never the slots).
class Builder {
 public:
  Builder(RawArray<BuildItem>& items, RawArray<BuildNode>& nodes, int threads, uint32_t leafSize)
      : items_(items), nodes_(nodes), threads_(threads), leafSize_(leafSize) {}

  // Returns the number of nodes made.
  uint32_t build() {
    const uint32_t n = uint32_t(items_.size());
    const uint32_t shared = std::max(kSharedItems, n / (8 * uint32_t(std::max(threads_, 1))));
    uint32_t next = 0;
    if (threads_ <= 1 || n < shared) {
      subtree(0, n, 1, next);
      return next;
    }
    const TopLevels top(items_.begin(), n, shared, threads_, leafSize_);
    std::vector<Pending> pending;
    place(top.nodes(), 0, next, pending);
    // The biggest first, so that no thread is left with a big one at the end.
    std::sort(pending.begin(), pending.end(), [](const Pending& a, const Pending& b) {
      return a.end - a.begin > b.end - b.begin || (a.end - a.begin == b.end - b.begin && a.begin < b.begin);
    });
    std::vector<uint32_t> made(pending.size());
    parallelIndices(pending.size(), threads_, [&](size_t k) {
      const Pending& p = pending[k];
      uint32_t at = p.slot;
      subtree(p.begin, p.end, p.depth, at);
      made[k] = at - p.slot;
    });
    return std::accumulate(made.begin(), made.end(), uint32_t(shared_.size()));
  }

  // The nodes built by the threads together, in increasing order.
  const std::vector<uint32_t>& shared() const { return shared_; }

 private:
  // A subtree left to one thread: items [begin, end) from slot `slot`.
  struct Pending {
    uint32_t begin, end, slot;
    int depth;
  };

  // Gives top node t and the top nodes below it their slots, depth first, and the subtrees
  // below them their room.
  void place(const std::vector<TopLevels::Node>& top, int32_t t, uint32_t& next, std::vector<Pending>& pending) {
    const TopLevels::Node& n = top[size_t(t)];
    const uint32_t self = next++;
    shared_.push_back(self);
    if (n.mid == n.end) {
      nodes_[self] = {n.bounds, n.begin, n.end - n.begin};
      return;
    }
    uint32_t right = 0;
    const uint32_t sides[2][2] = {{n.begin, n.mid}, {n.mid, n.end}};
    for (int side = 0; side < 2; ++side) {
      if (side == 1) right = next;
      if (n.child[side] >= 0) {
        place(top, n.child[side], next, pending);
      } else {
        pending.push_back({sides[side][0], sides[side][1], next, n.depth + 1});
        next += 2 * (sides[side][1] - sides[side][0]) - 1;  // the most a binary tree over them takes
      }
    }
    nodes_[self] = {n.bounds, right, 0};
  }

  // `known`: the node's boxes, when its parent's partition gathered them.
  void subtree(uint32_t begin, uint32_t end, int depth, uint32_t& next, const NodeBoxes* known = nullptr) {
    const uint32_t self = next++;
    const SerialPasses passes(items_.begin());
    const NodeBoxes boxes = known ? *known : passes.boxes(begin, end);
    const Bounds bounds = boxes.box.bounds(), centroids = boxes.centroids.bounds();
    const uint32_t count = end - begin;
    uint32_t mid = end;
    NodeBoxes halves[2];
    bool halvesKnown = false;
    if (count > 1 && depth >= kMaxSahDepth) {
      mid = median(items_.begin(), begin, end, centroids, leafSize_);
    } else if (count > 1) {
      const Binning binning(centroids);
      BinSplit best;
      const Cut cut = choose(passes.bins(begin, end, binning), binning, bounds, count, leafSize_, best);
      if (cut == Cut::Half) mid = begin + count / 2;
      if (cut == Cut::Partition) {
        mid = passes.partition(
            begin, end, [&](const BuildItem& it) { return binning.bin(it, best.axis) <= best.bin; }, halves[0],
            halves[1]);
        halvesKnown = mid != begin && mid != end;
        if (!halvesKnown) mid = begin + count / 2;
      }
    }
    // Once a signal is caught the tree is thrown away (Bvh::Bvh): its subtrees end at once.
    if (mid == end || interrupt::requested()) {
      nodes_[self] = {bounds, begin, count};
      return;
    }
    subtree(begin, mid, depth + 1, next, halvesKnown ? &halves[0] : nullptr);
    const uint32_t right = next;
    subtree(mid, end, depth + 1, next, halvesKnown ? &halves[1] : nullptr);
    nodes_[self] = {bounds, right, 0};
  }

  RawArray<BuildItem>& items_;
  RawArray<BuildNode>& nodes_;
  int threads_;
  uint32_t leafSize_;
  std::vector<uint32_t> shared_;
};

// Where Collapser::collapse() puts the wide nodes it makes: appended to `grow`, or written
// from `at` on; with neither, they are only counted. `first` is the index of the first one.
class WideOut {
 public:
  static WideOut appending(std::vector<BvhNode>& nodes) { return WideOut(&nodes, nullptr, uint32_t(nodes.size())); }
  static WideOut writing(BvhNode* at, uint32_t first) { return WideOut(nullptr, at, first); }
  static WideOut counting() { return WideOut(nullptr, nullptr, 0); }

  // A new empty node; its index.
  uint32_t make() {
    if (grow_) grow_->emplace_back();
    else if (at_) at_[made_] = BvhNode();
    return first_ + made_++;
  }
  // The node of that index, or null when counting.
  BvhNode* node(uint32_t index) {
    if (grow_) return &(*grow_)[index];
    return at_ ? at_ + (index - first_) : nullptr;
  }
  uint32_t made() const { return made_; }

 private:
  WideOut(std::vector<BvhNode>* grow, BvhNode* at, uint32_t first) : grow_(grow), at_(at), first_(first) {}
  std::vector<BvhNode>* grow_;
  BvhNode* at_;
  uint32_t first_;
  uint32_t made_ = 0;
};

// Turns the binary tree into the wide one: each wide node takes the children of a binary
// node, then keeps opening its largest interior child until it has kBvhWidth. The wide nodes
// of the shared binary nodes are made first; then the subtrees below them are counted at the
// same time, placed (depth first, as one thread would put them), and made at the same time,
// each straight into its place: the wide tree is never held twice.
class Collapser {
 public:
  // `shared`: the binary nodes that the threads built together, in increasing order.
  Collapser(const BuildNode* binary, const std::vector<uint32_t>& shared, int threads)
      : binary_(binary), shared_(shared), threads_(threads) {}

  void collapse(std::vector<BvhNode>& wide, BvhStats& stats) {
    if (binary_[0].count > 0) {  // the whole tree is one leaf
      wide.emplace_back();
      wide[0].setChild(0, binary_[0].bounds, binary_[0].rightOrFirst, uint8_t(binary_[0].count));
      stats.leaves = 1;
      stats.maxDepth = 1;
      return;
    }
    if (threads_ <= 1 || shared_.empty()) {
      WideOut out = WideOut::appending(wide);
      collapse(0, 1, out, stats, nullptr);
      return;
    }
    std::vector<BvhNode> top;
    std::vector<Deferred> deferred;
    WideOut topOut = WideOut::appending(top);
    collapse(0, 1, topOut, stats, &deferred);
    parallelIndices(deferred.size(), threads_, [&](size_t k) {
      Deferred& d = deferred[k];
      WideOut count = WideOut::counting();
      collapse(d.binary, d.depth, count, d.stats, nullptr);
      d.count = count.made();
    });
    // Where the nodes go, depth first: each node of `top` is followed by its children's
    // subtrees, in slot order, whether made in `top` or deferred.
    std::vector<uint32_t> place(top.size());
    uint32_t next = 0;
    const auto locate = [&](const auto& self, uint32_t t) -> void {
      place[t] = next++;
      const BvhNode& n = top[t];
      for (int i = 0; i < n.used; ++i) {
        if (n.count[i] > 0) continue;
        if (n.child[i] & kDeferred) {
          Deferred& d = deferred[n.child[i] & ~kDeferred];
          d.at = next;
          next += d.count;
        } else {
          self(self, n.child[i]);
        }
      }
    };
    locate(locate, 0);
    for (BvhNode& n : top)
      for (int i = 0; i < n.used; ++i)
        if (n.count[i] == 0)
          n.child[i] = n.child[i] & kDeferred ? deferred[n.child[i] & ~kDeferred].at : place[n.child[i]];
    resizePrefaulted(wide, next, threads_);
    for (size_t t = 0; t < top.size(); ++t) wide[place[t]] = top[t];
    parallelIndices(deferred.size(), threads_, [&](size_t k) {
      const Deferred& d = deferred[k];
      WideOut out = WideOut::writing(wide.data() + d.at, d.at);
      BvhStats unused;
      collapse(d.binary, d.depth, out, unused, nullptr);
    });
    for (const Deferred& d : deferred) {
      stats.leaves += d.stats.leaves;
      stats.maxDepth = std::max(stats.maxDepth, d.stats.maxDepth);
    }
  }

 private:
  static constexpr uint32_t kDeferred = 0x80000000u;

  // A subtree left to one thread, from binary node `binary` at `depth`.
  struct Deferred {
    uint32_t binary;
    int depth;
    BvhStats stats;
    uint32_t count = 0;  // its wide nodes
    uint32_t at = 0;     // where they go
  };

  // Makes the wide node for binary node b and its subtree into `out`, and returns its index
  // there. With `deferred`, the subtrees below the shared nodes are left to it instead (their
  // slots' child is kDeferred | their index there).
  uint32_t collapse(uint32_t b, int depth, WideOut& out, BvhStats& stats, std::vector<Deferred>* deferred) {
    stats.maxDepth = std::max(stats.maxDepth, depth);
    const uint32_t self = out.make();
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
        ++stats.leaves;
        stats.maxDepth = std::max(stats.maxDepth, depth + 1);
        if (BvhNode* node = out.node(self)) node->setChild(i, k.bounds, k.rightOrFirst, uint8_t(k.count));
      } else if (deferred && !std::binary_search(shared_.begin(), shared_.end(), kids[i])) {
        out.node(self)->setChild(i, k.bounds, kDeferred | uint32_t(deferred->size()), 0);
        deferred->push_back({kids[i], depth + 1, {}});
      } else {
        const uint32_t child = collapse(kids[i], depth + 1, out, stats, deferred);
        if (BvhNode* node = out.node(self)) node->setChild(i, k.bounds, child, 0);
      }
    }
    return self;
  }

  const BuildNode* binary_;
  const std::vector<uint32_t>& shared_;
  int threads_;
};

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

Bvh::Bvh(PrimitiveStore primitives, unsigned buildThreads, uint32_t leafSize) {
  const auto start = std::chrono::steady_clock::now();
  leafSize = std::clamp<uint32_t>(leafSize, kBvhLeafSize, kBvhMaxLeafSize);
  stats_.leafSize = leafSize;
  const int threads = buildThreads > 0 ? int(buildThreads) : threadBudget();
  const uint32_t total = uint32_t(primitives.size());
  // The bounded primitives' items, in primitive order: each block's are counted, then written
  // where the blocks before leave off (one thread writes them as it finds them).
  const bool alone = threads <= 1;
  const Blocks blocks(total, threads, alone ? std::max<size_t>(total, 1) : kGrain);
  std::vector<uint32_t> firstItem(blocks.count + 1, 0);
  if (alone) firstItem[1] = total;  // at most
  else
    parallelBlocks(blocks, threads, [&](size_t b, size_t lo, size_t hi) {
      uint32_t n = 0;
      for (size_t i = lo; i < hi; ++i) n += !primitives.bounds(i).empty();
      firstItem[b + 1] = n;
    });
  std::partial_sum(firstItem.begin(), firstItem.end(), firstItem.begin());
  RawArray<BuildItem> items(firstItem.back());
  std::vector<std::vector<uint32_t>> unbounded(blocks.count);
  parallelBlocks(blocks, threads, [&](size_t b, size_t lo, size_t hi) {
    uint32_t k = firstItem[b];
    for (size_t i = lo; i < hi; ++i) {
      const Bounds box = primitives.bounds(i);
      if (box.empty()) unbounded[b].push_back(uint32_t(i));
      else items[k++] = {{positiveZero(box.lo), positiveZero(box.hi)}, positiveZero(box.centroid()), uint32_t(i)};
    }
  });
  if (alone) items.shrink(total - uint32_t(unbounded[0].size()));
  if (items.size() > 0) {
    RawArray<BuildNode> binary(2 * items.size() - 1);
    Builder builder(items, binary, threads, leafSize);
    const uint32_t made = builder.build();
    interrupt::check();
    nodes_.reserve(made / 2 + 1);  // a wide node takes at least one of the binary interior ones
    Collapser(binary.begin(), builder.shared(), threads).collapse(nodes_, stats_);
  }
  // The order the primitives take: the bounded ones as the leaves have them, then the others.
  std::vector<uint32_t> order(total);
  boundedCount_ = uint32_t(items.size());
  parallelBlocks(Blocks(items.size(), threads, kGrain), threads, [&](size_t, size_t lo, size_t hi) {
    for (size_t j = lo; j < hi; ++j) order[j] = items[j].index;
  });
  items = RawArray<BuildItem>(0);
  for (size_t b = 0, j = boundedCount_; b < unbounded.size(); ++b)
    for (uint32_t i : unbounded[b]) order[j++] = i;
  // The records gathered into their new places on every thread (48 bytes each, beside the
  // tree's 100 or so a primitive freed just before, so the peak is not raised). In place, the
  // permutation's cycles had to be listed on one thread first: a random walk over all of
  // them that took a fifth of a 10^6-sphere build on 2 threads.
  if (threads > 1) {
    std::vector<PrimitiveRecord> gathered;
    resizePrefaulted(gathered, total, threads);
    parallelBlocks(Blocks(total, threads, kGrain), threads, [&](size_t, size_t lo, size_t hi) {
      for (size_t j = lo; j < hi; ++j) gathered[j] = primitives.records[order[j]];
    });
    primitives.records.swap(gathered);
  } else {
    permuteInPlace(primitives.records, order, threads);
  }
  interrupt::check();
  items_ = std::move(primitives.records);
  others_ = std::move(primitives.others);
  followRecords(threads);
  markSharedObjects();
  makePovTieRoot();
  stats_.nodes = nodes_.size();
  stats_.bytes = nodes_.size() * sizeof(BvhNode) + items_.size() * sizeof(PrimitiveRecord) +
                 others_.size() * sizeof(Primitive);
  // An upper bound: primitives may share one. A mesh's triangles share theirs, and lie
  // mostly side by side here, so one is counted for each run of them.
  const Transform* previous = nullptr;
  for (const Primitive& p : others_) {
    if (p.transform && p.transform.get() != previous) stats_.bytes += sizeof(Transform);
    previous = p.transform.get();
  }
  stats_.buildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

PrimitiveStore Bvh::release() && {
  PrimitiveStore store;
  store.records = std::move(items_);
  store.others = std::move(others_);
  *this = Bvh();
  return store;
}

// For ties at equal keys (Bvh::replacesHit) in scenes small enough to sort: the finite objects'
// POV-Ray boxes in declaration order and POV-Ray's root made of them (accel/pov_bbox_root.h).
// Made once here, not at every tie: a room of six planes round 1000 small spheres, whose
// corner lines tie, rendered in 2.0-2.2 s with the root made at each tie and 0.35-0.54 s
// without the rule.
void Bvh::makePovTieRoot() {
  constexpr uint32_t kMostObjects = 1024;
  if (boundedCount_ > kMostObjects) return;
  std::vector<std::pair<uint32_t, PovBBox>> objects;  // (object, box), to be put in declaration order
  for (uint32_t i = 0; i < boundedCount_; ++i) {
    const PrimitiveRecord& it = items_[i];
    std::optional<PovBBox> box;
    if (it.kind == PrimitiveRecord::Kind::Sphere) box = povSphereBBox(it.sphere.center, it.sphere.radius);
    else if (it.kind == PrimitiveRecord::Kind::Other) box = others_[it.other].povBBox();
    if (!box) return;  // a box pvrt does not know (a mesh, a shape it holds otherwise)
    objects.emplace_back(it.object, *box);
  }
  std::sort(objects.begin(), objects.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  // A mesh's triangles all carry the mesh's box: one leaf. Any other object of several
  // primitives has no box of its own that pvrt knows.
  const auto sameBox = [](const PovBBox& x, const PovBBox& y) { return std::memcmp(&x, &y, sizeof x) == 0; };
  size_t kept = 0;
  for (size_t k = 0; k < objects.size(); ++k) {
    if (kept > 0 && objects[k].first == objects[kept - 1].first) {
      if (!sameBox(objects[k].second, objects[kept - 1].second)) return;
      continue;
    }
    objects[kept++] = objects[k];
  }
  objects.resize(kept);
  std::vector<PovBBox> finite;
  for (const auto& [object, box] : objects) {
    povTieObjects_.push_back(object);
    finite.push_back(box);
  }
  povTieRootHoldsObjects_ = true;
  const PovBBoxTree tree = povBBoxTree(finite);
  std::vector<uint32_t> placeOf(objects.empty() ? 0 : size_t(objects.back().first) + 1, 0);
  for (size_t k = 0; k < objects.size(); ++k) placeOf[objects[k].first] = uint32_t(k);
  // The root's box is tested only where no plane makes the root infinite (Build_BBox_Tree).
  const bool rootTested = boundedCount_ == items_.size();
  povAbove_.assign(boundedCount_, {});
  for (uint32_t i = 0; i < boundedCount_; ++i) {
    if (items_[i].kind != PrimitiveRecord::Kind::Other) continue;
    povAbove_[i] = tree.above[placeOf[items_[i].object]];
    if (!rootTested && !povAbove_[i].empty()) povAbove_[i].pop_back();
  }
  for (const pov_bbox_root_detail::Entry& entry : tree.root) {
    povTieRootBoxes_.push_back(entry.box);
    povTieRootEntries_.push_back(entry.object);
    povTieRootHoldsObjects_ = povTieRootHoldsObjects_ && entry.object >= 0;
  }
  povTieKnown_ = true;
}

// Only shapes kept whole (Kind::Other) come several to an object: a mesh's triangles. So the
// pass reads others_, which a scene of spheres has none of.
void Bvh::markSharedObjects() {
  uint32_t last = 0;
  for (const Primitive& p : others_) last = std::max(last, p.object);
  std::vector<uint8_t> count(others_.empty() ? 0 : size_t(last) + 1, 0);
  for (const Primitive& p : others_) count[p.object] = uint8_t(std::min(count[p.object] + 1, 2));
  for (PrimitiveRecord& r : items_)
    r.sharesObject = r.kind == PrimitiveRecord::Kind::Other && count[r.object] > 1;
}

// The shapes of the Kind::Other records put in their records' order, for locality: a leaf's
// triangles then lie side by side. Each block of records counts its own, then renumbers
// them from where the blocks before leave off.
void Bvh::followRecords(int threads) {
  if (others_.empty()) return;
  const Blocks blocks(items_.size(), threads, kGrain);
  std::vector<uint32_t> first(blocks.count + 1, 0);
  parallelBlocks(blocks, threads, [&](size_t b, size_t lo, size_t hi) {
    for (size_t i = lo; i < hi; ++i) first[b + 1] += items_[i].kind == PrimitiveRecord::Kind::Other;
  });
  std::partial_sum(first.begin(), first.end(), first.begin());
  std::vector<uint32_t> order(others_.size());
  parallelBlocks(blocks, threads, [&](size_t b, size_t lo, size_t hi) {
    uint32_t k = first[b];
    for (size_t i = lo; i < hi; ++i) {
      PrimitiveRecord& r = items_[i];
      if (r.kind != PrimitiveRecord::Kind::Other) continue;
      order[k] = r.other;
      r.other = k++;
    }
  });
  permuteInPlace(others_, order, threads);
  interrupt::check();
}

}  // namespace pvrt
