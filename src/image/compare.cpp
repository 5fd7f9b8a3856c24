#include "image/compare.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

#include "core/error.h"
#include "image/image_io.h"
#include "image/oiio_module.h"
#include "image/png_io.h"

namespace pvrt {

CompareResult compareImages8(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b, int width, int height) {
  CompareResult r;
  r.width = width;
  r.height = height;
  r.channels = long(width) * height * 3;
  // OpenImageIO gives the error statistics; the per-channel counts that the verdict rests
  // on are taken on the exact 8-bit integers (OIIO counts pixels, not channels).
  OiioErrorStats c;
  const std::string why = oiioModule().compare8(a.data(), b.data(), width, height, c);
  if (!why.empty()) throw Error(ExitCode::OutputError, "cannot compare images: " + why);
  r.meanError = c.meanError * 255.0;
  r.rmsError = c.rmsError * 255.0;
  r.maxError = int(std::lround(c.maxError * 255.0));
  r.psnr = r.maxError == 0 ? std::numeric_limits<double>::infinity() : c.psnr;
  r.maxX = c.maxX;
  r.maxY = c.maxY;
  r.maxChannel = c.maxChannel;
  for (size_t i = 0; i < a.size(); ++i) {
    const int d = std::abs(int(a[i]) - int(b[i]));
    r.over0 += d > 0;
    r.over1 += d > 1;
    r.over2 += d > 2;
  }
  return r;
}

CompareResult compareFiles(const std::string& a, const std::string& b) {
  int wa = 0, ha = 0, wb = 0, hb = 0;
  const std::vector<uint8_t> pa = readImage8(a, wa, ha), pb = readImage8(b, wb, hb);
  if (wa != wb || ha != hb) {
    CompareResult r;
    r.sizeMismatch = true;
    r.width = wa;
    r.height = ha;
    r.otherWidth = wb;
    r.otherHeight = hb;
    return r;
  }
  return compareImages8(pa, pb, wa, ha);
}

void writeDifferenceImage(const std::string& a, const std::string& b, const std::string& out, int scale) {
  int wa = 0, ha = 0, wb = 0, hb = 0;
  const std::vector<uint8_t> pa = readImage8(a, wa, ha), pb = readImage8(b, wb, hb);
  if (wa != wb || ha != hb) throw Error(ExitCode::OutputError, "cannot diff images of different sizes");
  std::vector<uint8_t> diff(pa.size());
  for (size_t i = 0; i < pa.size(); ++i) diff[i] = uint8_t(std::min(255, std::abs(int(pa[i]) - int(pb[i])) * scale));
  const std::string why = writePng8(out, wa, ha, diff.data());
  if (!why.empty()) throw Error(ExitCode::OutputError, "cannot write the difference image: " + why);
}

}  // namespace pvrt
