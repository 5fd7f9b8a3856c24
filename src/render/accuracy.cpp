#include "render/accuracy.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "core/error.h"
#include "image/image_io.h"

namespace pvrt {

ImageError imageError8(const std::vector<uint8_t>& test, const std::vector<uint8_t>& reference) {
  if (test.size() != reference.size() || test.size() % 3 != 0)
    throw Error(ExitCode::Usage, "images of different sizes cannot be compared");
  ImageError e;
  if (test.empty()) return e;
  double sum2 = 0;
  long over1 = 0;
  for (size_t i = 0; i < test.size(); i += 3) {
    int worst = 0;
    for (size_t k = i; k < i + 3; ++k) {
      const int d = std::abs(int(test[k]) - int(reference[k]));
      sum2 += double(d) * d;
      worst = std::max(worst, d);
    }
    over1 += worst > 1 ? 1 : 0;
  }
  e.rmse = std::sqrt(sum2 / double(test.size()));
  e.psnr = e.rmse > 0 ? 20.0 * std::log10(255.0 / e.rmse) : std::numeric_limits<double>::infinity();
  e.shareOver1 = double(over1) / double(test.size() / 3);
  return e;
}

ImageError imageError(const Image& test, const Image& reference) {
  if (test.width() != reference.width() || test.height() != reference.height())
    throw Error(ExitCode::Usage, "images of different sizes cannot be compared");
  return imageError8(encodeSrgb8(test), encodeSrgb8(reference));
}

namespace {

void sortByTime(std::vector<CurvePoint>& c) {
  std::sort(c.begin(), c.end(), [](const CurvePoint& a, const CurvePoint& b) { return a.seconds < b.seconds; });
}
// log, with zero errors (an exact match) kept finite so that curves can still be read.
double safeLog(double v) { return std::log(std::max(v, 1e-12)); }

}  // namespace

std::optional<double> errorAtTime(std::vector<CurvePoint> curve, double seconds) {
  sortByTime(curve);
  if (curve.empty() || seconds < curve.front().seconds || seconds > curve.back().seconds) return std::nullopt;
  for (size_t i = 1; i < curve.size(); ++i) {
    const CurvePoint &a = curve[i - 1], &b = curve[i];
    if (seconds > b.seconds) continue;
    const double span = safeLog(b.seconds) - safeLog(a.seconds);
    const double t = span > 0 ? (safeLog(seconds) - safeLog(a.seconds)) / span : 1.0;
    return std::exp(safeLog(a.error) + t * (safeLog(b.error) - safeLog(a.error)));
  }
  return curve.front().error;  // a single point, at exactly its time
}

std::optional<double> timeAtError(std::vector<CurvePoint> curve, double error) {
  sortByTime(curve);
  // The first time the curve comes down to `error`, walking forward in time.
  for (size_t i = 0; i < curve.size(); ++i) {
    if (curve[i].error > error) continue;
    if (i == 0) return error == curve[0].error ? std::optional<double>(curve[0].seconds) : std::nullopt;
    const CurvePoint &a = curve[i - 1], &b = curve[i];
    const double span = safeLog(b.error) - safeLog(a.error);
    const double t = span != 0 ? (safeLog(error) - safeLog(a.error)) / span : 1.0;
    return std::exp(safeLog(a.seconds) + t * (safeLog(b.seconds) - safeLog(a.seconds)));
  }
  return std::nullopt;
}

double commonTime(const std::vector<std::vector<CurvePoint>>& curves) {
  double t = std::numeric_limits<double>::infinity();
  for (const auto& c : curves) {
    double end = 0;
    for (const CurvePoint& p : c) end = std::max(end, p.seconds);
    t = std::min(t, end);
  }
  return curves.empty() ? 0 : t;
}

double commonError(const std::vector<std::vector<CurvePoint>>& curves) {
  double e = 0;
  for (const auto& c : curves) {
    double best = std::numeric_limits<double>::infinity();
    for (const CurvePoint& p : c) best = std::min(best, p.error);
    e = std::max(e, best);
  }
  return e;
}

int nearestPerfectSquare(double c) {
  const double r = std::sqrt(std::max(c, 1.0));
  const int lo = int(std::floor(r)), hi = lo + 1;
  return c - double(lo) * lo < double(hi) * hi - c ? lo * lo : hi * hi;
}

}  // namespace pvrt
