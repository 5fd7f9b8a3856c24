// The entries of POV-Ray 3.7's bounding-tree root (bbox.cpp, Build_BBox_Tree): which boxes
// a ray's walk pushes into its priority queue beside the planes (accel/pov_heap_order.h).
// Build_BBox_Tree sorts and splits the finite objects' boxes into nodes of at most
// BUNCHING_FACTOR (4) entries by surface area (sort_and_split), then does the same to those
// nodes, round after round, until one node is left: the root. Made here from the objects'
// float boxes with POV-Ray's arithmetic, its find_axis slip included (the far side of each box
// is its near corner), so that the root's entries are POV-Ray's.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

#include "geometry/pov_bbox.h"

namespace pvrt {

namespace pov_bbox_root_detail {

constexpr size_t kBunchingFactor = 4;  // bbox.cpp's BUNCHING_FACTOR
constexpr double kBoundHuge = 2.0e10;  // BOUND_HUGE

// find_axis: the axis along which the boxes' near corners spread most (POV-Ray compares
// the far side, float near corner + float length, but records the near corner).
template <class Boxes>
inline int findAxis(const Boxes& f, size_t first, size_t last) {
  double mins[3] = {kBoundHuge, kBoundHuge, kBoundHuge}, maxs[3] = {-kBoundHuge, -kBoundHuge, -kBoundHuge};
  for (size_t i = first; i < last; ++i)
    for (int a = 0; a < 3; ++a) {
      const PovBBox& b = f[i].box;
      if (b.lowerLeft[a] < mins[a]) mins[a] = b.lowerLeft[a];
      if (b.lowerLeft[a] + b.lengths[a] > maxs[a]) maxs[a] = b.lowerLeft[a];
    }
  int which = 0;
  double d = -kBoundHuge;
  for (int a = 0; a < 3; ++a)
    if (const double e = maxs[a] - mins[a]; e > d) d = e, which = a;
  return which;
}

// calc_bbox and build_area_table's running union: double corners from the float boxes.
struct Union {
  double lo[3] = {kBoundHuge, kBoundHuge, kBoundHuge}, hi[3] = {-kBoundHuge, -kBoundHuge, -kBoundHuge};
  void add(const PovBBox& b) {
    for (int a = 0; a < 3; ++a) {
      const double tmin = b.lowerLeft[a], tmax = tmin + b.lengths[a];
      if (tmin < lo[a]) lo[a] = tmin;
      if (tmax > hi[a]) hi[a] = tmax;
    }
  }
  double area() const {
    const double x = hi[0] - lo[0], y = hi[1] - lo[1], z = hi[2] - lo[2];
    return x * (y + z) + y * z;
  }
};

struct Entry {
  PovBBox box;
  int object;     // the object's place in declaration order, or -1 for a node
  int node = -1;  // for a node, its index among the nodes made
};

// A node sort_and_split made: its box and the node it went into (-1: none yet, the root).
struct Node {
  PovBBox box;
  int parent = -1;
};

// sort_and_split on f[first, last): true when it made one node of them all (its entries in
// `root`, in the node's order), false when it split them into nodes appended to f.
inline bool sortAndSplit(std::vector<Entry>& f, size_t first, size_t last, std::vector<Entry>& root,
                         std::vector<Node>& nodes, std::vector<int>& parentOf) {
  if (last <= first) return true;
  const int axis = findAxis(f, first, last);
  const size_t size = last - first;
  // compboxes: the float 2 * near corner + length; glibc's qsort of a small array is a merge
  // sort, which keeps equal keys in order, as std::stable_sort does.
  auto key = [axis](const Entry& e) { return float(2.0 * e.box.lowerLeft[axis] + e.box.lengths[axis]); };
  std::stable_sort(f.begin() + std::ptrdiff_t(first), f.begin() + std::ptrdiff_t(last),
                   [&key](const Entry& a, const Entry& b) { return key(a) < key(b); });
  std::vector<double> left(size), right(size);
  Union u;
  for (size_t i = first; i < last; ++i) u.add(f[i].box), left[i - first] = u.area();
  u = Union{};
  for (size_t i = last; i-- > first;) u.add(f[i].box), right[i - first] = u.area();
  double best = right[0] * (double(size) - 3.0);
  std::ptrdiff_t bestLoc = -1;
  for (size_t i = 0; i + 1 < size; ++i)
    if (const double index = double(i + 1) * left[i] + double(size - 1 - i) * right[i + 1]; index < best)
      best = index, bestLoc = std::ptrdiff_t(i + first);
  if (size <= kBunchingFactor || bestLoc < 0) {
    root.assign(f.begin() + std::ptrdiff_t(first), f.begin() + std::ptrdiff_t(last));
    Union node;
    for (size_t i = first; i < last; ++i) node.add(f[i].box);
    const int made = int(nodes.size());
    nodes.push_back({povBBoxFromMinMax({node.lo[0], node.lo[1], node.lo[2]}, {node.hi[0], node.hi[1], node.hi[2]})});
    for (size_t i = first; i < last; ++i) {
      if (f[i].object >= 0) parentOf[size_t(f[i].object)] = made;
      else nodes[size_t(f[i].node)].parent = made;
    }
    f.push_back({nodes.back().box, -1, made});
    return true;
  }
  sortAndSplit(f, first, size_t(bestLoc) + 1, root, nodes, parentOf);
  sortAndSplit(f, size_t(bestLoc) + 1, last, root, nodes, parentOf);
  return false;
}

}  // namespace pov_bbox_root_detail

// POV-Ray's bounding tree of finite objects with these boxes, in declaration order.
struct PovBBoxTree {
  std::vector<pov_bbox_root_detail::Entry> root;  // the root's entries, as the root node holds them
  // For each object, the boxes of the nodes above it, its parent first and the root last:
  // Intersect_BBox_Tree reaches the object only through Check_And_Enqueue of each of them
  // (the root's own box is not tested where planes make the root infinite).
  std::vector<std::vector<PovBBox>> above;
};

inline PovBBoxTree povBBoxTree(const std::vector<PovBBox>& finite) {
  using namespace pov_bbox_root_detail;
  PovBBoxTree tree;
  std::vector<Entry> f;
  std::vector<Node> nodes;
  std::vector<int> parentOf(finite.size(), -1);
  for (size_t i = 0; i < finite.size(); ++i) f.push_back({finite[i], int(i)});
  size_t low = 0, high = f.size();
  while (!sortAndSplit(f, low, high, tree.root, nodes, parentOf)) low = high, high = f.size();
  tree.above.resize(finite.size());
  for (size_t i = 0; i < finite.size(); ++i)
    for (int n = parentOf[i]; n >= 0; n = nodes[size_t(n)].parent) tree.above[i].push_back(nodes[size_t(n)].box);
  return tree;
}

// The root's entries for finite objects with these boxes, in declaration order, as the root
// node holds them (none for none: the root is then the planes' node itself).
inline std::vector<pov_bbox_root_detail::Entry> povRootEntries(const std::vector<PovBBox>& finite) {
  return povBBoxTree(finite).root;
}

// The boxes of those entries.
inline std::vector<PovBBox> povRootEntryBoxes(const std::vector<PovBBox>& finite) {
  std::vector<PovBBox> boxes;
  for (const auto& e : povRootEntries(finite)) boxes.push_back(e.box);
  return boxes;
}

}  // namespace pvrt
