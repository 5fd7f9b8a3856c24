// The body of every kernel: the pixel loop over one rectangle, instantiated for an
// effect set in kernels_*.cpp (split so the instantiations compile in parallel).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "render/kernel.h"
#include "render/tracer.h"

namespace pvrt {

// Below this many rays per pixel a packet saves too little to pay for itself.
inline constexpr size_t kMinPacket = 4;

// The NaN census. A camera sample whose colour is not finite (NaN or infinite: a bug, or
// arithmetic past the range of a double) is counted and counts as black: one bad ray must
// neither poison its pixel nor reach the image, and black is what no light looks like. A
// pixel whose value overflows the image's float is written as +-FLT_MAX (the brightest
// value the image can hold) and counted too. Either way `pvrt render` warns.
inline bool finiteSamples(Color* colors, size_t count, RenderStats& stats) {
  bool all = true;
  for (size_t k = 0; k < count; ++k) {
    Color& c = colors[k];
    if (std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b)) continue;
    c = Color();
    ++stats.nonFiniteSamples;
    all = false;
  }
  return all;
}
inline void setPixel(Image& image, int x, int y, Color c, bool finite, RenderStats& stats) {
  constexpr double kMax = std::numeric_limits<float>::max();
  for (double* v : {&c.r, &c.g, &c.b})
    if (!(std::fabs(*v) <= kMax)) {
      *v = std::copysign(kMax, *v);
      finite = false;
    }
  if (!finite) ++stats.nonFinitePixels;
  image.set(x, y, c);
}

// A pixel's rays' colours summed as POV-Ray sums them (TraceTask::SupersampleOnePixel):
// each a float colour, added in sample order in float, the sum divided by the count in
// double and stored as a float. Summed in double, a channel within a hair of a level's
// edge lands on the other side of it.
struct PixelSum {
  float r = 0, g = 0, b = 0;
  void add(const Color& c) {
    r += float(c.r);
    g += float(c.g);
    b += float(c.b);
  }
  Color mean(size_t count) const {
    const double n = double(count);
    return {double(r) / n, double(g) / n, double(b) / n};
  }
};

// The colour of a pixel from its rays' colours: every path below gives the same bits.
inline Color pixelColor(const Color* colors, size_t count) {
  PixelSum sum;
  for (size_t k = 0; k < count; ++k) sum.add(colors[k]);
  return sum.mean(count);
}

// Neighbouring pixels of a row share one packet when their rays fit in it: the tree is
// then walked once for all of them, and their hits' shadow segments go toward each light
// together. How many: a power of two (up to 8), so that the groups tile every work item
// whose width is a multiple of it; at c = 4, 9 and 16 with the pov sampler, 8, 4 and 2.
inline constexpr int kMaxPacketPixels = 8;
inline int pixelsPerPacket(size_t raysPerPixel) {
  if (raysPerPixel < kMinPacket) return 1;
  int k = 1;
  while (2 * k <= kMaxPacketPixels && size_t(2 * k) * raysPerPixel <= size_t(kMaxPacket)) k *= 2;
  return k;
}

// The pixel loop over one rectangle. A pixel with enough rays is traced as packets (its
// rays share the camera's origin), and a group of pixelsPerPacket() neighbours, the first
// at a multiple of that in x, as one packet. The groups are fixed by position, so every
// schedule whose work items do not split them (rows, and tiles of the default size)
// traces the same packets and counts the same work; one that splits a group traces its
// pixels alone. A load map needs each pixel's own work, so with one every pixel is traced
// alone. The image is the same either way: a packet gives each ray the answers it would
// get alone, and each pixel's colours are summed in the same order.
template <EffectSet E>
void renderRectKernel(const Scene& scene, const PixelSampler& sampler, const WorkItem& rect, Image& image,
                      float* load, RenderStats& stats) {
  Tracer<E> tracer(scene, stats);
  std::vector<SubSample> offsets;
  std::vector<Ray> rays(kMaxPacket);
  std::vector<Color> colors(kMaxPacket);
  const int w = image.width(), h = image.height();
  const int group = load ? 1 : pixelsPerPacket(size_t(sampler.count()));
  for (int y = rect.y0; y < rect.y1; ++y) {
    for (int x = rect.x0; x < rect.x1; ++x) {
      if (group > 1 && x % group == 0 && x + group <= rect.x1) {
        tracer.beginPixel();
        size_t first[kMaxPacketPixels + 1] = {};  // pixel i's rays are [first[i], first[i + 1])
        for (int i = 0; i < group; ++i) {
          sampler.offsets(x + i, y, offsets);
          scene.camera.rays(x + i, y, offsets.data(), int(offsets.size()), w, h, rays.data() + first[i]);
          first[i + 1] = first[i] + offsets.size();
        }
        stats.primaryRays += uint64_t(first[group]);
        uint64_t starts = 0;
        for (int i = 0; i < group; ++i) starts |= uint64_t(1) << first[i];
        tracer.setPixelStarts(starts);
        tracer.tracePacket(rays.data(), int(first[group]), scene.cameraInteriors, colors.data());
        for (int i = 0; i < group; ++i) {
          Color* c = colors.data() + first[i];
          const bool finite = finiteSamples(c, first[i + 1] - first[i], stats);
          setPixel(image, x + i, y, pixelColor(c, first[i + 1] - first[i]), finite, stats);
        }
        x += group - 1;
        continue;
      }
      sampler.offsets(x, y, offsets);
      const size_t n = offsets.size();
      const uint64_t before = stats.work();
      tracer.beginPixel();
      if (n < kMinPacket) {
        for (size_t k = 0; k < n; ++k) {
          ++stats.primaryRays;
          colors[k] = tracer.trace(scene.camera.ray(x, y, offsets[k].dx, offsets[k].dy, w, h), 0, 1.0,
                                   scene.cameraInteriors);
        }
        const bool finite = finiteSamples(colors.data(), n, stats);
        setPixel(image, x, y, pixelColor(colors.data(), n), finite, stats);
      } else {
        PixelSum sum;
        bool finite = true;
        for (size_t first = 0; first < n; first += kMaxPacket) {
          const int count = int(std::min<size_t>(kMaxPacket, n - first));
          scene.camera.rays(x, y, offsets.data() + first, count, w, h, rays.data());
          stats.primaryRays += uint64_t(count);
          tracer.tracePacket(rays.data(), count, scene.cameraInteriors, colors.data());
          finite = finiteSamples(colors.data(), size_t(count), stats) && finite;
          for (int k = 0; k < count; ++k) sum.add(colors[k]);
        }
        setPixel(image, x, y, sum.mean(n), finite, stats);
      }
      if (load) load[size_t(y) * w + x] = float(stats.work() - before);
    }
  }
}

// Fills table[Base .. Base+Count) with the kernels for those effect sets.
template <EffectSet Base, EffectSet... I>
void fillKernels(RectKernel* table, std::integer_sequence<EffectSet, I...>) {
  ((table[Base + I] = &renderRectKernel<Base + I>), ...);
}

}  // namespace pvrt
