#include "image/compare.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <cmath>
#include <cstdlib>
#include <limits>

#include "core/atomic_file.h"
#include "core/error.h"
#include "image/image_io.h"

namespace pvrt {

namespace {

OIIO::ImageBuf wrap(const std::vector<uint8_t>& px, int width, int height) {
  OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
  OIIO::ImageBuf buf(spec);
  buf.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::UINT8, px.data());
  return buf;
}

}  // namespace

CompareResult compareImages8(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b, int width, int height) {
  CompareResult r;
  r.width = width;
  r.height = height;
  r.channels = long(width) * height * 3;
  // OpenImageIO gives the error statistics; the per-channel counts that the verdict rests
  // on are taken on the exact 8-bit integers (OIIO counts pixels, not channels).
  const OIIO::ImageBuf ia = wrap(a, width, height), ib = wrap(b, width, height);
  const auto c = OIIO::ImageBufAlgo::compare(ia, ib, 0.5f / 255.0f, 0.5f / 255.0f);
  r.meanError = c.meanerror * 255.0;
  r.rmsError = c.rms_error * 255.0;
  r.maxError = int(std::lround(c.maxerror * 255.0));
  r.psnr = r.maxError == 0 ? std::numeric_limits<double>::infinity() : c.PSNR;
  r.maxX = c.maxx;
  r.maxY = c.maxy;
  r.maxChannel = c.maxc;
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
    return r;
  }
  return compareImages8(pa, pb, wa, ha);
}

void writeDifferenceImage(const std::string& a, const std::string& b, const std::string& out, int scale) {
  int wa = 0, ha = 0, wb = 0, hb = 0;
  const std::vector<uint8_t> pa = readImage8(a, wa, ha), pb = readImage8(b, wb, hb);
  if (wa != wb || ha != hb) throw Error(ExitCode::OutputError, "cannot diff images of different sizes");
  const OIIO::ImageBuf diff = OIIO::ImageBufAlgo::absdiff(wrap(pa, wa, ha), wrap(pb, wb, hb));
  const OIIO::ImageBuf scaled = OIIO::ImageBufAlgo::mul(diff, float(scale));
  const std::string tmp = temporarySibling(out);
  if (!scaled.write(tmp, OIIO::TypeDesc::UINT8)) {
    std::remove(tmp.c_str());
    throw Error(ExitCode::OutputError, "cannot write \"" + out + "\": " + scaled.geterror());
  }
  if (std::rename(tmp.c_str(), out.c_str()) != 0) {
    std::remove(tmp.c_str());
    throw Error(ExitCode::OutputError, "cannot write \"" + out + "\"");
  }
}

}  // namespace pvrt
