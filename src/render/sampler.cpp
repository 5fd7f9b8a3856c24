#include "render/sampler.h"

#include <cmath>

#include <fmt/format.h>

#include "core/error.h"

namespace pvrt {

namespace {

// SplitMix64: a well-mixed hash of the pixel and sample index (Steele et al. 2014).
uint64_t mix(uint64_t z) {
  z += 0x9e3779b97f4a7c15ull;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}
double unitFloat(uint64_t h) { return double(h >> 11) * 0x1.0p-53; }

// POV-Ray's sub-pixel offsets for +Rn (TraceTask::SupersampleOnePixel): a loop that adds
// the step to a running offset, so the offsets are not the exact -1/2 + (k + 1/2)/n
// (for n = 3: -0.33333333333333337, -5.55e-17, 0.33333333333333326). The last bits decide
// which side of a checker cell boundary a sample falls on.
std::vector<double> povOffsets(int n) {
  constexpr double kEpsilon = 1e-10;  // POV-Ray's EPSILON
  const double step = 1.0 / double(n), range = 0.5 - step * 0.5;
  std::vector<double> out;
  for (double d = -range; d <= range + kEpsilon; d += step) out.push_back(d);
  return out;
}

// Roberts' R2 sequence: sample k at frac(shift + k (1/g, 1/g^2)), g the plastic number (the
// real root of x^3 = x + 1). Its first n points are well spread for every n.
constexpr double kPlastic = 1.32471795724474602596;
constexpr double kR2StepX = 1.0 / kPlastic, kR2StepY = 1.0 / (kPlastic * kPlastic);
double fractionOf(double v) { return v - std::floor(v); }

}  // namespace

int perfectSquareRoot(int c) {
  if (c < 1) return -1;
  int n = int(std::lround(std::sqrt(double(c))));
  return n * n == c ? n : -1;
}

int stratumRows(int c) {
  int rows = 1;
  for (int d = 1; int64_t(d) * d <= c; ++d)
    if (c % d == 0) rows = d;
  return rows;
}

PixelSampler::PixelSampler(const SamplerSettings& settings) : s_(settings) {
  const int c = settings.samplesPerPixel;
  if (c < 1) throw Error(ExitCode::Usage, "--spp must be a positive whole number, got " + std::to_string(c));
  if (s_.kind == SamplerKind::Jitter || s_.kind == SamplerKind::Sequence) {
    // Strata of any shape: the paper's c is any whole number (its figures use c = 8).
    rows_ = stratumRows(c);
    cols_ = c / rows_;
  } else {
    // POV-Ray's +Rn grid is square, and so is ours: other c have no such pattern.
    rows_ = cols_ = perfectSquareRoot(c);
    if (rows_ < 1)
      throw Error(ExitCode::Usage, std::string("--spp must be a perfect square (1, 4, 9, 16, ...) for --sampler ") +
                                       samplerName(s_.kind) + ", got " + std::to_string(c) +
                                       " (--sampler jitter takes any c)");
  }
  if (s_.kind == SamplerKind::Pov) {
    fixed_.push_back({0, 0});
    if (c > 1)
      for (double dy : povOffsets(rows_))
        for (double dx : povOffsets(cols_)) fixed_.push_back({dx, dy});
  } else {
    for (int j = 0; j < rows_; ++j)
      for (int i = 0; i < cols_; ++i) fixed_.push_back({-0.5 + (i + 0.5) / cols_, -0.5 + (j + 0.5) / rows_});
  }
  count_ = int(fixed_.size());
  if (s_.firstSample != 0) {
    if (s_.kind != SamplerKind::Sequence)
      throw Error(ExitCode::Usage, "a render in passes needs the sequence sampler");
    if (s_.firstSample < 0 || s_.firstSample >= count_)
      throw Error(ExitCode::Usage, fmt::format("a pass cannot start at sample {} of {}", s_.firstSample, count_));
    first_ = s_.firstSample;
  }
  validateAdaptive();
}

void PixelSampler::validateAdaptive() {
  const AdaptiveSettings& a = s_.adaptive;
  if (!(a.threshold >= 0 && a.threshold <= 1))
    throw Error(ExitCode::Usage, "--aa-threshold must be between 0 and 1 (POV-Ray's +A), got " +
                                     fmt::format("{}", a.threshold));
  if (a.method != 1 && a.method != 2)
    throw Error(ExitCode::Usage, "--aa-method must be 1 or 2 (POV-Ray's +AM), got " + std::to_string(a.method));
  if (a.blockSize < 4)
    throw Error(ExitCode::Usage, "--aa-block must be at least 4 (POV-Ray's +BS), got " + std::to_string(a.blockSize));
  const bool asked = a.threshold > 0 || a.method == 2 || a.blocks;
  if (asked && s_.kind != SamplerKind::Pov)
    throw Error(ExitCode::Usage, std::string("--aa-threshold, --aa-method 2 and --pov-blocks are POV-Ray's "
                                             "antialiasing: they need --sampler pov, not ") +
                                     samplerName(s_.kind));
  if (asked && a.method == 2 && rows_ > 9)
    throw Error(ExitCode::Usage, "--aa-method 2 goes at most 9 levels deep (POV-Ray's +R9, --spp 81), got --spp " +
                                     std::to_string(s_.samplesPerPixel));
  adaptive_ = asked && count_ > 1;
  blockCache_ = a.blocks && count_ == 1;
}

void PixelSampler::offsets(int x, int y, std::vector<SubSample>& out) const {
  if (s_.kind == SamplerKind::Sequence) {
    out.resize(size_t(count_ - first_));
    const uint64_t pixel = mix(s_.seed ^ mix((uint64_t(uint32_t(y)) << 32) | uint32_t(x)));
    const double shiftX = unitFloat(pixel), shiftY = unitFloat(mix(pixel));
    for (int k = first_; k < count_; ++k)
      out[size_t(k - first_)] = {fractionOf(shiftX + k * kR2StepX) - 0.5, fractionOf(shiftY + k * kR2StepY) - 0.5};
    return;
  }
  out = fixed_;
  if (s_.kind != SamplerKind::Jitter || count_ == 1) return;
  const uint64_t pixel = mix(s_.seed ^ mix((uint64_t(uint32_t(y)) << 32) | uint32_t(x)));
  for (int k = 0; k < count_; ++k) {
    const uint64_t h = mix(pixel + uint64_t(k));
    out[k].dx += (unitFloat(h) - 0.5) / cols_;
    out[k].dy += (unitFloat(mix(h)) - 0.5) / rows_;
  }
}

SamplerKind parseSamplerKind(const std::string& name) {
  if (name == "pov") return SamplerKind::Pov;
  if (name == "grid") return SamplerKind::Grid;
  if (name == "jitter") return SamplerKind::Jitter;
  if (name == "sequence") return SamplerKind::Sequence;
  throw Error(ExitCode::Usage, "unknown sampler \"" + name + "\" (use pov, grid, jitter or sequence)");
}

const char* samplerName(SamplerKind kind) {
  switch (kind) {
    case SamplerKind::Pov: return "pov";
    case SamplerKind::Grid: return "grid";
    case SamplerKind::Jitter: return "jitter";
    case SamplerKind::Sequence: return "sequence";
  }
  return "?";
}

}  // namespace pvrt
