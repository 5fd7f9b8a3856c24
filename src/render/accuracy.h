// How close a render is to a converged one (`pvrt accuracy`): the error of an image
// against a reference in the 8-bit sRGB levels a PNG holds (POV-Ray's output pipeline),
// and readings of error-versus-time curves at equal time and at equal error.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "image/image.h"
#include "render/renderer.h"

namespace pvrt {

struct ImageError {
  double rmse = 0;        // root mean square over all channels, in levels of 255
  double psnr = 0;        // 20 log10(255 / rmse) dB; infinite when identical
  double shareOver1 = 0;  // share of pixels with some channel more than 1 level off
};

// Interleaved 8-bit RGB buffers of the same size.
ImageError imageError8(const std::vector<uint8_t>& test, const std::vector<uint8_t>& reference);
// Both images encoded the way a PNG is written, then compared.
ImageError imageError(const Image& test, const Image& reference);

// One point of an error-versus-time curve.
struct CurvePoint {
  double seconds;
  double error;
};

// The error a curve reaches at `seconds` and the time it needs to reach `error`, by
// linear interpolation in log-log space between its points (taken in order of time);
// nullopt outside the curve's range.
std::optional<double> errorAtTime(std::vector<CurvePoint> curve, double seconds);
std::optional<double> timeAtError(std::vector<CurvePoint> curve, double error);

// The readings that compare several curves: the latest time every curve has reached
// (its shortest curve's end), and the smallest error every curve reaches.
double commonTime(const std::vector<std::vector<CurvePoint>>& curves);
double commonError(const std::vector<std::vector<CurvePoint>>& curves);

// The perfect square nearest to c (ties go up); at least 1.
int nearestPerfectSquare(double c);

}  // namespace pvrt
