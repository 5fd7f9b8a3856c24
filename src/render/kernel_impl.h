// The body of every kernel: the pixel loop over one rectangle, instantiated for an
// effect set in kernels_*.cpp (split so the instantiations compile in parallel).
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include "render/adaptive_kernel.h"
#include "render/camera_grid.h"
#include "render/kernel.h"
#include "render/pixel_value.h"
#include "render/tracer.h"
#include "render/vista.h"

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

// Where a pixel's sum goes: its value in the image, or in a render in passes its sum so
// far (read back by the next pass; setPixel()'s checks come in finishPasses()).
class PixelOut {
 public:
  PixelOut(Image& image, PassBuffers* pass, RenderStats& stats) : image_(image), pass_(pass), stats_(stats) {}
  // Whether start() gives sums so far (a later pass), not zero.
  bool resumes() const { return pass_ && pass_->resume; }
  PixelSum start(int x, int y) const {
    if (!pass_ || !pass_->resume) return {};
    const float* p = image_.row(y) + size_t(x) * 3;
    return {p[0], p[1], p[2]};
  }
  void finish(int x, int y, const PixelSum& sum, size_t count, bool finite) {
    if (!pass_) return setPixel(image_, x, y, sum.mean(count), finite, stats_);
    float* p = image_.row(y) + size_t(x) * 3;
    p[0] = sum.r, p[1] = sum.g, p[2] = sum.b;
    if (!finite) pass_->nonFinite[size_t(y) * size_t(image_.width()) + size_t(x)] = 1;
  }

 private:
  Image& image_;
  PassBuffers* pass_;
  RenderStats& stats_;
};

// The pixel loop over one rectangle. A pixel with enough rays is traced as packets (its
// rays share the camera's origin), and a group of pixelsPerPacket() neighbours, the first
// at a multiple of that in x, as one packet. The groups are fixed by position, so every
// schedule whose work items do not split them (rows, and tiles of the default size)
// traces the same packets and counts the same work; one that splits a group traces its
// pixels alone. A load map needs each pixel's own work, so with one every pixel is traced
// alone. The image is the same either way: a packet gives each ray the answers it would
// get alone, and each pixel's colours are summed in the same order. A pixel's own packets
// start at its samples' multiples of kMaxPacket, and its shadow cache restarts where the
// sampler says (PixelSampler::restartsAt), so that a render in passes traces each sample
// as one pass would.
template <EffectSet E>
void renderRectKernel(const Scene& scene, const PixelSampler& sampler, const WorkItem& rect, Image& image,
                      float* load, RenderStats& stats, PassBuffers* pass) {
  if (sampler.adaptive()) return renderAdaptiveRect<E>(scene, sampler, rect, image, stats);
  Tracer<E> tracer(scene, stats);
  PixelOut out(image, pass, stats);
  std::vector<SubSample> offsets;
  std::vector<Ray> rays(kMaxPacket);
  std::vector<Color> colors(kMaxPacket);
  const int w = image.width(), h = image.height();
  const int firstSample = sampler.firstSample(), total = sampler.count();
  const int group = load ? 1 : pixelsPerPacket(size_t(total - firstSample));
  // Bit k set where ray k of a packet of one pixel's samples from `from` restarts the cache.
  auto restarts = [&](int from, int count) {
    uint64_t bits = 0;
    for (int k = 0; k < count; ++k)
      if (sampler.restartsAt(from + k)) bits |= uint64_t(1) << k;
    return bits;
  };
  const int perPixel = total - firstSample;
  const uint64_t pixelStarts = restarts(firstSample, perPixel);
  // With the same offsets for every pixel, the camera's quotients once per column and row,
  // and the pixels whose rays surely meet nothing. Those get the background without their
  // rays being made or traced, where each pixel starts its own shadow cache (then whether
  // a pixel's rays went with its neighbours' or not, it leaves the next pixel nothing).
  std::optional<CameraGrid> grid;
  std::optional<VistaMask> vista;
  if (sampler.sameOffsetsEveryPixel()) {
    sampler.offsets(rect.x0, rect.y0, offsets);
    grid.emplace(scene.camera, offsets, rect.x0, rect.x1, w, h);
    if (scene.vista.usable() && (pixelStarts & 1)) {
      vista.emplace(scene.vista, scene.bvh, rect, w, h, offsets);
      if (!vista->any()) vista.reset();
    }
  }
  // A clear pixel's value: the background's colour for each of its rays, summed as any
  // pixel's are. Every pixel starts its own shadow cache (above), so a clear one leaves the
  // tracer nothing to do for it.
  PixelSum skySum;
  for (int k = 0; k < perPixel; ++k) skySum.add(scene.background);
  const Color& bg = scene.background;
  const uint64_t skyNonFinite =
      std::isfinite(bg.r) && std::isfinite(bg.g) && std::isfinite(bg.b) ? 0 : uint64_t(perPixel);
  auto skyPixel = [&](int px, int py) {
    PixelSum sum = skySum;
    if (out.resumes()) {
      sum = out.start(px, py);
      for (int k = 0; k < perPixel; ++k) sum.add(scene.background);
    }
    stats.primaryRays += uint64_t(perPixel);
    stats.vistaRays += uint64_t(perPixel);
    stats.nonFiniteSamples += skyNonFinite;
    out.finish(px, py, sum, size_t(total), skyNonFinite == 0);
  };
  if (sampler.blockCache()) {
    // --pov-blocks at one ray a pixel (POV-Ray's -A): each block's pixels row by row, as
    // SimpleSamplingM0 traces them, the shadow cache kept from pixel to pixel within the
    // block. Work items hold whole blocks (blockGranule), so every schedule traces the same.
    const int b = sampler.blockGranule();
    for (int by = rect.y0 - rect.y0 % b; by < rect.y1; by += b) {
      for (int bx = rect.x0 - rect.x0 % b; bx < rect.x1; bx += b) {
        tracer.beginPixel();
        for (int y = std::max(by, rect.y0); y < std::min(by + b, rect.y1); ++y) {
          if (grid) grid->setRow(y);
          for (int x = std::max(bx, rect.x0); x < std::min(bx + b, rect.x1); ++x) {
            const uint64_t before = stats.work();
            if (vista && vista->clear(x, y)) {
              skyPixel(x, y);
            } else {
              if (!grid) sampler.offsets(x, y, offsets);
              ++stats.primaryRays;
              const Ray ray = grid ? grid->ray(x, 0) : scene.camera.ray(x, y, offsets[0].dx, offsets[0].dy, w, h);
              const Color c = tracer.trace(ray, 0, 1.0, scene.cameraInteriors);
              PixelSum sum = out.start(x, y);
              sum.add(c);
              out.finish(x, y, sum, size_t(total), finiteSamples(&c, 1, stats));
            }
            if (load) load[size_t(y) * w + x] += float(stats.work() - before);
          }
        }
      }
    }
    return;
  }
  for (int y = rect.y0; y < rect.y1; ++y) {
    if (grid) grid->setRow(y);
    for (int x = rect.x0; x < rect.x1; ++x) {
      if (group > 1 && x % group == 0 && x + group <= rect.x1) {
        // The group's clear pixels leave its packet (a packet gives each ray the answer it
        // would get alone).
        unsigned clear = 0;
        if (vista)
          for (int i = 0; i < group; ++i) clear |= unsigned(vista->clear(x + i, y)) << i;
        tracer.beginPixel();
        size_t first[kMaxPacketPixels + 1] = {};  // pixel i's rays are [first[i], first[i + 1])
        uint64_t starts = 0;
        for (int i = 0; i < group; ++i) {
          if (clear >> i & 1u) {
            first[i + 1] = first[i];
            continue;
          }
          if (!grid) {
            sampler.offsets(x + i, y, offsets);
            scene.camera.rays(x + i, y, offsets.data(), perPixel, w, h, rays.data() + first[i]);
          } else if (clear) {
            grid->rays(x + i, 0, perPixel, rays.data() + first[i]);
          }
          first[i + 1] = first[i] + size_t(perPixel);
          starts |= pixelStarts << first[i];
        }
        if (grid && !clear) grid->rays(x, group, rays.data());
        if (first[group] > 0) {
          stats.primaryRays += uint64_t(first[group]);
          tracer.setPixelStarts(starts);
          tracer.tracePacket(rays.data(), int(first[group]), scene.cameraInteriors, colors.data());
        }
        for (int i = 0; i < group; ++i) {
          if (clear >> i & 1u) {
            skyPixel(x + i, y);
            continue;
          }
          const Color* c = colors.data() + first[i];
          const size_t n = first[i + 1] - first[i];
          const bool finite = finiteSamples(c, n, stats);
          PixelSum sum = out.start(x + i, y);
          for (size_t k = 0; k < n; ++k) sum.add(c[k]);
          out.finish(x + i, y, sum, size_t(total), finite);
        }
        x += group - 1;
        continue;
      }
      if (!grid) sampler.offsets(x, y, offsets);
      const int n = perPixel;
      const uint64_t before = stats.work();
      if (vista && vista->clear(x, y)) {
        skyPixel(x, y);
        if (load) load[size_t(y) * w + x] += float(stats.work() - before);
        continue;
      }
      PixelSum sum = out.start(x, y);
      bool finite = true;
      if (size_t(n) < kMinPacket) {
        for (int k = 0; k < n; ++k) {
          if (sampler.restartsAt(firstSample + k)) tracer.beginPixel();
          ++stats.primaryRays;
          const Ray ray = grid ? grid->ray(x, k) : scene.camera.ray(x, y, offsets[size_t(k)].dx, offsets[size_t(k)].dy, w, h);
          colors[size_t(k)] = tracer.trace(ray, 0, 1.0, scene.cameraInteriors);
        }
        finite = finiteSamples(colors.data(), size_t(n), stats);
        for (int k = 0; k < n; ++k) sum.add(colors[size_t(k)]);
      } else {
        for (int from = firstSample; from < total;) {
          const int to = std::min(total, (from / kMaxPacket + 1) * kMaxPacket);
          const int count = to - from;
          if (sampler.restartsAt(from)) tracer.beginPixel();
          tracer.setPixelStarts(restarts(from, count) | 1);
          if (grid)
            grid->rays(x, from - firstSample, count, rays.data());
          else
            scene.camera.rays(x, y, offsets.data() + (from - firstSample), count, w, h, rays.data());
          stats.primaryRays += uint64_t(count);
          tracer.tracePacket(rays.data(), count, scene.cameraInteriors, colors.data());
          finite = finiteSamples(colors.data(), size_t(count), stats) && finite;
          for (int k = 0; k < count; ++k) sum.add(colors[size_t(k)]);
          from = to;
        }
      }
      out.finish(x, y, sum, size_t(total), finite);
      if (load) load[size_t(y) * w + x] += float(stats.work() - before);
    }
  }
}

// Fills table[Base .. Base+Count) with the kernels for those effect sets.
template <EffectSet Base, EffectSet... I>
void fillKernels(RectKernel* table, std::integer_sequence<EffectSet, I...>) {
  ((table[Base + I] = &renderRectKernel<Base + I>), ...);
}

}  // namespace pvrt
