// The body of every kernel: the pixel loop over one rectangle, instantiated for an
// effect set in kernels_*.cpp (split so the instantiations compile in parallel).
#pragma once

#include <algorithm>
#include <vector>

#include "render/kernel.h"
#include "render/tracer.h"

namespace pvrt {

// Below this many rays per pixel a packet saves too little to pay for itself.
inline constexpr size_t kMinPacket = 4;

// The colour of a pixel from its rays' colours, summed in sample order: every path below
// gives the same bits.
inline Color pixelColor(const Color* colors, size_t count) {
  Color sum;
  for (size_t k = 0; k < count; ++k) sum += colors[k];
  return count == 1 ? sum : sum * (1.0 / double(count));
}

// The pixel loop over one rectangle. A pixel with enough rays is traced as packets of
// them (they share the camera's origin). Two neighbouring pixels of a row, the left one
// at an even x, share one packet when their rays fit in it: the tree is walked once for
// both, which on the paper's scene at c=16 saves an eighth of the render (docs/design.md).
// The pairs are fixed by position, so every schedule whose work items do not split them
// (rows, and tiles of an even size) traces the same packets. A load map needs each
// pixel's own work, so with one every pixel is traced alone; the image is the same
// either way, since a packet gives every ray the answers it would get alone.
template <EffectSet E>
void renderRectKernel(const Scene& scene, const PixelSampler& sampler, const WorkItem& rect, Image& image,
                      float* load, RenderStats& stats) {
  Tracer<E> tracer(scene, stats);
  std::vector<SubSample> offsets, partner;
  std::vector<Ray> rays(kMaxPacket);
  std::vector<Color> colors(kMaxPacket);
  const int w = image.width(), h = image.height();
  for (int y = rect.y0; y < rect.y1; ++y) {
    for (int x = rect.x0; x < rect.x1; ++x) {
      sampler.offsets(x, y, offsets);
      const size_t n = offsets.size();
      if (!load && x % 2 == 0 && x + 1 < rect.x1 && n >= kMinPacket) {
        sampler.offsets(x + 1, y, partner);
        const size_t m = partner.size();
        if (n + m <= size_t(kMaxPacket)) {
          tracer.beginPixel();
          scene.camera.rays(x, y, offsets.data(), int(n), w, h, rays.data());
          scene.camera.rays(x + 1, y, partner.data(), int(m), w, h, rays.data() + n);
          stats.primaryRays += uint64_t(n + m);
          tracer.tracePacket(rays.data(), int(n + m), scene.cameraInteriors, colors.data());
          image.set(x, y, pixelColor(colors.data(), n));
          image.set(x + 1, y, pixelColor(colors.data() + n, m));
          ++x;
          continue;
        }
      }
      const uint64_t before = stats.work();
      tracer.beginPixel();
      if (n < kMinPacket) {
        for (size_t k = 0; k < n; ++k) {
          ++stats.primaryRays;
          colors[k] = tracer.trace(scene.camera.ray(x, y, offsets[k].dx, offsets[k].dy, w, h), 0, 1.0,
                                   scene.cameraInteriors);
        }
        image.set(x, y, pixelColor(colors.data(), n));
      } else {
        Color sum;
        for (size_t first = 0; first < n; first += kMaxPacket) {
          const int count = int(std::min<size_t>(kMaxPacket, n - first));
          scene.camera.rays(x, y, offsets.data() + first, count, w, h, rays.data());
          stats.primaryRays += uint64_t(count);
          tracer.tracePacket(rays.data(), count, scene.cameraInteriors, colors.data());
          for (int k = 0; k < count; ++k) sum += colors[k];
        }
        image.set(x, y, sum * (1.0 / double(n)));
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
