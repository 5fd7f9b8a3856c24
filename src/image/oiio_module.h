// The OpenImageIO module: pvrt's only use of OpenImageIO, built as a separate shared
// object and loaded with dlopen the first time a format other than PNG is read or
// written, or images are compared. Linking OpenImageIO into the program would make
// every process, even `pvrt --help`, load about 260 libraries (0.35 s).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace pvrt {

struct OiioErrorStats {  // OpenImageIO's comparison statistics, in [0,1] units
  double meanError = 0, rmsError = 0, psnr = 0, maxError = 0;
  int maxX = 0, maxY = 0, maxChannel = 0;
};

// The module's entry points. Each returns an empty string on success, else what went wrong.
struct OiioModule {
  // Writes `channels` interleaved float (linear, tagged as such) or 8-bit (sRGB) values.
  std::string (*write)(const std::string& path, int width, int height, bool isFloat, const void* pixels);
  std::string (*read8)(const std::string& path, int& width, int& height, std::vector<uint8_t>& rgb);
  std::string (*compare8)(const uint8_t* a, const uint8_t* b, int width, int height, OiioErrorStats& out);
};

// Loads the module once (thread-safe). Throws pvrt::Error(`code`) when it cannot be found.
const OiioModule& oiioModule();

}  // namespace pvrt

// The symbol the module exports.
extern "C" const pvrt::OiioModule* pvrtOiioModule();
