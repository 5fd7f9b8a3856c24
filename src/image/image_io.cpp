#include "image/image_io.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "core/atomic_file.h"
#include "core/error.h"

namespace pvrt {

namespace {

std::string extensionOf(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

Error outputError(const std::string& path, const std::string& what) {
  return Error(ExitCode::OutputError, "cannot write \"" + path + "\": " + what);
}

}  // namespace

uint8_t encodeSrgb8(double linear) {
  const double v = std::clamp(std::isnan(linear) ? 0.0 : linear, 0.0, 1.0);
  const double s = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
  return uint8_t(std::floor(std::clamp(s, 0.0, 1.0) * 255.0 + 0.5));
}

std::vector<uint8_t> encodeSrgb8(const Image& image) {
  const std::vector<float>& src = image.data();
  std::vector<uint8_t> out(src.size());
  for (size_t i = 0; i < src.size(); ++i) out[i] = encodeSrgb8(double(src[i]));
  return out;
}

void writeImage(const Image& image, const std::string& path) {
  const std::string ext = extensionOf(path);
  if (ext != ".png" && ext != ".tga" && ext != ".exr")
    throw Error(ExitCode::Usage, "cannot write \"" + path + "\": unsupported image format (use .png, .tga or .exr)");
  const std::filesystem::path dir = std::filesystem::path(path).parent_path();
  std::error_code ec;
  if (!dir.empty() && !std::filesystem::is_directory(dir, ec))
    throw outputError(path, "no such directory \"" + dir.string() + "\"");

  const bool linear = ext == ".exr";
  OIIO::ImageSpec spec(image.width(), image.height(), 3, linear ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
  if (linear) {
    spec.attribute("oiio:ColorSpace", "Linear");
    spec.attribute("compression", "zip");
  } else {
    spec.attribute("oiio:ColorSpace", "sRGB");
  }
  spec.attribute("Software", "pvrt");

  // Write to a temporary sibling and rename it into place when complete.
  const std::string tmp = temporarySibling(path);
  auto out = OIIO::ImageOutput::create(tmp);
  bool ok = out && out->open(tmp, spec);
  if (ok) {
    if (linear) {
      ok = out->write_image(OIIO::TypeDesc::FLOAT, image.data().data());
    } else {
      const std::vector<uint8_t> px = encodeSrgb8(image);
      ok = out->write_image(OIIO::TypeDesc::UINT8, px.data());
    }
    ok = out->close() && ok;
  }
  if (!ok) {
    const std::string why = out ? out->geterror() : OIIO::geterror();
    std::remove(tmp.c_str());
    throw outputError(path, why.empty() ? "write failed" : why);
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    std::remove(tmp.c_str());
    throw outputError(path, why);
  }
}

std::vector<uint8_t> readImage8(const std::string& path, int& width, int& height) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) {
    const std::string why = OIIO::geterror();
    throw Error(ExitCode::SceneError, "cannot read image \"" + path + "\": " + (why.empty() ? "unknown error" : why));
  }
  const OIIO::ImageSpec& spec = in->spec();
  width = spec.width;
  height = spec.height;
  std::vector<uint8_t> all(size_t(width) * height * size_t(spec.nchannels));
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT8, all.data()))
    throw Error(ExitCode::SceneError, "cannot read image \"" + path + "\": " + in->geterror());
  in->close();
  // Keep RGB; a grey image is expanded, alpha dropped.
  std::vector<uint8_t> rgb(size_t(width) * height * 3);
  const int n = spec.nchannels;
  for (size_t i = 0; i < size_t(width) * height; ++i)
    for (int c = 0; c < 3; ++c) rgb[i * 3 + size_t(c)] = all[i * size_t(n) + size_t(n >= 3 ? c : 0)];
  return rgb;
}

}  // namespace pvrt
