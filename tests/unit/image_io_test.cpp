#include <gtest/gtest.h>

#include <bit>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <random>

#include "core/error.h"
#include "image/image_io.h"
#include "image/png_io.h"
#include "parallel/threads.h"

namespace pvrt {
namespace {

// POV-Ray 3.7 encodes in single precision (SRGBGammaCurve::Encode, IntEncode): these linear
// values lie within a hair of a level's edge, and POV-Ray 3.7.0.10 wrote the level given here
// for each (rendered as a background colour, 1x1, -A); the double-precision encoder pvrt had
// gives the level above or below for every one of them.
TEST(ImageIo, EncoderIsPovRaysSinglePrecisionOne) {
  const struct {
    float linear;
    int level;
  } povray[] = {{0.00197292538f, 7}, {0.00350925932f, 12}, {0.00384831498f, 12}, {0.00497683743f, 15},
                {0.00582465064f, 18}, {0.00627796911f, 19}, {0.00675122719f, 20}, {0.00724466797f, 21},
                {0.00775852986f, 22}, {0.00829304755f, 23}};
  for (const auto& p : povray) EXPECT_EQ(encodeSrgb8(double(p.linear)), p.level) << p.linear;
}

// The table-driven image encoder must give exactly what the per-value formula gives.
TEST(ImageIo, TableEncodingMatchesFormula) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> wide(-0.5f, 1.5f);
  Image img(1000, 100);
  auto& px = img.data();
  for (float& v : px) v = wide(rng);
  // Values at and around every level boundary, and the special ones.
  size_t i = 0;
  for (int level = 0; level < 256 && i + 8 < px.size(); ++level) {
    for (float probe = std::pow(level / 255.0f, 2.2f) * 0.999f; i < size_t(level + 1) * 8; ++i) {
      px[i] = probe;
      probe = std::nextafter(probe, 2.0f);
    }
  }
  // Exactly at every level's threshold and one float below it (found here by bisection
  // over the float bit patterns, independently of the encoder's own tables).
  for (int level = 1; level < 256; ++level) {
    uint32_t lo = 0, hi = 0x3f800000u;
    while (lo < hi) {
      const uint32_t mid = lo + (hi - lo) / 2;
      if (encodeSrgb8(double(std::bit_cast<float>(mid))) >= level) hi = mid; else lo = mid + 1;
    }
    px[i++] = std::bit_cast<float>(lo);
    px[i++] = std::bit_cast<float>(lo - 1);
  }
  px[i++] = std::numeric_limits<float>::quiet_NaN();
  px[i++] = std::numeric_limits<float>::infinity();
  px[i++] = -std::numeric_limits<float>::infinity();
  px[i++] = 0.0f;
  px[i++] = -0.0f;
  px[i++] = 1.0f;
  px[i++] = std::nextafter(1.0f, 0.0f);
  for (int threads : {1, 3}) {  // blocks of the image on each thread
    setThreadBudget(threads);
    const std::vector<uint8_t> out = encodeSrgb8(img);
    for (size_t k = 0; k < px.size(); ++k) ASSERT_EQ(out[k], encodeSrgb8(double(px[k]))) << "value " << px[k];
  }
  setThreadBudget(0);
}

std::string tempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("pvrt_image_io_" + name)).string();
}

TEST(ImageIo, PngRoundTripIsExact) {
  Image img(37, 11);
  for (size_t k = 0; k < img.data().size(); ++k) img.data()[k] = float(k % 97) / 96.0f;
  const std::string path = tempPath("round.png");
  writeImage(img, path);
  int w = 0, h = 0;
  EXPECT_TRUE(isPngFile(path));
  const std::vector<uint8_t> back = readImage8(path, w, h);
  EXPECT_EQ(w, 37);
  EXPECT_EQ(h, 11);
  EXPECT_EQ(back, encodeSrgb8(img));
  std::remove(path.c_str());
}

// TGA and EXR go through the OpenImageIO module, loaded on demand.
TEST(ImageIo, OtherFormatsThroughTheModule) {
  Image img(9, 5);
  for (size_t k = 0; k < img.data().size(); ++k) img.data()[k] = float(k) / float(img.data().size());
  for (const char* ext : {".tga", ".exr"}) {
    const std::string path = tempPath(std::string("module") + ext);
    writeImage(img, path);
    int w = 0, h = 0;
    EXPECT_FALSE(isPngFile(path));
    const std::vector<uint8_t> back = readImage8(path, w, h);
    EXPECT_EQ(w, 9);
    EXPECT_EQ(h, 5);
    EXPECT_EQ(back.size(), size_t(9 * 5 * 3));
    std::remove(path.c_str());
  }
}

TEST(ImageIo, UnreadableImageIsAnError) {
  const std::string path = tempPath("garbage.png");
  std::FILE* f = std::fopen(path.c_str(), "wb");
  std::fputs("\x89PNG\r\n\x1a\n but then nothing sensible", f);
  std::fclose(f);
  int w = 0, h = 0;
  EXPECT_THROW(readImage8(path, w, h), Error);
  std::remove(path.c_str());
}

}  // namespace
}  // namespace pvrt
