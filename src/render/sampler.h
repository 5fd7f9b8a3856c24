// Where the rays of one pixel go and how they are weighted (the paper's supersampling
// coefficient c = samples per pixel).
//   pov:    POV-Ray's +A0.0 +AM1 +Rn -J: the centre ray plus an n x n grid at POV-Ray's offsets
//           (-1/2 + (k+1/2)/n summed up as POV-Ray does), all n*n+1 rays weighted equally.
//           c = n*n; c = 1 is -A.
//   grid:   an n x n grid at cell centres, equal weights (c = n*n).
//   jitter: one random point in each cell of an n x m grid (n rows, m columns, n*m = c,
//           n the largest divisor of c not above sqrt(c): any c >= 1, and n x n when c
//           is a square), seeded from (pixel, sample, seed) so the image never depends
//           on the thread.
// With `adaptive` (pov only) the pov sampler is POV-Ray's +A<t> +AM1 or +AM2 +Rn -J instead
// (render/adaptive.h): which pixels get more rays depends on their neighbours, so the
// kernel renders whole POV-Ray blocks (blockGranule()).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "render/adaptive.h"
#include "render/sample_offset.h"

namespace pvrt {

enum class SamplerKind { Pov, Grid, Jitter };

struct SamplerSettings {
  SamplerKind kind = SamplerKind::Pov;
  int samplesPerPixel = 1;  // c; a perfect square for pov and grid, any c >= 1 for jitter
  uint64_t seed = 0;        // jitter only
  // POV-Ray's antialiasing threshold and method (pov only). Threshold 0 with method 1 is
  // the plain pov sampler (every pixel supersampled); c = 1 is -A whatever they say.
  AdaptiveSettings adaptive = {};
};

class PixelSampler {
 public:
  explicit PixelSampler(const SamplerSettings& settings);

  // The sub-pixel offsets of pixel (x, y), in a fixed order. Their colours are summed in
  // that order and divided by count() — the same arithmetic on every backend.
  void offsets(int x, int y, std::vector<SubSample>& out) const;
  int count() const { return count_; }
  // POV-Ray's +R n: the side of the grid (1 for c = 1).
  int depth() const { return rows_; }
  // True when pixels are rendered by render/adaptive.h rather than by offsets().
  bool adaptive() const { return adaptive_; }
  const AdaptiveSettings& adaptiveSettings() const { return s_.adaptive; }
  // The side of the squares whose pixels must be rendered together: work items are cut
  // along multiples of it (POV-Ray's block when adaptive, else 1).
  int blockGranule() const { return adaptive_ ? s_.adaptive.blockSize : 1; }

 private:
  void validateAdaptive();
  SamplerSettings s_;
  int rows_ = 1, cols_ = 1;  // the strata: rows_ x cols_ cells
  int count_ = 1;
  bool adaptive_ = false;
  std::vector<SubSample> fixed_;
};

SamplerKind parseSamplerKind(const std::string& name);  // throws pvrt::Error(Usage)
const char* samplerName(SamplerKind kind);
// Exact integer square root, or -1 when c is not a perfect square.
int perfectSquareRoot(int c);
// The rows of the jitter sampler's strata for c samples: the largest divisor of c that is at
// most sqrt(c) (so c / rows >= rows columns; 1 for a prime c).
int stratumRows(int c);

}  // namespace pvrt
