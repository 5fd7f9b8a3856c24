// 8-bit RGB PNG files: written by hand around zlib so that every thread deflates
// (png_write.cpp), read through libpng (png_io.cpp). PNG is what nearly every render
// writes, so it must not pay for loading OpenImageIO and its ~260 shared libraries (about
// 0.35 s per process); every other format goes through the OpenImageIO module.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace pvrt {

// Writes interleaved 8-bit RGB to `path` (not atomically: callers pass a temporary name),
// deflating bands of rows on up to `threads` threads (0: threadBudget()); the file's bytes
// do not depend on the threads. Returns an empty string on success, else what went wrong.
std::string writePng8(const std::string& path, int width, int height, const uint8_t* rgb, int threads = 0);
// Reads a PNG of any bit depth and colour type as 8-bit RGB (grey expanded, alpha dropped).
// Returns an empty string on success, else what went wrong.
std::string readPng8(const std::string& path, int& width, int& height, std::vector<uint8_t>& rgb);
// Does the file start with the PNG signature?
bool isPngFile(const std::string& path);

}  // namespace pvrt
