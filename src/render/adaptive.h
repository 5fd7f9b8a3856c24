// POV-Ray's adaptive antialiasing (+A<t> with +AM1 or +AM2, jitter off), decision for
// decision (source/backend/render/tracetask.cpp of POV-Ray 3.7; the facts are in
// shared/povray-semantics.md section 2).
//
// Both methods work on POV-Ray's render blocks (+BS, 32 x 32 pixels from the image's
// top-left corner) and never look outside the block they render, so the image depends
// on the block size but not on which thread, rank or schedule renders a block:
//   method 1  every pixel gets its centre ray; a pixel is supersampled (the centre plus an
//             n x n grid, as the pov sampler) when its colour differs from its left or top
//             neighbour's by at least the threshold, and so is that neighbour if it was
//             not yet. Pixels are visited row by row, so a neighbour may already hold its
//             supersampled colour when it is compared. The row above a block and the
//             column left of it are traced afresh (centre rays) and count as done.
//   method 2  rays at pixel corners (shared by the pixels of a block); a cell whose four
//             corners differ pairwise by at least the threshold is split into four, down to
//             n - 1 levels, tracing the edge midpoints and the centre; a cell's colour is the
//             mean of its four corners, a split cell's the mean of its four quarters.
// Colours are POV-Ray's float colours, compared after its antialiasing gamma (2.5):
// |dr| + |dg| + |db| >= threshold, in float.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "render/sample_offset.h"

namespace pvrt {

struct AdaptiveSettings {
  double threshold = 0;  // +A t (0 to 1)
  int method = 1;        // +AM 1 or 2
  int blockSize = 32;    // +BS (at least 4)
  // --pov-blocks: trace threshold 0 (+A0.0) as POV-Ray does, block by block through the
  // method-1 kernel (every pixel supersampled, the shadow cache kept within each block),
  // rather than pixel by pixel with the cache restarted at each pixel.
  bool blocks = false;
};

// POV-Ray's colour: three floats (its transmit channel is 0 without alpha output).
struct FloatRgb {
  float r = 0, g = 0, b = 0;
};

// The comparison POV-Ray makes: both colours through the power law x^(1/2.5) (negative
// channels as 0), then the sum of the channels' absolute differences against the
// threshold, which POV-Ray holds as a float.
class ColourTest {
 public:
  explicit ColourTest(double threshold) : threshold_(float(threshold)) {}
  static FloatRgb encode(FloatRgb c) {
    constexpr float kEncode = 1.0f / 2.5f;
    return {std::pow(std::max(c.r, 0.0f), kEncode), std::pow(std::max(c.g, 0.0f), kEncode),
            std::pow(std::max(c.b, 0.0f), kEncode)};
  }
  bool differ(FloatRgb a, FloatRgb b) const { return differEncoded(encode(a), encode(b)); }
  // The same test on colours already through encode(): POV-Ray encodes a colour again
  // for every comparison, pvrt once per sample (the same bits, a sixth of the powf calls).
  bool differEncoded(FloatRgb x, FloatRgb y) const {
    const float d = std::fabs(x.r - y.r) + std::fabs(x.g - y.g) + std::fabs(x.b - y.b);
    return d >= threshold_;
  }

 private:
  float threshold_;
};

// What the block algorithms ask of their `source` (the renderer's tracer, or a test's picture):
//   void row(int x, int y, int count, double dx, double dy, FloatRgb* out)
//       rays at (x + i + dx, y + dy) for i < count, pixels outside the image included;
//       a row at a time, so that they can be traced as a packet
//   void several(int x, int y, const SubSample* offsets, int count, FloatRgb* out)
//       rays of pixel (x, y) at these offsets from its centre
//   FloatRgb supersample(int x, int y, FloatRgb first)   (first + n x n grid) / (n*n + 1)
//   void put(int x, int y, FloatRgb c)                    a finished pixel of the block
// Rays are asked for earlier than POV-Ray traces them (a row of centres before the row's
// decisions, say); nothing but the order of the tracer's shadow cache can tell.

// One POV-Ray block [x0,x1) x [y0,y1) by method 1.
template <class Source>
void antialiasBlockMethod1(int x0, int y0, int x1, int y1, const ColourTest& test, Source& source) {
  // The block and a frame of one pixel above and left: cell (x, y) at [(y-y0+1)*w + x-x0+1].
  const int w = x1 - x0 + 1;
  std::vector<FloatRgb> colour(size_t(w) * (y1 - y0 + 1)), encoded(colour.size());
  std::vector<char> done(colour.size(), 0);
  auto at = [&](int x, int y) { return size_t(y - y0 + 1) * w + size_t(x - x0 + 1); };
  auto supersample = [&](int x, int y, size_t i) {
    colour[i] = source.supersample(x, y, colour[i]);
    encoded[i] = ColourTest::encode(colour[i]);
    done[i] = 1;
  };
  source.row(x0, y0 - 1, x1 - x0, 0.0, 0.0, &colour[at(x0, y0 - 1)]);
  for (int x = x0; x < x1; ++x) {
    encoded[at(x, y0 - 1)] = ColourTest::encode(colour[at(x, y0 - 1)]);
    done[at(x, y0 - 1)] = 1;  // the block above's: never supersampled here
  }
  for (int y = y0; y < y1; ++y) {
    // The centre rays of the column left of the block (done, like the row above) and of the row.
    source.row(x0 - 1, y, x1 - x0 + 1, 0.0, 0.0, &colour[at(x0 - 1, y)]);
    for (int x = x0 - 1; x < x1; ++x) encoded[at(x, y)] = ColourTest::encode(colour[at(x, y)]);
    done[at(x0 - 1, y)] = 1;
    for (int x = x0; x < x1; ++x) {
      const size_t cur = at(x, y), left = at(x - 1, y), top = at(x, y - 1);
      const bool leftDiff = test.differEncoded(encoded[left], encoded[cur]);
      const bool topDiff = test.differEncoded(encoded[top], encoded[cur]);
      // POV-Ray's order: the left neighbour, the top one, then the pixel itself.
      if (leftDiff && !done[left]) supersample(x - 1, y, left);
      if (topDiff && !done[top]) supersample(x, y - 1, top);
      if (leftDiff || topDiff) supersample(x, y, cur);
    }
  }
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) source.put(x, y, colour[at(x, y)]);
}

namespace adaptive_detail {

inline FloatRgb operator+(FloatRgb a, FloatRgb b) { return {a.r + b.r, a.g + b.g, a.b + b.b}; }
// POV-Ray divides its float colour by a double and stores the quotient as a float.
inline FloatRgb quarter(FloatRgb a) { return {float(a.r / 4.0), float(a.g / 4.0), float(a.b / 4.0)}; }

// The samples of one pixel on a (2^n + 1)^2 lattice, corners at its ends.
struct Lattice {
  size_t size;
  std::vector<FloatRgb> colour, encoded;  // encoded: through ColourTest::encode
  std::vector<char> sampled;
  explicit Lattice(size_t s) : size(s), colour(s * s), encoded(s * s), sampled(s * s, 0) {}
  void set(size_t i, FloatRgb c, FloatRgb e) {
    colour[i] = c;
    encoded[i] = e;
    sampled[i] = 1;
  }
};

// POV-Ray's SubdivideOnePixel: the cell of lattice side `step` at (bx, by), centred at
// (cx, cy) pixels from the pixel's centre with half-side d.
template <class Source>
FloatRgb subdivide(int px, int py, double cx, double cy, double d, size_t bx, size_t by, size_t step,
                   Lattice& lat, int level, const ColourTest& test, Source& source) {
  const size_t i00 = bx + by * lat.size, i02 = bx + (by + step) * lat.size;
  const size_t i20 = bx + step + by * lat.size, i22 = bx + step + (by + step) * lat.size;
  const FloatRgb c00 = lat.colour[i00], c02 = lat.colour[i02], c20 = lat.colour[i20], c22 = lat.colour[i22];
  auto differ = [&](size_t a, size_t b) { return test.differEncoded(lat.encoded[a], lat.encoded[b]); };
  const bool split = level > 0 && (differ(i00, i02) || differ(i00, i20) || differ(i00, i22) || differ(i02, i20) ||
                                   differ(i02, i22) || differ(i20, i22));
  if (!split) return quarter(c00 + c02 + c20 + c22);
  const size_t h = step / 2;
  // Left, top, right and bottom edge midpoints, then the centre, as POV-Ray traces them;
  // those a neighbouring cell has not traced yet go together.
  const struct {
    size_t x, y;
    double dx, dy;
  } mids[5] = {{bx, by + h, cx - d, cy},
               {bx + h, by, cx, cy - d},
               {bx + step, by + h, cx + d, cy},
               {bx + h, by + step, cx, cy + d},
               {bx + h, by + h, cx, cy}};
  SubSample offsets[5];
  size_t where[5];
  int n = 0;
  for (const auto& m : mids)
    if (!lat.sampled[m.x + m.y * lat.size]) {
      offsets[n] = {m.dx, m.dy};
      where[n++] = m.x + m.y * lat.size;
    }
  FloatRgb traced[5];
  if (n > 0) source.several(px, py, offsets, n, traced);
  for (int k = 0; k < n; ++k) lat.set(where[k], traced[k], ColourTest::encode(traced[k]));
  const double d2 = d * 0.5;
  const FloatRgb q00 = subdivide(px, py, cx - d2, cy - d2, d2, bx, by, h, lat, level - 1, test, source);
  const FloatRgb q01 = subdivide(px, py, cx - d2, cy + d2, d2, bx, by + h, h, lat, level - 1, test, source);
  const FloatRgb q10 = subdivide(px, py, cx + d2, cy - d2, d2, bx + h, by, h, lat, level - 1, test, source);
  const FloatRgb q11 = subdivide(px, py, cx + d2, cy + d2, d2, bx + h, by + h, h, lat, level - 1, test, source);
  return quarter(q00 + q01 + q10 + q11);
}

}  // namespace adaptive_detail

// One POV-Ray block [x0,x1) x [y0,y1) by method 2 with POV-Ray's +R depth.
template <class Source>
void antialiasBlockMethod2(int x0, int y0, int x1, int y1, int depth, const ColourTest& test, Source& source) {
  using namespace adaptive_detail;
  // Upper-left corners of the block's pixels and of the row and column after it.
  const int w = x1 - x0 + 1;
  std::vector<FloatRgb> corner(size_t(w) * (y1 - y0 + 1)), encoded(corner.size());
  for (int y = y0; y <= y1; ++y) source.row(x0, y, w, -0.5, -0.5, &corner[size_t(y - y0) * w]);
  for (size_t i = 0; i < corner.size(); ++i) encoded[i] = ColourTest::encode(corner[i]);
  const size_t sub = size_t(1) << depth;
  Lattice lat(sub + 1);
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      std::fill(lat.sampled.begin(), lat.sampled.end(), 0);
      const size_t c = size_t(y - y0) * w + (x - x0);
      lat.set(0, corner[c], encoded[c]);
      lat.set(sub * lat.size, corner[c + w], encoded[c + w]);
      lat.set(sub, corner[c + 1], encoded[c + 1]);
      lat.set(sub + sub * lat.size, corner[c + w + 1], encoded[c + w + 1]);
      source.put(x, y, subdivide(x, y, 0.0, 0.0, 0.5, 0, 0, sub, lat, depth - 1, test, source));
    }
}

}  // namespace pvrt
