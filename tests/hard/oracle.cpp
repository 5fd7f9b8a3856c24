#include "oracle.h"

#include <algorithm>
#include <cstring>

namespace pvrt::hard {

namespace {

// Distance in pixels from pixel (x, y) to the boundary of decision k: |value| over the
// largest change of the value to a neighbouring pixel (infinite when nothing changes).
double pixelsToBoundary(const ExpectedImage& e, int x, int y, int k) {
  const double v = e.at(x, y).margin[size_t(k)];
  if (std::isnan(v)) return INFINITY;
  double step = 0;
  const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
  for (int i = 0; i < 4; ++i) {
    const int nx = x + dx[i], ny = y + dy[i];
    if (nx < 0 || ny < 0 || nx >= e.width || ny >= e.height) continue;
    const double n = e.at(nx, ny).margin[size_t(k)];
    if (!std::isnan(n)) step = std::max(step, std::fabs(n - v));
  }
  // A sign change next door puts the boundary within one pixel even where the value
  // jumps (e.g. from "in front" to "behind").
  return step > 0 ? std::fabs(v) / step : INFINITY;
}

}  // namespace

Figures evaluate(const ExpectedImage& want, const Image& got, double absTol, double relTol) {
  Figures f;
  for (int y = 0; y < want.height; ++y) {
    for (int x = 0; x < want.width; ++x) {
      ++f.pixels;
      const float* g = got.row(y) + size_t(x) * 3;
      if (!std::isfinite(g[0]) || !std::isfinite(g[1]) || !std::isfinite(g[2])) {
        ++f.nonFinite;
        continue;
      }
      const Expected& e = want.at(x, y);
      if (e.skip) {
        ++f.skipped;
        continue;
      }
      ++f.compared;
      double nearest = INFINITY;
      for (int k = 0; k < int(e.margin.size()); ++k) nearest = std::min(nearest, pixelsToBoundary(want, x, y, k));
      f.closestPixels = std::min(f.closestPixels, nearest);
      const double w[3] = {e.c.r, e.c.g, e.c.b};
      double err = 0;
      bool differs = false;
      for (int c = 0; c < 3; ++c) {
        const double d = std::fabs(double(g[c]) - w[c]);
        err = std::max(err, d);
        if (d > absTol + relTol * std::fabs(w[c])) differs = true;
      }
      if (e.litTerm > 1e-3) {
        ++f.lit;
        const double mean = (g[0] + g[1] + g[2]) / 3.0, wantMean = (w[0] + w[1] + w[2]) / 3.0;
        if (mean < wantMean - 0.5 * e.litTerm) ++f.acne;
      }
      if (!differs) {
        f.maxAbsError = std::max(f.maxAbsError, err);
        continue;
      }
      ++f.mismatched;
      if (nearest <= 1.0) {
        ++f.edge;
        f.maxEdgePixels = std::max(f.maxEdgePixels, nearest);
      } else {
        ++f.errors;
      }
    }
  }
  return f;
}

long countNonFinite(const Image& image) {
  long n = 0;
  for (size_t i = 0; i < image.data().size(); i += 3) {
    const float* p = image.data().data() + i;
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) ++n;
  }
  return n;
}

long countDifferent(const Image& a, const Image& b) {
  if (a.width() != b.width() || a.height() != b.height()) return long(a.data().size() / 3);
  long n = 0;
  for (size_t i = 0; i < a.data().size(); i += 3)
    if (std::memcmp(a.data().data() + i, b.data().data() + i, 3 * sizeof(float)) != 0) ++n;
  return n;
}

double maxAbsDifference(const Image& a, const Image& b) {
  double m = 0;
  for (size_t i = 0; i < a.data().size(); ++i)
    m = std::max(m, std::fabs(double(a.data()[i]) - double(b.data()[i])));
  return m;
}

}  // namespace pvrt::hard
