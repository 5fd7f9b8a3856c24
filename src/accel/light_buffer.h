// Haines and Greenberg's light buffer ("The Light Buffer: A Shadow-Testing Accelerator",
// 1986): the directions around a point light, split into the cells of a cube's six faces,
// each cell listing the primitives seen from the light within it, nearest first. A shadow
// segment ends at the light, so every primitive it can meet lies in the cell of its
// direction: a segment blocked by the first primitive there costs a lookup and one test,
// where a walk of the BVH visits a dozen nodes in a big scene. Built once per light, then
// immutable and shared by every thread.
//
// The lists are conservative: a primitive is listed in every cell its bounding box may
// be seen in, widened by kMargin radians, so that a segment whose direction is off the
// light's by less than that (the rounding of a shadow origin, see Bvh::occlusionToLight)
// still finds it. The answers are therefore exactly the BVH's.
#pragma once

#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "core/vec3.h"
#include "geometry/bounds.h"

namespace pvrt {

class LightBuffer {
 public:
  static constexpr double kMargin = 1e-7;  // radians
  // A primitive seen in more cells than this is tested for every segment instead; a light
  // with more such primitives than kMaxEverywhere, or more entries than
  // kEntriesPerPrimitive a primitive, gets no buffer (valid() is false): its segments walk
  // the BVH.
  static constexpr int kCrowded = 256;
  static constexpr size_t kMaxEverywhere = 32;
  static constexpr size_t kEntriesPerPrimitive = 8;

  // What the buffer knows of a primitive: its box and, where it has one, a ball holding
  // it (a sphere's own), whose cone of directions is tighter than the box's footprint.
  struct Occluder {
    Bounds box;
    Vec3 center{};
    double radius = INFINITY;  // no ball
  };

  // (In this order, so that on a little-endian machine an entry's 8 bytes read as one integer
  // order the entries by distance, then by primitive: the build sorts millions of them.)
  struct Entry {
    uint32_t primitive;  // index into the BVH's primitives
    float near;          // the distance from the light to the primitive's box, rounded down
  };

  LightBuffer() = default;
  // `occluders[i]` is primitive i, for the first occluders.size() (bounded) primitives. Built
  // by up to `threads` threads (0: threadBudget()); the buffer is the same whatever the number.
  LightBuffer(const Vec3& light, const std::vector<Occluder>& occluders, int threads = 0);
  // The buffers of several lights, built together: buffer k is LightBuffer(lights[k], occluders),
  // or an invalid one for the lights that do not fit in `memoryBytes`. The lights are built a
  // batch at a time, in order, and the build's own temporaries count too: it never holds more
  // than memoryBytes, and the lights left without a buffer are the last ones (their segments
  // walk the BVH: the same answers). The same buffers whatever the number of threads. Stops
  // early, leaving the rest invalid, once a signal is caught (core/interrupt.h).
  static std::vector<LightBuffer> build(std::span<const Vec3> lights, const std::vector<Occluder>& occluders,
                                        int threads = 0, size_t memoryBytes = SIZE_MAX);
  // What the build of one light may hold at once per entry (its listing, 12 bytes, and the
  // entry itself) and per cell (its count and its offset).
  static constexpr size_t kBuildBytesPerEntry = 20, kBuildBytesPerCell = 8;

  // Whether the buffer was built (see kMaxEverywhere and build's memory limit).
  bool valid() const { return !offsets_.empty(); }
  // Whether it was left out to stay within build's memory limit.
  bool overMemoryLimit() const { return overMemoryLimit_; }
  const Vec3& light() const { return light_; }
  // The primitives that may lie along direction `fromLight` (any length), nearest first;
  // false for a zero or non-finite direction, which has no cell.
  bool cell(const Vec3& fromLight, std::span<const Entry>& out) const;
  // The cell of a direction from the light; -1 for a zero or non-finite one, or when there
  // are no cells.
  int cellIndexOf(const Vec3& fromLight) const;
  // The cell that cellIndexOf gives every direction d with lo <= d <= hi (componentwise),
  // when it is one cell; else -1. For a packet of segments, from the range of their
  // directions, so that none needs a lookup of its own.
  int commonCell(const Vec3& lo, const Vec3& hi) const;
  // The primitives listed in cell `index` (a cellIndexOf or commonCell answer), nearest first.
  std::span<const Entry> list(int index) const {
    return {entries_.data() + offsets_[size_t(index)], offsets_[size_t(index) + 1] - offsets_[size_t(index)]};
  }
  // Hints that cell `index` (from cellIndexOf, -1 for none) will soon be read: prefetchCell
  // starts fetching where its list is, prefetchList (which waits for that) the list's first
  // entries. Between the two, other work (other lights' cells) overlaps the wait.
  void prefetchCell(int index) const {
    if (index >= 0) __builtin_prefetch(&offsets_[size_t(index)]);
  }
  void prefetchList(int index) const {
    if (index >= 0) __builtin_prefetch(&entries_[offsets_[size_t(index)]]);
  }
  // The primitives whose box holds the light or covers much of its view: tested for every
  // segment.
  std::span<const uint32_t> everywhere() const { return everywhere_; }

  int resolution() const { return res_; }
  // The cells that have a list (list(0) .. list(cells() - 1)): those of the faces' windows
  // and the one empty cell that stands for every other.
  size_t cells() const { return offsets_.empty() ? 0 : offsets_.size() - 1; }
  size_t entries() const { return entries_.size(); }
  size_t bytes() const {
    return entries_.size() * sizeof(Entry) + offsets_.size() * sizeof(uint32_t) + everywhere_.size() * 4;
  }

 private:
  // The cells of a face that may list anything: those where the box around all the
  // primitives may be seen. Only they have offsets; every other cell is the one empty cell.
  struct Window {
    int i0 = 0, j0 = 0, width = 0, height = 0;
    uint32_t base = 0;  // its first cell's index
  };
  int cellIndex(int face, int i, int j) const {
    const Window& w = windows_[face];
    const unsigned di = unsigned(i - w.i0), dj = unsigned(j - w.j0);
    if (di >= unsigned(w.width) || dj >= unsigned(w.height)) return emptyCell_;
    return int(w.base + dj * unsigned(w.width) + di);
  }
  // What build()'s batches share: the scene's box, each resolution's cell cones, and the
  // listings' memory (light_buffer.cpp).
  struct BuildShared;
  // One batch of build(): each light's listings stop (and the light gets no buffer) beyond
  // `entryCap` entries.
  static std::vector<LightBuffer> buildBatch(std::span<const Vec3> lights, const std::vector<Occluder>& occluders,
                                             int threads, size_t entryCap, BuildShared& shared);

  Vec3 light_;
  int res_ = 1;                    // cells along each side of a face
  Window windows_[6];
  int emptyCell_ = 0;              // the last cell, which lists nothing
  std::vector<uint32_t> offsets_;  // the windows' cells + the empty one + 1: where each cell's entries start
  std::vector<Entry> entries_;
  std::vector<uint32_t> everywhere_;
  bool overMemoryLimit_ = false;
};

}  // namespace pvrt
