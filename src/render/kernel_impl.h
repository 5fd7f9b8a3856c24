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

template <EffectSet E>
void renderRectKernel(const Scene& scene, const PixelSampler& sampler, const WorkItem& rect, Image& image,
                      float* load, RenderStats& stats) {
  Tracer<E> tracer(scene, stats);
  std::vector<SubSample> offsets;
  std::vector<Ray> rays(kMaxPacket);
  std::vector<Color> colors(kMaxPacket);
  const int w = image.width(), h = image.height();
  for (int y = rect.y0; y < rect.y1; ++y) {
    for (int x = rect.x0; x < rect.x1; ++x) {
      const uint64_t before = stats.work();
      tracer.beginPixel();
      sampler.offsets(x, y, offsets);
      Color sum;
      if (offsets.size() < kMinPacket) {
        for (const SubSample& s : offsets) {
          ++stats.primaryRays;
          sum += tracer.trace(scene.camera.ray(x, y, s.dx, s.dy, w, h), 0, 1.0, scene.cameraInteriors);
        }
      } else {
        // The pixel's rays share the camera's origin: traced as packets. The colours are
        // summed in sample order, as above, so both paths give the same bits.
        for (size_t first = 0; first < offsets.size(); first += kMaxPacket) {
          const int n = int(std::min<size_t>(kMaxPacket, offsets.size() - first));
          scene.camera.rays(x, y, offsets.data() + first, n, w, h, rays.data());
          stats.primaryRays += uint64_t(n);
          tracer.tracePacket(rays.data(), n, scene.cameraInteriors, colors.data());
          for (int k = 0; k < n; ++k) sum += colors[k];
        }
      }
      image.set(x, y, offsets.size() == 1 ? sum : sum * (1.0 / double(offsets.size())));
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
