#include "image/compare.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <cmath>
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
  // OIIO compares in [0,1]; thresholds are set half a level under 1, 2 and 3 levels so
  // that "more than k levels" is decided on exact integers.
  const OIIO::ImageBuf ia = wrap(a, width, height), ib = wrap(b, width, height);
  const auto c0 = OIIO::ImageBufAlgo::compare(ia, ib, 1.0f, 0.5f / 255.0f);
  const auto c1 = OIIO::ImageBufAlgo::compare(ia, ib, 1.0f, 1.5f / 255.0f);
  const auto c2 = OIIO::ImageBufAlgo::compare(ia, ib, 1.0f, 2.5f / 255.0f);
  r.meanError = c0.meanerror * 255.0;
  r.rmsError = c0.rms_error * 255.0;
  r.psnr = c0.nfail == 0 ? std::numeric_limits<double>::infinity() : c0.PSNR;
  r.maxError = int(std::lround(c0.maxerror * 255.0));
  r.maxX = c0.maxx;
  r.maxY = c0.maxy;
  r.maxChannel = c0.maxc;
  r.over0 = long(c0.nfail);
  r.over1 = long(c1.nfail);
  r.over2 = long(c2.nfail);
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
