// Pixel comparison of two 8-bit images (decoded values, not file bytes), with the
// golden-image verdict used everywhere in pvrt's tests:
//   pass when no channel differs by more than 2 levels (of 255) and at most 0.01% of
//   the channels differ by more than 1 level (the golden tests ask more: golden.sh).
// A scene may loosen these only with a written reason next to its thresholds.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace pvrt {

struct CompareThresholds {
  int maxLevels = 2;                 // no channel may differ by more
  double maxFractionOver1 = 0.0001;  // share of channels allowed to differ by more than 1 level
  long maxOffBy1 = -1;               // channels allowed to differ by exactly 1 level; -1: any
};

struct CompareResult {
  int width = 0, height = 0;
  double meanError = 0;  // in levels, over all channels
  double rmsError = 0;
  double psnr = 0;       // dB, infinite when identical
  int maxError = 0;      // levels
  int maxX = 0, maxY = 0, maxChannel = 0;
  long channels = 0;
  long over0 = 0, over1 = 0, over2 = 0;  // channels differing by more than 0, 1, 2 levels
  bool sizeMismatch = false;
  int otherWidth = 0, otherHeight = 0;  // the second image's size, when sizeMismatch
  bool pass(const CompareThresholds& t = {}) const {
    return !sizeMismatch && maxError <= t.maxLevels && double(over1) <= t.maxFractionOver1 * double(channels) &&
           (t.maxOffBy1 < 0 || over0 - over1 <= t.maxOffBy1);
  }
};

// `pvrt compare`'s exit codes: the verdict it prints, and apart from it a usage error (2, as
// for every pvrt command) and an unreadable image (4). OpenImageIO's idiff gives 1 to images
// within tolerance; a script testing `$? -eq 0` then failed a PASS, so pvrt does not.
enum class CompareExit : int { Pass = 0, Failure = 1, FileError = 4 };

// Compares interleaved 8-bit RGB buffers of the same size (OpenImageIO's ImageBufAlgo::compare).
CompareResult compareImages8(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b, int width, int height);
// Reads both files; throws pvrt::Error(OutputError) when one cannot be read.
CompareResult compareFiles(const std::string& a, const std::string& b);
// |a - b| x `scale`, written as an 8-bit PNG to exactly `out` (a staged temporary,
// core/output_files.h).
void writeDifferenceImage(const std::string& a, const std::string& b, const std::string& out, int scale = 16);

}  // namespace pvrt
