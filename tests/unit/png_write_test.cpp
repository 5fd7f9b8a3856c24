// The PNG writer deflates bands of rows on several threads and joins them (png_write.cpp).
// Whatever the size and the threads, the file must be valid PNG chunk by chunk, its zlib
// stream one whole stream, its pixels the input's, and its bytes the same for any threads.
#include <gtest/gtest.h>
#include <zlib.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "core/error.h"
#include "image/image_io.h"
#include "image/png_io.h"
#include "parallel/threads.h"

namespace pvrt {
namespace {

std::string tempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("pvrt_png_write_" + name)).string();
}

std::string fileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

uint32_t bigEndian(const std::string& s, size_t at) {
  const auto* p = reinterpret_cast<const uint8_t*>(s.data() + at);
  return uint32_t(p[0]) << 24 | uint32_t(p[1]) << 16 | uint32_t(p[2]) << 8 | p[3];
}

// A render-like picture: smooth gradients, flat areas and noisy ones.
std::vector<uint8_t> picture(int width, int height, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<uint8_t> rgb(size_t(width) * size_t(height) * 3);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      uint8_t* p = rgb.data() + (size_t(y) * size_t(width) + size_t(x)) * 3;
      const bool noisy = (x / 64 + y / 48) % 3 == 0, flat = (x / 64 + y / 48) % 3 == 1;
      for (int c = 0; c < 3; ++c)
        p[c] = flat ? uint8_t(40 * c) : uint8_t((x * (c + 1) + y * (3 - c)) / 5 + (noisy ? rng() % 24 : 0));
    }
  return rgb;
}

// Checks every chunk (order, lengths, CRC-32, the header's fields) and inflates the IDATs
// as one zlib stream that must end exactly with the data; returns the inflated bytes.
std::string checkedImageData(const std::string& png, int width, int height) {
  static const char signature[] = "\x89PNG\r\n\x1a\n";
  EXPECT_EQ(png.compare(0, 8, signature, 8), 0) << "signature";
  std::vector<std::string> types;
  std::string idat;
  size_t at = 8;
  while (at + 12 <= png.size()) {
    const uint32_t length = bigEndian(png, at);
    if (at + 12 + length > png.size()) break;
    const std::string type = png.substr(at + 4, 4);
    const uint32_t crc = uint32_t(crc32(0, reinterpret_cast<const Bytef*>(png.data() + at + 4), length + 4));
    EXPECT_EQ(bigEndian(png, at + 8 + length), crc) << type << " chunk at " << at << ": CRC";
    if (type == "IHDR") {
      EXPECT_EQ(length, 13u);
      EXPECT_EQ(bigEndian(png, at + 8), uint32_t(width));
      EXPECT_EQ(bigEndian(png, at + 12), uint32_t(height));
      EXPECT_EQ(png.substr(at + 16, 5), std::string("\x08\x02\x00\x00\x00", 5)) << "8-bit RGB, no interlace";
    }
    if (type == "IDAT") idat += png.substr(at + 8, length);
    if (types.empty() || types.back() != type) types.push_back(type);
    at += 12 + length;
  }
  EXPECT_EQ(at, png.size()) << "bytes after the last whole chunk";
  EXPECT_EQ(types, (std::vector<std::string>{"IHDR", "gAMA", "sRGB", "cHRM", "tEXt", "IDAT", "IEND"}));

  std::string raw(size_t(height) * (size_t(width) * 3 + 1) + 1, '\0');  // one spare byte: no more data
  z_stream z{};
  inflateInit(&z);
  z.next_in = reinterpret_cast<Bytef*>(idat.data());
  z.avail_in = uInt(idat.size());
  z.next_out = reinterpret_cast<Bytef*>(raw.data());
  z.avail_out = uInt(raw.size());
  EXPECT_EQ(inflate(&z, Z_FINISH), Z_STREAM_END) << "one whole zlib stream, Adler-32 included";
  EXPECT_EQ(z.avail_in, 0u) << "data after the zlib stream";
  EXPECT_EQ(z.total_out, raw.size() - 1) << "a filter byte and the row for every row";
  inflateEnd(&z);
  raw.pop_back();
  return raw;
}

struct Size {
  int width, height;
};

// 1x1; odd widths; heights that leave a short last band; one wide row longer than a band
// (bands of one row, each primed from the row before); a column whose dictionary spans
// many rows; and a render's size.
const Size kSizes[] = {{1, 1}, {2, 1}, {1, 3}, {7, 5}, {33, 1000}, {1281, 803},
                       {50001, 2}, {1, 70001}, {1280, 800}};

TEST(PngWrite, EveryThreadCountWritesTheSameValidFileOfTheInput) {
  for (const Size& s : kSizes) {
    const std::vector<uint8_t> rgb = picture(s.width, s.height, unsigned(s.width + s.height));
    std::string first;
    for (int threads : {1, 2, 3, 8}) {
      SCOPED_TRACE(std::to_string(s.width) + "x" + std::to_string(s.height) + ", " + std::to_string(threads) +
                   " threads");
      const std::string path = tempPath("sizes.png");
      ASSERT_EQ(writePng8(path, s.width, s.height, rgb.data(), threads), "");
      const std::string png = fileBytes(path);
      const std::string raw = checkedImageData(png, s.width, s.height);
      for (size_t y = 0; y < raw.size() / (size_t(s.width) * 3 + 1); ++y)
        ASSERT_EQ(raw[y * (size_t(s.width) * 3 + 1)], 1) << "row " << y << " filtered by Sub";
      int w = 0, h = 0;
      std::vector<uint8_t> back;
      ASSERT_EQ(readPng8(path, w, h, back), "");
      EXPECT_EQ(w, s.width);
      EXPECT_EQ(h, s.height);
      EXPECT_TRUE(back == rgb) << "decoded pixels differ from the input";
      if (first.empty()) first = png;
      EXPECT_TRUE(png == first) << "the file's bytes depend on the threads";
      std::remove(path.c_str());
    }
  }
}

// Through writeImage, with the threads of every stage set the way --threads sets them.
TEST(PngWrite, WriteImageUsesTheThreadBudget) {
  Image img(1280, 800);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-0.1f, 1.2f);
  for (float& v : img.data()) v = u(rng);
  std::string first;
  for (int threads : {1, 2, 3, 8}) {
    setThreadBudget(threads);
    const std::string path = tempPath("budget.png");
    writeImage(img, path);
    int w = 0, h = 0;
    EXPECT_TRUE(readImage8(path, w, h) == encodeSrgb8(img)) << threads << " threads";
    const std::string png = fileBytes(path);
    if (first.empty()) first = png;
    EXPECT_TRUE(png == first) << threads << " threads";
    std::remove(path.c_str());
  }
  setThreadBudget(0);
}

// Each band's deflate starts from the 32 KiB of rows before it, so the bands compress about
// as well as one stream. Here noise that repeats every 8 rows (30 KiB) is all matches from
// the 9th row on, which a band finds only in its dictionary: one stream of the filtered rows
// takes 57 KB; unprimed bands would take 13 times that, primed ones take 1% more.
TEST(PngWrite, BandsCompressAboutAsWellAsOneStream) {
  const int width = 1280, height = 800;
  const size_t rowBytes = size_t(width) * 3;
  std::vector<uint8_t> rgb(rowBytes * height);
  std::mt19937 rng(11);
  for (size_t i = 0; i < 8 * rowBytes; ++i) rgb[i] = uint8_t(rng());
  for (size_t i = 8 * rowBytes; i < rgb.size(); ++i) rgb[i] = rgb[i - 8 * rowBytes];
  const std::string path = tempPath("size.png");
  ASSERT_EQ(writePng8(path, width, height, rgb.data(), 8), "");
  const std::string png = fileBytes(path);
  const std::string raw = checkedImageData(png, width, height);
  uLongf serial = compressBound(uLong(raw.size()));
  std::vector<Bytef> out(serial);
  ASSERT_EQ(compress2(out.data(), &serial, reinterpret_cast<const Bytef*>(raw.data()), uLong(raw.size()), 3), Z_OK);
  EXPECT_LT(double(png.size()), 1.05 * double(serial)) << "one zlib stream: " << serial << " bytes";
  std::remove(path.c_str());
}

TEST(PngWrite, FailuresAreReported) {
  const uint8_t rgb[3] = {1, 2, 3};
  EXPECT_NE(writePng8(tempPath("no/such/dir.png"), 1, 1, rgb), "");
  if (std::filesystem::exists("/dev/full")) {
    EXPECT_EQ(writePng8("/dev/full", 1, 1, rgb), std::strerror(ENOSPC));
  }
  EXPECT_NE(writePng8(tempPath("empty.png"), 0, 1, rgb), "");
}

}  // namespace
}  // namespace pvrt
