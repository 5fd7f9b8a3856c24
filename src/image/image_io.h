// Image output: PNG deflated on every thread (image/png_io.h), TGA and OpenEXR through the
// OpenImageIO module (image/oiio_module.h). 8-bit formats (PNG, TGA) get POV-Ray's pipeline:
// clip to [0,1], sRGB curve, round half up, on every thread. OpenEXR keeps linear float values.
// Files are written to a temporary name beside the target and renamed into place, so a
// failed or interrupted write never leaves a truncated file or spoils an existing one.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "image/image.h"

namespace pvrt {

// POV-Ray's 8-bit encoding of one linear value: floor(sRGB(clip(v)) * 255 + 0.5).
uint8_t encodeSrgb8(double linear);
// The whole image encoded as interleaved 8-bit RGB.
std::vector<uint8_t> encodeSrgb8(const Image& image);

// Writes by extension: .png, .tga, .exr. Throws pvrt::Error(ExitCode::OutputError).
void writeImage(const Image& image, const std::string& path);
// Reads PNG, or any format OpenImageIO knows, as 8-bit RGB (for comparisons against golden PNGs).
std::vector<uint8_t> readImage8(const std::string& path, int& width, int& height);

}  // namespace pvrt
