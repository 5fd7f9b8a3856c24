// The light buffer's build: each box's footprint on the six faces of a cube around the
// light, in face coordinates u = x_b / x_a, v = x_c / x_a (a the face's axis), widened by
// the margin; then the cells' lists, nearest first.
#include "accel/light_buffer.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <memory>

#include "core/interrupt.h"
#include "core/prefault.h"
#include "parallel/median.h"
#include "parallel/parallel_for.h"

namespace pvrt {

namespace {

constexpr double kInf = INFINITY;
constexpr size_t kGrain = 2048;  // the fewest primitives of a block of the build
// The cells' offsets cost 4 bytes each whether a cell lists anything or not: only the cells
// where the scene may be seen get one (LightBuffer::Window), and at most this many a
// primitive, so that a light far from a few primitives costs about what its entries do. 100
// spheres and 10^4 far lights: 864 KB a light before (256 x 256 cells on each face).
constexpr size_t kCellsPerPrimitive = 64;
// The lights of a batch of the build: enough that a batch holds about this many (light,
// primitive) pairs, so that 10^5 lights among 100 primitives still keep every thread busy,
// few enough that a batch's temporaries stay small next to the buffers.
constexpr size_t kBatchPairs = size_t(1) << 20;

struct Range {
  double lo, hi;
};

// The range of x / w over x in [xLo, xHi] and w in (max(wLo, 0), wHi], wHi > 0, given
// 1 / wLo and 1 / wHi: the ratio is monotonic in each, so its extremes lie at the corners,
// or at infinity when w can come arbitrarily close to zero. Products with the reciprocals
// (a face's two divisions, not eight) are within 2 ulps of the quotients, far inside the
// footprint's margin.
Range ratio(double xLo, double xHi, double wLo, double invLo, double invHi) {
  if (wLo <= 0) return {xLo < 0 ? -kInf : xLo * invHi, xHi > 0 ? kInf : xHi * invHi};
  return {std::min(xLo * invLo, xLo * invHi), std::max(xHi * invLo, xHi * invHi)};
}

// The face coordinate's cell, clamped to the face (NaN and infinities included).
int cellOf(double u, int res) {
  const double x = (u + 1) * 0.5 * res;
  if (!(x >= 0)) return 0;
  if (x >= res) return res - 1;
  return int(x);
}

// A cell's order, nearest first and then by primitive, as one integer: a distance is a float
// of at least +0 (never -0 or NaN), whose bits order as the numbers do. On a little-endian
// machine that integer is the entry's own 8 bytes (LightBuffer::Entry's order).
uint64_t sortKey(const LightBuffer::Entry& e) {
  if constexpr (std::endian::native == std::endian::little) return std::bit_cast<uint64_t>(e);
  return uint64_t(std::bit_cast<uint32_t>(e.near)) << 32 | e.primitive;
}

float roundDown(double v) {
  const float f = float(v);
  if (!(double(f) > v)) return f;
  // The float below a positive one (infinity included) is the one whose bits are one less:
  // what std::nextafter gives, without its call for each of a big scene's listings.
  return f > 0 ? std::bit_cast<float>(std::bit_cast<uint32_t>(f) - 1) : std::nextafter(f, -INFINITY);
}

// A box as seen from the light: its corners relative to the light, widened by far more
// than the rounding of the subtraction (and of a primitive's own hit test).
struct RelativeBox {
  Vec3 lo, hi;
  RelativeBox(const Bounds& b, const Vec3& light) {
    lo = b.lo - light;
    hi = b.hi - light;
    double scale = 0;
    for (int a = 0; a < 3; ++a) scale = std::max({scale, std::fabs(lo[a]), std::fabs(hi[a])});
    const double grow = scale * 1e-9 + 1e-300;
    for (int a = 0; a < 3; ++a) {
      lo[a] -= grow;
      hi[a] += grow;
    }
  }
  // Holds the light, or cannot tell (a NaN bound, which the BVH's box test lets through
  // too): such a box is tested for every segment.
  bool holdsLight() const {
    for (int a = 0; a < 3; ++a)
      if (std::isnan(lo[a]) || std::isnan(hi[a])) return true;
    return lo.x <= 0 && lo.y <= 0 && lo.z <= 0 && hi.x >= 0 && hi.y >= 0 && hi.z >= 0;
  }
  double distance() const {
    double d2 = 0;
    for (int a = 0; a < 3; ++a) {
      const double d = std::max({0.0, lo[a], -hi[a]});
      d2 += d * d;
    }
    return std::sqrt(d2);
  }
};

// The cells [i0, i1] x [j0, j1] of one face that a box may be seen in, if any.
struct Footprint {
  int i0, i1, j0, j1;
  bool any = false;
  int cells() const { return any ? (i1 - i0 + 1) * (j1 - j0 + 1) : 0; }
};

template <int face>
Footprint footprint(const RelativeBox& box, int res) {
  // The face's axes known when compiled: Vec3's [] is a choice between its fields.
  constexpr int a = face / 2, b = (a + 1) % 3, c = (a + 2) % 3;
  constexpr bool negative = face % 2 != 0;
  const double wLo = negative ? -box.hi[a] : box.lo[a], wHi = negative ? -box.lo[a] : box.hi[a];
  Footprint f;
  if (!(wHi > 0)) return f;
  // The box is seen on the face only where |x_b| and |x_c| are at most about w <= wHi: a box
  // beyond that (most faces of most boxes: a small one is seen on one or two of six) is ruled
  // out without a division. The factor's 1e-6 exceeds the margin below and the rounding, so
  // only faces that the quotients would rule out are.
  const double reach = wHi * (1 + 1e-6);
  if (box.lo[b] > reach || box.hi[b] < -reach || box.lo[c] > reach || box.hi[c] < -reach) return f;
  const double invLo = 1 / wLo, invHi = 1 / wHi;
  Range u = ratio(box.lo[b], box.hi[b], wLo, invLo, invHi), v = ratio(box.lo[c], box.hi[c], wLo, invLo, invHi);
  // A direction within kMargin of the box's moves u and v by at most 2 kMargin (|u|, |v|
  // <= 1 on a face); the rest covers the rounding of the divisions and of the lookup.
  const double m = 2 * LightBuffer::kMargin + 1e-12;
  u = {u.lo - m, u.hi + m};
  v = {v.lo - m, v.hi + m};
  if (u.hi < -1 || u.lo > 1 || v.hi < -1 || v.lo > 1) return f;
  f = {cellOf(u.lo, res), cellOf(u.hi, res), cellOf(v.lo, res), cellOf(v.hi, res), true};
  return f;
}

// A box's footprints on the six faces; the cells they span together.
int footprints(const RelativeBox& box, int res, Footprint (&f)[6]) {
  f[0] = footprint<0>(box, res);
  f[1] = footprint<1>(box, res);
  f[2] = footprint<2>(box, res);
  f[3] = footprint<3>(box, res);
  f[4] = footprint<4>(box, res);
  f[5] = footprint<5>(box, res);
  int cells = 0;
  for (const Footprint& x : f) cells += x.cells();
  return cells;
}

// Cells a side: about two per typical primitive's apparent size (the median over the
// primitives, in radians; a face spans 2 in u), at most 256. Finer cells list fewer
// primitives a segment misses but list each primitive in more cells; on 10^6 spheres 256
// renders fastest (of 64 to 1024), and on 10^2 spheres two cells per size (of 1 to 8).
// `median` is that of the sizes of the primitives at a finite, nonzero distance.
int resolutionFor(double median) {
  if (!(median > 0)) return 256;
  return int(std::clamp(std::ceil(4 / median), 8.0, 256.0));
}

// The apparent size of primitives [lo, hi) from the light, where it has one, appended to `out`.
void sizesFrom(const Vec3& light, const std::vector<LightBuffer::Occluder>& occluders, size_t lo, size_t hi,
               std::vector<float>& out) {
  for (size_t i = lo; i < hi; ++i) {
    const Bounds& box = occluders[i].box;
    const double d = length(box.centroid() - light);
    const float size = float(length(box.extent()) / d);
    if (d > 0 && std::isfinite(d) && !std::isnan(size)) out.push_back(size);
  }
}

// The angle between two unit vectors, accurate for small angles too (acos of the dot
// product is not).
double angleBetween(const Vec3& x, const Vec3& y) { return 2 * std::atan2(length(x - y), length(x + y)); }

// The directions from the light that may meet a ball: a cone about the ball's direction,
// half-angle asin(radius / distance), widened like the footprints by the margin and the
// rounding (the ball's own hit test is exact to far less than 1e-9 radians). None when the
// ball is missing or holds the light: the box's footprint alone decides.
struct Cone {
  Vec3 axis;                        // unit
  double sinHalf = 0, cosHalf = 0;  // of half the cone's half-angle
  bool any = false;
};

// The half-angle is (asin(r / d) + widening) / 2. Its sine and cosine come from half-angle
// and sum identities rather than from asin, sin and cos, which a big scene would call for
// every (light, sphere) pair: with s = r / d and c = sqrt(1 - s^2), sin(asin(s) / 2) =
// s / sqrt(2 (1 + c)) and cos(asin(s) / 2) = sqrt((1 + c) / 2), both without cancellation;
// their few ulps of rounding are far below the 1e-9 radians of widening.
Cone coneOf(const LightBuffer::Occluder& o, const Vec3& light) {
  static const double kWiden = 0.5 * (2 * LightBuffer::kMargin + 1e-9);
  static const double kSinWiden = std::sin(kWiden), kCosWiden = std::cos(kWiden);
  Cone cone;
  const Vec3 c = o.center - light;
  const double d = length(c);
  if (!(o.radius < d) || !std::isfinite(d)) return cone;
  const double s = o.radius / d;
  const double cosA = std::sqrt((1 - s) * (1 + s));
  const double sinHalfA = s / std::sqrt(2 * (1 + cosA)), cosHalfA = std::sqrt(0.5 * (1 + cosA));
  cone = {c / d, sinHalfA * kCosWiden + cosHalfA * kSinWiden, cosHalfA * kCosWiden - sinHalfA * kSinWiden, true};
  return cone;
}

// Each cell's centre direction in face coordinates, (1, u, v) / |(1, u, v)|, and its
// angular radius (the largest angle to a corner: the directions within an angle of the
// centre form a convex region of the face, so holding the corners it holds the cell). The
// same for every face, so kept for one.
class CellCones {
 public:
  CellCones(int res, int threads) : res_(res), cells_(size_t(res) * res) {
    const auto unit = [](double u, double v) { return normalize(Vec3{1, u, v}); };
    parallelIndices(size_t(res), threads, [&](size_t row) {
      const int j = int(row);
      for (int i = 0; i < res; ++i) {
        const double u0 = 2.0 * i / res - 1, u1 = 2.0 * (i + 1) / res - 1;
        const double v0 = 2.0 * j / res - 1, v1 = 2.0 * (j + 1) / res - 1;
        const Vec3 centre = unit(0.5 * (u0 + u1), 0.5 * (v0 + v1));
        double radius = 0;
        for (double u : {u0, u1})
          for (double v : {v0, v1}) radius = std::max(radius, angleBetween(centre, unit(u, v)));
        radius += 1e-9;  // the lookup's rounding of a direction on an edge
        cells_[size_t(j) * res + i] = {centre, std::sin(radius / 2), std::cos(radius / 2)};
      }
    });
  }
  int resolution() const { return res_; }
  // A direction in the frame of `face`'s cells: (along the face's axis, u, v).
  static Vec3 inFaceFrame(const Vec3& d, int face) {
    const int a = face / 2, b = (a + 1) % 3, c = (a + 2) % 3;
    return {face % 2 ? -d[a] : d[a], d[b], d[c]};
  }
  // Whether the cone may meet cell (i, j) of the face where its axis is `axis`
  // (inFaceFrame). Two cones meet when the angle between their axes is at most the sum of
  // their half-angles, i.e. when the chord between the axes is at most 2 sin of half that
  // sum (a well-conditioned test, unlike a dot product).
  bool meets(const Cone& cone, const Vec3& axis, int i, int j) const {
    const Cell& cell = cells_[size_t(j) * res_ + i];
    const double cosSum = cell.cosHalf * cone.cosHalf - cell.sinHalf * cone.sinHalf;
    if (cosSum <= 0) return true;  // the half-angles add up to a half-turn or more
    const double sinSum = cell.sinHalf * cone.cosHalf + cell.cosHalf * cone.sinHalf;
    const Vec3 chord = axis - cell.centre;
    return dot(chord, chord) <= 4 * sinSum * sinSum;
  }

 private:
  struct Cell {
    Vec3 centre;
    double sinHalf, cosHalf;  // of half the angular radius
  };
  int res_;
  std::vector<Cell> cells_;
};

// Calls visit(cell index) for each cell where a primitive may be seen: within its box's
// footprint on a face and, if it has one, its ball's cone.
template <class F>
void forEachCell(const Footprint (&f)[6], const Cone& cone, const CellCones& cones, F&& visit) {
  for (int face = 0; face < 6; ++face) {
    if (!f[face].any) continue;
    const Vec3 axis = CellCones::inFaceFrame(cone.axis, face);
    for (int j = f[face].j0; j <= f[face].j1; ++j)
      for (int i = f[face].i0; i <= f[face].i1; ++i)
        if (!cone.any || cones.meets(cone, axis, i, j)) visit(face, i, j);
  }
}

// Every (cell, entry) pair of a light's block of primitives, as its footprints and cones give
// them, and the primitives seen from everywhere.
struct Listing {
  uint32_t cell;
  LightBuffer::Entry entry;
};
struct Part {
  std::vector<Listing> listings;
  std::vector<uint32_t> everywhere;
};

}  // namespace

struct LightBuffer::BuildShared {
  Bounds scene;                                   // around every occluder
  std::vector<std::unique_ptr<CellCones>> cones;  // one for each resolution a light has had
  // The batches' listings, kept from batch to batch (emptied, not freed, while they fit in the
  // next batch's share): a big scene's lights go one a batch, and each would otherwise fault
  // in tens of MB of fresh pages.
  std::vector<Part> parts;

  const CellCones& conesFor(int res, int threads) {
    auto found = std::find_if(cones.begin(), cones.end(), [&](const auto& c) { return c->resolution() == res; });
    if (found == cones.end()) found = cones.insert(cones.end(), std::make_unique<CellCones>(res, threads));
    return **found;
  }
};

namespace {

Bounds boundsOf(const std::vector<LightBuffer::Occluder>& occluders, int threads) {
  const Blocks blocks(occluders.size(), threads, kGrain);
  std::vector<Bounds> parts(blocks.count);
  parallelBlocks(blocks, threads, [&](size_t b, size_t lo, size_t hi) {
    for (size_t i = lo; i < hi; ++i) parts[b].extend(occluders[i].box);
  });
  Bounds all;
  for (const Bounds& b : parts) all.extend(b);
  return all;
}

}  // namespace

LightBuffer::LightBuffer(const Vec3& light, const std::vector<Occluder>& occluders, int threads)
    : LightBuffer(std::move(build({&light, 1}, occluders, threads)[0])) {}

// Batches of lights in order. A batch may hold what is left of the budget: each of its
// lights gets an equal share for its cells and its listings, and a light whose listings
// outgrow its share gets no buffer. What the batch keeps is then taken off the budget.
std::vector<LightBuffer> LightBuffer::build(std::span<const Vec3> lights, const std::vector<Occluder>& occluders,
                                            int threads, size_t memoryBytes) {
  std::vector<LightBuffer> out(lights.size());
  const size_t batch = std::max<size_t>(1, kBatchPairs / std::max<size_t>(1, occluders.size()));
  size_t left = memoryBytes;
  BuildShared shared;
  shared.scene = boundsOf(occluders, threads);
  for (size_t first = 0; first < lights.size() && !interrupt::requested(); first += batch) {
    const size_t n = std::min(batch, lights.size() - first);
    std::vector<LightBuffer> built = buildBatch(lights.subspan(first, n), occluders, threads, left / n, shared);
    bool anyFit = false;
    for (size_t k = 0; k < n; ++k) {
      anyFit = anyFit || !built[k].overMemoryLimit();
      left -= std::min(left, built[k].bytes());
      out[first + k] = std::move(built[k]);
    }
    // A batch none of whose lights fit in its share: the budget is spent. The lights after it
    // go without a buffer rather than each costing a pass over the primitives to find that out
    // (10^5 spheres under 1000 lights: 26 s of a build that made 16 buffers).
    if (!anyFit) {
      for (size_t k = first + n; k < lights.size(); ++k) out[k].overMemoryLimit_ = true;
      break;
    }
  }
  return out;
}

// All the lights' buffers at once, each step one parallel loop over the lights' blocks of
// primitives or cells: a scene has fewer lights than a machine has threads.
std::vector<LightBuffer> LightBuffer::buildBatch(std::span<const Vec3> lights, const std::vector<Occluder>& occluders,
                                                 int threads, size_t shareBytes, BuildShared& kept) {
  const size_t count = lights.size();
  std::vector<LightBuffer> out(count);
  const Blocks blocks(occluders.size(), threads, kGrain);
  // A light's block: [lo, hi) of the primitives (or of the cells).
  struct Piece {
    size_t light, block;
  };
  std::vector<Piece> pieces;
  for (size_t l = 0; l < count; ++l)
    for (size_t b = 0; b < blocks.count; ++b) pieces.push_back({l, b});

  // The resolution: the median of the apparent sizes, found on one thread a light.
  std::vector<std::vector<float>> sizes(pieces.size());
  parallelIndices(pieces.size(), threads, [&](size_t p) {
    sizes[p].reserve(blocks.end(pieces[p].block) - blocks.begin(pieces[p].block));
    sizesFrom(lights[pieces[p].light], occluders, blocks.begin(pieces[p].block), blocks.end(pieces[p].block),
              sizes[p]);
  });
  // A batch of one light (a big scene's) counts each digit of its median on every thread; a
  // batch of many finds one light's median on each.
  parallelIndices(count, count == 1 ? 1 : threads, [&](size_t l) {
    const std::span<const std::vector<float>> all(sizes.data() + l * blocks.count, blocks.count);
    const float median = parallelMedian(all, count == 1 ? threads : 1);
    out[l].light_ = lights[l];
    out[l].res_ = std::isnan(median) ? 8 : resolutionFor(median);
  });
  std::vector<std::vector<float>>().swap(sizes);
  // Each light's windows: the footprint of the box around every primitive on each face (a
  // primitive's box lies inside it, its footprint inside the window). Then the resolution is
  // lowered, if need be, until the windows hold at most kCellsPerPrimitive cells a primitive.
  const Bounds& scene = kept.scene;
  const size_t mostCells = std::max<size_t>(6 * 8 * 8, kCellsPerPrimitive * occluders.size());
  parallelIndices(count, threads, [&](size_t l) {
    LightBuffer& b = out[l];
    const RelativeBox box(scene, lights[l]);
    for (;;) {
      uint32_t base = 0;
      Footprint seen[6] = {};
      if (!box.holdsLight() && !scene.empty()) footprints(box, b.res_, seen);
      for (int face = 0; face < 6; ++face) {
        const Footprint f = box.holdsLight() ? Footprint{0, b.res_ - 1, 0, b.res_ - 1, true} : seen[face];
        b.windows_[face] = f.any ? Window{f.i0, f.j0, f.i1 - f.i0 + 1, f.j1 - f.j0 + 1, base} : Window{0, 0, 0, 0, base};
        base += uint32_t(f.cells());
      }
      b.emptyCell_ = int(base);
      if (base <= mostCells || b.res_ <= 8) break;
      // A multiple of 8, so that the lights share few resolutions (each has its CellCones).
      b.res_ = std::max(8, int(double(b.res_) * std::sqrt(double(mostCells) / double(base))) / 8 * 8);
    }
  });
  std::vector<const CellCones*> conesOf(count);
  for (size_t l = 0; l < count; ++l) conesOf[l] = &kept.conesFor(out[l].res_, threads);

  // Every (cell, entry) pair as the footprints and cones give them, a block of primitives at
  // a time, then moved to their cells: each footprint and cone is worked out once.
  // Each light's entries: at most kEntriesPerPrimitive a primitive (`usual`), and what its
  // equal share of the batch's memory leaves beside its cells. Where a share is short of
  // that (`tight`) and a light's entries outgrow it, the batch's memory goes to its lights in
  // order instead, each taking what it needs while that fits, so that the lights left without
  // a buffer are the last ones, whatever the number of threads: each light's entries are
  // counted (a second pass over the footprints, only then) and listed again. Where every
  // light's entries fit its equal share, that order would give each what it listed.
  const size_t usual = kEntriesPerPrimitive * occluders.size() + 65536;
  const auto cellBytes = [&](size_t l) { return (size_t(out[l].emptyCell_) + 2) * kBuildBytesPerCell; };
  std::vector<size_t> budget(count);
  std::vector<char> overLimit(count, 0);
  bool tight = false;
  for (size_t l = 0; l < count; ++l) {
    budget[l] = std::min(usual, shareBytes > cellBytes(l) ? (shareBytes - cellBytes(l)) / kBuildBytesPerEntry : 0);
    tight = tight || budget[l] < usual;
  }
  std::vector<Part>& parts = kept.parts;
  // What the batches before left counts toward this batch's share; more than the share is given
  // back first, so that the build never holds more than its memory limit allows.
  size_t retained = 0;
  for (const Part& part : parts)
    retained += part.listings.capacity() * sizeof(Listing) + part.everywhere.capacity() * sizeof(uint32_t);
  if (retained > shareBytes * count) std::vector<Part>().swap(parts);
  if (parts.size() < pieces.size()) parts.resize(pieces.size());
  std::vector<std::atomic<size_t>> listed(count);  // by a light's blocks done so far
  const auto listWithinBudgets = [&] {
    for (Part& part : parts) {
      part.listings.clear();
      part.everywhere.clear();
    }
    for (std::atomic<size_t>& n : listed) n = 0;
    parallelIndices(pieces.size(), threads, [&](size_t p) {
      const size_t l = pieces[p].light;
      const Vec3& light = lights[l];
      const int res = out[l].res_;
      Part& part = parts[p];
      if (budget[l] == 0) return;  // not even its cells fit
      part.listings.reserve(2 * (blocks.end(pieces[p].block) - blocks.begin(pieces[p].block)));
      for (size_t i = blocks.begin(pieces[p].block); i < blocks.end(pieces[p].block); ++i) {
        if (occluders[i].box.empty()) continue;
        const RelativeBox box(occluders[i].box, light);
        Footprint f[6];
        const int cellsSeen = footprints(box, res, f);
        if (box.holdsLight() || cellsSeen > kCrowded) {
          part.everywhere.push_back(uint32_t(i));
          continue;
        }
        const Entry e{uint32_t(i), roundDown(box.distance())};
        const LightBuffer& buffer = out[l];
        forEachCell(f, coneOf(occluders[i], light), *conesOf[l], [&](int face, int ci, int cj) {
          part.listings.push_back({uint32_t(buffer.cellIndex(face, ci, cj)), e});
        });
        // No buffer (below) once the budget is spent: no need to list the rest.
        if (part.listings.size() > budget[l] || listed[l].load(std::memory_order_relaxed) > budget[l]) break;
        if ((i & 1023) == 0 && interrupt::requested()) break;  // the buffers are thrown away
      }
      listed[l] += part.listings.size();
    });
  };
  listWithinBudgets();
  bool outgrown = false;
  for (size_t l = 0; l < count; ++l) outgrown = outgrown || budget[l] == 0 || listed[l] > budget[l];
  if (tight && outgrown && !interrupt::requested()) {
    std::vector<size_t> counted(pieces.size(), 0);
    parallelIndices(pieces.size(), threads, [&](size_t p) {
      const size_t l = pieces[p].light;
      for (size_t i = blocks.begin(pieces[p].block); i < blocks.end(pieces[p].block) && counted[p] <= usual; ++i) {
        if (occluders[i].box.empty()) continue;
        const RelativeBox box(occluders[i].box, lights[l]);
        Footprint f[6];
        const int cellsSeen = footprints(box, out[l].res_, f);
        if (box.holdsLight() || cellsSeen > kCrowded) continue;
        forEachCell(f, coneOf(occluders[i], lights[l]), *conesOf[l], [&](int, int, int) { ++counted[p]; });
      }
    });
    size_t left = shareBytes * count;
    for (size_t l = 0; l < count; ++l) {
      size_t n = 0;
      for (size_t b = 0; b < blocks.count; ++b) n += counted[l * blocks.count + b];
      const size_t need = cellBytes(l) + std::min(n, usual + 1) * kBuildBytesPerEntry;
      if (n > usual) {
        budget[l] = 0;  // too many entries: no buffer, as without a limit
      } else if (need <= left) {
        budget[l] = n;
        left -= need;
      } else {
        budget[l] = 0;
        overLimit[l] = 1;
      }
    }
    listWithinBudgets();
  }
  std::vector<size_t> cells(count, 0);  // 0 for a light left without a buffer
  for (size_t l = 0; l < count; ++l) {
    LightBuffer& buffer = out[l];
    for (size_t b = 0; b < blocks.count; ++b) {
      const std::vector<uint32_t>& e = parts[l * blocks.count + b].everywhere;
      buffer.everywhere_.insert(buffer.everywhere_.end(), e.begin(), e.end());
    }
    buffer.overMemoryLimit_ = overLimit[l] || (!tight && budget[l] < usual && (budget[l] == 0 || listed[l] > budget[l]));
    if (buffer.everywhere_.size() > kMaxEverywhere || listed[l] > budget[l] || budget[l] == 0 ||
        interrupt::requested()) {
      // Too many primitives too big for cells: the BVH answers this light's segments better.
      buffer.everywhere_.clear();
      for (size_t b = 0; b < blocks.count; ++b) parts[l * blocks.count + b].listings.clear();
      continue;
    }
    cells[l] = size_t(buffer.emptyCell_) + 1;
  }
  // Each cell's entries in the order the blocks happen to put them there, then sorted: the
  // lists are the same whatever that order. The cells' counts, then cursors, are updated
  // atomically where several threads share them.
  const bool shared = (threads > 0 ? threads : threadBudget()) > 1;
  const auto bump = [shared](uint32_t& n) {
    return shared ? std::atomic_ref<uint32_t>(n).fetch_add(1, std::memory_order_relaxed) : n++;
  };
  std::vector<std::vector<uint32_t>> filled(count);
  parallelIndices(count, threads, [&](size_t l) { filled[l].assign(cells[l], 0); });
  parallelIndices(pieces.size(), threads, [&](size_t p) {
    for (const Listing& x : parts[p].listings) bump(filled[pieces[p].light][x.cell]);
  });
  parallelIndices(count, threads, [&](size_t l) {
    if (cells[l] == 0) return;
    LightBuffer& buffer = out[l];
    buffer.offsets_.resize(cells[l] + 1);
    buffer.offsets_[0] = 0;
    for (size_t c = 0; c < cells[l]; ++c) {
      buffer.offsets_[c + 1] = buffer.offsets_[c] + filled[l][c];
      filled[l][c] = buffer.offsets_[c];
    }
  });
  // Tens of MB for a big scene's light: its pages faulted in by every thread, not by one.
  for (size_t l = 0; l < count; ++l)
    if (cells[l] != 0) resizePrefaulted(out[l].entries_, out[l].offsets_[cells[l]], threads);
  parallelIndices(pieces.size(), threads, [&](size_t p) {
    std::vector<Entry>& entries = out[pieces[p].light].entries_;
    std::vector<uint32_t>& at = filled[pieces[p].light];
    for (const Listing& x : parts[p].listings) entries[bump(at[x.cell])] = x.entry;
    parts[p].listings.clear();
  });
  constexpr size_t kCellsAtATime = 1024;
  std::vector<Piece> cellRuns;  // a light's cells [block x kCellsAtATime, ...)
  for (size_t l = 0; l < count; ++l)
    for (size_t k = 0; k * kCellsAtATime < cells[l]; ++k) cellRuns.push_back({l, k});
  parallelIndices(cellRuns.size(), threads, [&](size_t r) {
    LightBuffer& buffer = out[cellRuns[r].light];
    const size_t first = cellRuns[r].block * kCellsAtATime;
    for (size_t c = first; c < std::min(cells[cellRuns[r].light], first + kCellsAtATime); ++c)
      std::sort(buffer.entries_.begin() + buffer.offsets_[c], buffer.entries_.begin() + buffer.offsets_[c + 1],
                [](const Entry& x, const Entry& y) { return sortKey(x) < sortKey(y); });
  });
  return out;
}

int LightBuffer::cellIndexOf(const Vec3& d) const {
  const double x = std::fabs(d.x), y = std::fabs(d.y), z = std::fabs(d.z);
  const int a = z > std::max(x, y) ? 2 : y > x ? 1 : 0;
  const double w = std::fabs(d[a]);
  if (offsets_.empty() || !(w > 0) || !std::isfinite(w)) return -1;
  const int b = (a + 1) % 3, c = (a + 2) % 3;
  const int face = 2 * a + (d[a] < 0 ? 1 : 0);
  return cellIndex(face, cellOf(d[b] / w, res_), cellOf(d[c] / w, res_));
}

bool LightBuffer::cell(const Vec3& d, std::span<const Entry>& out) const {
  const int index = cellIndexOf(d);
  if (index < 0) return false;
  out = list(index);
  return true;
}

// Every step of cellIndexOf is monotone in the components, rounding included (a correctly
// rounded sum, product or quotient never reverses an order), so over the box the face is
// one when one axis's magnitude beats the others' at every corner, and the cells along a
// side lie between those of the box's extreme quotients.
int LightBuffer::commonCell(const Vec3& lo, const Vec3& hi) const {
  if (offsets_.empty()) return -1;
  double least[3], most[3];  // the range of |d[a]| over the box
  for (int a = 0; a < 3; ++a) {
    if (!(lo[a] <= hi[a]) || !std::isfinite(lo[a]) || !std::isfinite(hi[a])) return -1;
    least[a] = lo[a] > 0 ? lo[a] : hi[a] < 0 ? -hi[a] : 0.0;
    most[a] = std::max(std::fabs(lo[a]), std::fabs(hi[a]));
  }
  // cellIndexOf's choice: z if |z| > max(|x|, |y|), else y if |y| > |x|, else x.
  int a;
  if (least[2] > std::max(most[0], most[1])) a = 2;
  else if (least[1] > most[0] && most[2] <= least[1]) a = 1;
  else if (least[0] > 0 && most[1] <= least[0] && most[2] <= least[0]) a = 0;
  else return -1;
  // |d[a]| > 0 throughout, so d[a] keeps one sign and the quotients below are monotone.
  const int b = (a + 1) % 3, c = (a + 2) % 3;
  const double wLo = least[a], wHi = most[a];
  auto side = [&](int axis, int& i) {
    const double uLo = lo[axis] / (lo[axis] >= 0 ? wHi : wLo), uHi = hi[axis] / (hi[axis] >= 0 ? wLo : wHi);
    i = cellOf(uLo, res_);
    return cellOf(uHi, res_) == i;
  };
  int i, j;
  if (!side(b, i) || !side(c, j)) return -1;
  return cellIndex(2 * a + (hi[a] < 0 ? 1 : 0), i, j);
}

}  // namespace pvrt
