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
//   sequence: a low-discrepancy sequence (Roberts' R2, the additive recurrence of the
//           plastic number), shifted at random per pixel (from (pixel, seed)). Sample k
//           does not depend on c, so the first c samples of any larger c are the c
//           samples: a render can go in passes of more samples and stop between them
//           (a time budget, render/passes.h), with the image of --spp c. Each sample is
//           traced on its own (restartsAt()).
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

enum class SamplerKind { Pov, Grid, Jitter, Sequence };

struct SamplerSettings {
  SamplerKind kind = SamplerKind::Pov;
  int samplesPerPixel = 1;  // c; a perfect square for pov and grid, any c >= 1 for jitter and sequence
  uint64_t seed = 0;        // jitter and sequence
  // POV-Ray's antialiasing threshold and method (pov only). Threshold 0 with method 1 is
  // the plain pov sampler (every pixel supersampled); c = 1 is -A whatever they say.
  AdaptiveSettings adaptive = {};
  // sequence only: this render traces samples [firstSample, samplesPerPixel) of each pixel,
  // one pass of a render in passes (render/passes.h).
  int firstSample = 0;
};

class PixelSampler {
 public:
  explicit PixelSampler(const SamplerSettings& settings);

  // The sub-pixel offsets of pixel (x, y), in a fixed order: samples [firstSample(),
  // count()). Their colours are summed in that order and divided by count() — the same
  // arithmetic on every backend.
  void offsets(int x, int y, std::vector<SubSample>& out) const;
  int count() const { return count_; }
  int firstSample() const { return first_; }
  // Whether offsets() gives every pixel the same offsets (pov and grid; not jitter or
  // sequence, which shift them pixel by pixel).
  bool sameOffsetsEveryPixel() const { return s_.kind == SamplerKind::Pov || s_.kind == SamplerKind::Grid; }
  // Whether the shadow cache starts empty at sample k of a pixel (render/tracer.h keeps it
  // from one sample to the next within a pixel, as POV-Ray keeps it from ray to ray): at
  // sample 0 for every sampler, and at every sample for sequence, whose samples are each
  // traced on their own, so that a pixel is the same bits however a render in passes cuts
  // its samples.
  bool restartsAt(int k) const { return k == 0 || s_.kind == SamplerKind::Sequence; }
  // POV-Ray's +R n: the side of the grid (1 for c = 1).
  int depth() const { return rows_; }
  // True when pixels are rendered by render/adaptive.h rather than by offsets().
  bool adaptive() const { return adaptive_; }
  const AdaptiveSettings& adaptiveSettings() const { return s_.adaptive; }
  // True for --pov-blocks at one ray a pixel (POV-Ray's -A): the pixels are traced block by
  // block in POV-Ray's order, the shadow cache kept from pixel to pixel within a block.
  bool blockCache() const { return blockCache_; }
  // The side of the squares whose pixels must be rendered together: work items are cut
  // along multiples of it (POV-Ray's block when adaptive or blockCache(), else 1).
  int blockGranule() const { return adaptive_ || blockCache_ ? s_.adaptive.blockSize : 1; }

 private:
  void validateAdaptive();
  SamplerSettings s_;
  int rows_ = 1, cols_ = 1;  // the strata: rows_ x cols_ cells
  int count_ = 1;
  int first_ = 0;
  bool adaptive_ = false;
  bool blockCache_ = false;
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
