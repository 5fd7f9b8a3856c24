// Where the rays of one pixel go and how they are weighted (the paper's supersampling
// coefficient c = samples per pixel).
//   pov:    POV-Ray's +A0.0 +AM1 +Rn -J: the centre ray plus an n x n grid at POV-Ray's offsets
//           (-1/2 + (k+1/2)/n summed up as POV-Ray does), all n*n+1 rays weighted equally.
//           c = n*n; c = 1 is -A.
//   grid:   an n x n grid at cell centres, equal weights (c = n*n).
//   jitter: one random point in each cell of an n x n grid, seeded from
//           (pixel, sample, seed) so the image never depends on the thread.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace pvrt {

enum class SamplerKind { Pov, Grid, Jitter };

struct SamplerSettings {
  SamplerKind kind = SamplerKind::Pov;
  int samplesPerPixel = 1;  // c; must be a perfect square
  uint64_t seed = 0;        // jitter only
};

struct SubSample {
  double dx, dy;  // offset from the pixel centre, in pixels (dy downward)
};

class PixelSampler {
 public:
  explicit PixelSampler(const SamplerSettings& settings);

  // The sub-pixel offsets of pixel (x, y), in a fixed order. Their colours are summed in
  // that order and divided by count() — the same arithmetic on every backend.
  void offsets(int x, int y, std::vector<SubSample>& out) const;
  int count() const { return count_; }
  int gridSide() const { return n_; }

 private:
  SamplerSettings s_;
  int n_ = 1;
  int count_ = 1;
  std::vector<SubSample> fixed_;
};

SamplerKind parseSamplerKind(const std::string& name);  // throws pvrt::Error(Usage)
const char* samplerName(SamplerKind kind);
// Exact integer square root, or -1 when c is not a perfect square.
int perfectSquareRoot(int c);

}  // namespace pvrt
