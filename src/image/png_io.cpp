#include "image/png_io.h"

#include <png.h>

#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <memory>

namespace pvrt {

namespace {

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

// libpng reports errors through a callback that must not return; it longjmps back to
// the setjmp in the caller, with the message kept here.
struct ErrorSink {
  std::string message;
};
void onError(png_structp png, png_const_charp msg) {
  static_cast<ErrorSink*>(png_get_error_ptr(png))->message = msg;
  png_longjmp(png, 1);
}
void onWarning(png_structp, png_const_charp) {}

}  // namespace

bool isPngFile(const std::string& path) {
  File f(std::fopen(path.c_str(), "rb"));
  png_byte sig[8];
  return f && std::fread(sig, 1, 8, f.get()) == 8 && png_sig_cmp(sig, 0, 8) == 0;
}

std::string readPng8(const std::string& path, int& width, int& height, std::vector<uint8_t>& rgb) {
  File f(std::fopen(path.c_str(), "rb"));
  if (!f) return std::strerror(errno);
  ErrorSink sink;
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &sink, onError, onWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info) {
    png_destroy_read_struct(&png, nullptr, nullptr);
    return "out of memory";
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    return sink.message.empty() ? "not a readable PNG" : sink.message;
  }
  png_init_io(png, f.get());
  png_read_info(png, info);
  // Normalise every variant to 8-bit RGB: palettes expanded, 16-bit reduced, grey
  // turned to RGB, alpha removed.
  png_set_expand(png);
  png_set_strip_16(png);
  png_set_strip_alpha(png);
  png_set_gray_to_rgb(png);
  png_read_update_info(png, info);
  width = int(png_get_image_width(png, info));
  height = int(png_get_image_height(png, info));
  if (png_get_rowbytes(png, info) != size_t(width) * 3) png_error(png, "unexpected pixel layout");
  rgb.resize(size_t(width) * size_t(height) * 3);
  for (int y = 0; y < height; ++y) png_read_row(png, rgb.data() + size_t(y) * size_t(width) * 3, nullptr);
  png_read_end(png, nullptr);
  png_destroy_read_struct(&png, &info, nullptr);
  return {};
}

}  // namespace pvrt
