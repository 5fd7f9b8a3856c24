// The OpenImageIO module (see image/oiio_module.h): every call pvrt makes into
// OpenImageIO, behind a small table of functions that pvrt looks up with dlopen.
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include "image/oiio_module.h"

namespace {

std::string orUnknown(std::string why) { return why.empty() ? "unknown error" : why; }

std::string write(const std::string& path, int width, int height, bool isFloat, const void* pixels) {
  OIIO::ImageSpec spec(width, height, 3, isFloat ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
  if (isFloat) {
    spec.attribute("oiio:ColorSpace", "Linear");
    spec.attribute("compression", "zip");
  } else {
    spec.attribute("oiio:ColorSpace", "sRGB");
  }
  spec.attribute("Software", "pvrt");
  auto out = OIIO::ImageOutput::create(path);
  if (!out) return orUnknown(OIIO::geterror());
  bool ok = out->open(path, spec) &&
            out->write_image(isFloat ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8, pixels);
  ok = out->close() && ok;
  return ok ? std::string() : orUnknown(out->geterror());
}

std::string read8(const std::string& path, int& width, int& height, std::vector<uint8_t>& rgb) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) return orUnknown(OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  width = spec.width;
  height = spec.height;
  const int n = spec.nchannels;
  std::vector<uint8_t> all(size_t(width) * size_t(height) * size_t(n));
  if (!in->read_image(0, 0, 0, n, OIIO::TypeDesc::UINT8, all.data())) return orUnknown(in->geterror());
  in->close();
  // Keep RGB; a grey image is expanded, alpha dropped.
  rgb.resize(size_t(width) * size_t(height) * 3);
  for (size_t i = 0; i < size_t(width) * size_t(height); ++i)
    for (int c = 0; c < 3; ++c) rgb[i * 3 + size_t(c)] = all[i * size_t(n) + size_t(n >= 3 ? c : 0)];
  return {};
}

OIIO::ImageBuf wrap(const uint8_t* px, int width, int height) {
  OIIO::ImageBuf buf(OIIO::ImageSpec(width, height, 3, OIIO::TypeDesc::UINT8));
  buf.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::UINT8, px);
  return buf;
}

std::string compare8(const uint8_t* a, const uint8_t* b, int width, int height, pvrt::OiioErrorStats& out) {
  const auto c = OIIO::ImageBufAlgo::compare(wrap(a, width, height), wrap(b, width, height), 0.5f / 255.0f,
                                             0.5f / 255.0f);
  // (c.error is also set when values differ beyond the fail threshold: not an error here.)
  out = {c.meanerror, c.rms_error, c.PSNR, c.maxerror, c.maxx, c.maxy, c.maxc};
  return {};
}

const pvrt::OiioModule kModule{write, read8, compare8};

}  // namespace

extern "C" __attribute__((visibility("default"))) const pvrt::OiioModule* pvrtOiioModule() { return &kModule; }
