#include "image/load_map_picture.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

namespace pvrt {

namespace {

// Glyphs of 3 x 5 pixels, a row a string, for the characters compactCount() writes.
struct Glyph {
  char c;
  const char* rows[5];
};
constexpr Glyph kFont[] = {
    {'0', {"###", "#.#", "#.#", "#.#", "###"}}, {'1', {".#.", "##.", ".#.", ".#.", "###"}},
    {'2', {"###", "..#", "###", "#..", "###"}}, {'3', {"###", "..#", "###", "..#", "###"}},
    {'4', {"#.#", "#.#", "###", "..#", "..#"}}, {'5', {"###", "#..", "###", "..#", "###"}},
    {'6', {"###", "#..", "###", "#.#", "###"}}, {'7', {"###", "..#", "..#", "..#", "..#"}},
    {'8', {"###", "#.#", "###", "#.#", "###"}}, {'9', {"###", "#.#", "###", "..#", "###"}},
    {'.', {"...", "...", "...", "...", ".#."}}, {'k', {"#..", "#.#", "##.", "#.#", "#.#"}},
    {'M', {"#.#", "###", "###", "#.#", "#.#"}}, {'G', {"###", "#..", "#.#", "#.#", "###"}},
};

const Glyph* glyph(char c) {
  for (const Glyph& g : kFont)
    if (g.c == c) return &g;
  return nullptr;
}

int scaleFor(int width) { return width >= 320 ? 2 : 1; }
// A label's width in pixels: 3 a glyph and 1 between them, at scale s.
int textWidth(const std::string& text, int s) { return text.empty() ? 0 : s * (4 * int(text.size()) - 1); }

void drawText(Image& image, const std::string& text, int x0, int y0, int s, const Color& ink) {
  for (size_t k = 0; k < text.size(); ++k) {
    const Glyph* g = glyph(text[k]);
    if (!g) continue;
    for (int r = 0; r < 5; ++r)
      for (int c = 0; c < 3; ++c)
        if (g->rows[r][c] == '#')
          for (int dy = 0; dy < s; ++dy)
            for (int dx = 0; dx < s; ++dx) {
              const int x = x0 + s * (4 * int(k) + c) + dx, y = y0 + s * r + dy;
              if (x >= 0 && x < image.width() && y >= 0 && y < image.height()) image.set(x, y, ink);
            }
  }
}

}  // namespace

Color loadMapColour(double v, double lo, double hi) {
  static const Color ramp[] = {{0.0, 0.0, 0.05}, {0.1, 0.0, 0.4}, {0.6, 0.05, 0.3}, {0.95, 0.4, 0.0}, {1.0, 1.0, 0.6}};
  const double logLo = std::log1p(lo), logSpan = std::log1p(hi) - logLo;
  const double t = logSpan > 0 ? std::clamp((std::log1p(v) - logLo) / logSpan, 0.0, 1.0) * 4.0 : 0.0;
  const int i = std::min(3, int(t));
  const double f = t - i;
  return ramp[i] * (1 - f) + ramp[i + 1] * f;
}

std::string compactCount(double v) {
  static const struct {
    double unit;
    const char* suffix;
  } units[] = {{1e9, "G"}, {1e6, "M"}, {1e3, "k"}};
  for (const auto& u : units) {
    if (v < u.unit * 0.9995) continue;
    const double x = v / u.unit;
    // One decimal below 10 (1.2k), none above (12k, 340k); 999.5k and up is 1.0M.
    if (x < 9.95) return fmt::format("{:.1f}{}", x, u.suffix);
    if (x < 999.5) return fmt::format("{:.0f}{}", x, u.suffix);
  }
  return fmt::format("{:.0f}", v);
}

int colourBarRows(int width) { return 19 * scaleFor(width); }

Image loadMapPicture(const std::vector<float>& load, int width, int height) {
  const int s = scaleFor(width);
  Image picture(width, height + colourBarRows(width));
  double lo = 0, hi = 0;
  if (!load.empty()) {
    const auto [mn, mx] = std::minmax_element(load.begin(), load.end());
    lo = *mn;
    hi = *mx;
  }
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      picture.set(x, y, loadMapColour(load[size_t(y) * size_t(width) + size_t(x)], lo, hi));

  // The strip: white, the bar (6 s rows) with a margin, ticks (2 s) under it, labels (5 s).
  const Color paper(1, 1, 1), ink(0, 0, 0);
  for (int y = height; y < picture.height(); ++y)
    for (int x = 0; x < width; ++x) picture.set(x, y, paper);
  const int barTop = height + 3 * s, barBottom = barTop + 6 * s, textTop = barBottom + 3 * s;
  const int left = std::min(2 * s, width / 4), right = width - 1 - left;  // bar columns, both included
  if (right < left) return picture;
  const double logLo = std::log1p(lo), logSpan = std::log1p(hi) - logLo;
  auto valueAt = [&](int x) {  // the work whose colour column x shows
    const double t = right > left ? double(x - left) / double(right - left) : 0.0;
    return std::expm1(logLo + t * logSpan);
  };
  auto columnOf = [&](double v) {
    return logSpan > 0 ? left + int(std::lround((std::log1p(v) - logLo) / logSpan * (right - left))) : left;
  };
  for (int x = left; x <= right; ++x) {
    const Color c = loadMapColour(valueAt(x), lo, hi);
    for (int y = barTop; y < barBottom; ++y) picture.set(x, y, c);
  }
  // Ticks: the ends first (they must be labelled), then powers of ten between them.
  std::vector<double> ticks = {lo, hi};
  for (double p = 1; p < hi; p *= 10)
    if (p > lo) ticks.push_back(p);
  std::vector<std::pair<int, int>> taken;  // columns of the labels drawn
  for (double v : ticks) {
    const int x = columnOf(v);
    for (int y = barBottom; y < barBottom + 2 * s; ++y)
      for (int dx = 0; dx < s; ++dx)
        if (x + dx < width) picture.set(x + dx, y, ink);
    const std::string text = compactCount(v);
    const int w = textWidth(text, s);
    const int x0 = std::clamp(x - w / 2, 0, std::max(0, width - w));
    if (w > width) continue;
    bool free = true;
    for (const auto& [a, b] : taken) free = free && (x0 + w + 2 * s <= a || x0 >= b + 2 * s);
    if (!free) continue;
    drawText(picture, text, x0, textTop, s, ink);
    taken.push_back({x0, x0 + w});
  }
  return picture;
}

}  // namespace pvrt
