// The body of every kernel: the pixel loop over one rectangle, instantiated for an
// effect set in kernels_*.cpp (split so the instantiations compile in parallel).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "render/adaptive_kernel.h"
#include "render/kernel.h"
#include "render/pixel_value.h"
#include "render/tracer.h"

namespace pvrt {

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
  if (sampler.adaptive()) return renderAdaptiveRect<E>(scene, sampler, rect, image, stats);
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
