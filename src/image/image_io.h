// Image output: PNG deflated on every thread (image/png_io.h), TGA and OpenEXR through the
// OpenImageIO module (image/oiio_module.h). 8-bit formats (PNG, TGA) get POV-Ray's pipeline:
// clip to [0,1], sRGB curve, round half up, on every thread. OpenEXR keeps linear float values.
// Files are written to a temporary name beside the target and renamed into place
// (core/output_files.h), so a failed or interrupted write never leaves a truncated file or
// spoils an existing one.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "image/image.h"

namespace pvrt {

// POV-Ray's 8-bit encoding of one linear value: floor(sRGB(clip(v)) * 255 + 0.5).
uint8_t encodeSrgb8(double linear);
// The whole image encoded as interleaved 8-bit RGB (on every thread).
std::vector<uint8_t> encodeSrgb8(const Image& image);
// `count` linear values encoded one by one, as encodeSrgb8(double) does, into out[0, count)
// (on the calling thread: for a part of an image, e.g. an MPI rank's share).
void encodeSrgb8(const float* linear, size_t count, uint8_t* out);

// The format `path` is written in, as its extension: .png, .tga or .exr by its name; .png for
// standard output ("-"), a device or a FIFO whose name has no extension. Throws
// pvrt::Error(ExitCode::Usage) for any other.
std::string imageFormatOf(const std::string& path);
// Writes `image` to exactly `path` (a staged temporary, core/output_files.h) in the format
// `extension` (as imageFormatOf gives it). Throws pvrt::Error(OutputError) naming `name`, the
// output as the user gave it.
void writeImageFile(const Image& image, const std::string& path, const std::string& extension,
                    const std::string& name);
// Whether `extension` (as imageFormatOf gives it) is written as 8-bit sRGB (.png, .tga), so
// that an image already encoded can be written by writeImageFile8.
bool isEightBitFormat(const std::string& extension);
// An image already encoded as interleaved 8-bit RGB (encodeSrgb8), written as writeImageFile
// would write the float image it came from: the same bytes.
void writeImageFile8(const std::vector<uint8_t>& rgb, int width, int height, const std::string& path,
                     const std::string& extension, const std::string& name);
// The whole write of one image on its own: checked, staged, committed.
void writeImage(const Image& image, const std::string& path);
// Reads PNG, or any format OpenImageIO knows, as 8-bit RGB (for comparisons against golden PNGs).
// Only regular files are read (a device or a FIFO is refused: it may never end).
std::vector<uint8_t> readImage8(const std::string& path, int& width, int& height);

}  // namespace pvrt
