// The kernel of POV-Ray's adaptive antialiasing (render/adaptive.h): the POV-Ray blocks of
// one work item, their rays traced by the kernel's tracer. Included by kernel_impl.h.
#pragma once

#include <algorithm>
#include <vector>

#include "accel/packet.h"
#include "core/error.h"
#include "render/adaptive.h"
#include "render/kernel.h"
#include "render/pixel_value.h"
#include "render/tracer.h"

namespace pvrt {

// What the block algorithms ask for, answered with Tracer<E>: every ray is a camera ray.
// The tracer's shadow cache starts empty at each block and is kept from ray to ray within
// it, packets included, in the block's fixed order (POV-Ray's): POV-Ray keeps it along its
// thread's whole run of blocks, which no schedule-independent image can do; the plain
// kernel empties it at each pixel.
template <EffectSet E>
class AdaptiveSource {
 public:
  AdaptiveSource(const Scene& scene, const PixelSampler& sampler, Image& image, RenderStats& stats)
      : scene_(scene), image_(image), stats_(stats), tracer_(scene, stats) {
    sampler.offsets(0, 0, grid_);  // the pov sampler's: the centre, then the n x n grid
    grid_.erase(grid_.begin());
    rays_.resize(std::max<size_t>(grid_.size(), size_t(kMaxPacket)));
    colors_.resize(rays_.size());
  }

  void beginBlock() { tracer_.beginPixel(); }

  void row(int x, int y, int count, double dx, double dy, FloatRgb* out) {
    for (int at = 0; at < count; at += kMaxPacket) {
      const int n = std::min(kMaxPacket, count - at);
      for (int k = 0; k < n; ++k)
        rays_[size_t(k)] = scene_.camera.ray(x + at + k, y, dx, dy, image_.width(), image_.height());
      traceRays(n);
      for (int k = 0; k < n; ++k) out[at + k] = single(colors_[size_t(k)]);
    }
  }

  void several(int x, int y, const SubSample* offsets, int count, FloatRgb* out) {
    scene_.camera.rays(x, y, offsets, count, image_.width(), image_.height(), rays_.data());
    traceRays(count);
    for (int k = 0; k < count; ++k) out[k] = single(colors_[size_t(k)]);
  }

  // POV-Ray's SupersampleOnePixel: the grid's colours added to the centre's in float, in
  // the pov sampler's order, the sum divided by n*n + 1 (PixelSum).
  FloatRgb supersample(int x, int y, FloatRgb first) {
    const int n = int(grid_.size());
    scene_.camera.rays(x, y, grid_.data(), n, image_.width(), image_.height(), rays_.data());
    traceRays(n);
    PixelSum sum;
    sum.add({first.r, first.g, first.b});
    for (int k = 0; k < n; ++k) sum.add(colors_[size_t(k)]);
    return single(sum.mean(size_t(n) + 1));
  }

  void put(int x, int y, FloatRgb c) {
    if (x < 0 || y < 0 || x >= image_.width() || y >= image_.height()) return;
    setPixel(image_, x, y, {c.r, c.g, c.b}, true, stats_);
  }

 private:
  static FloatRgb single(const Color& c) { return {float(c.r), float(c.g), float(c.b)}; }
  // rays_[0, n) into colors_: as packets (camera rays share their origin), or one by one
  // when too few; a sample that is not finite is counted (render/pixel_value.h) and kept, as
  // POV-Ray keeps it.
  void traceRays(int n) {
    stats_.primaryRays += uint64_t(n);
    if (size_t(n) < kMinPacket) {
      for (int k = 0; k < n; ++k) colors_[size_t(k)] = tracer_.trace(rays_[size_t(k)], 0, 1.0, scene_.cameraInteriors);
    } else {
      for (int at = 0; at < n; at += kMaxPacket) {
        tracer_.setPixelStarts(0);  // the cache goes on from the rays before, in the block's order
        tracer_.tracePacket(rays_.data() + at, std::min(kMaxPacket, n - at), scene_.cameraInteriors,
                            colors_.data() + at);
      }
    }
    finiteSamples(colors_.data(), size_t(n), stats_);
  }

  const Scene& scene_;
  Image& image_;
  RenderStats& stats_;
  Tracer<E> tracer_;
  std::vector<SubSample> grid_;
  std::vector<Ray> rays_;
  std::vector<Color> colors_;
};

// The work item `rect` is a union of whole POV-Ray blocks (the plan's granule,
// PixelSampler::blockGranule()); each is rendered on its own, in any order.
template <EffectSet E>
void renderAdaptiveRect(const Scene& scene, const PixelSampler& sampler, const WorkItem& rect, Image& image,
                        RenderStats& stats) {
  const AdaptiveSettings& a = sampler.adaptiveSettings();
  const ColourTest test(a.threshold);
  const int b = a.blockSize, depth = sampler.depth();
  auto onEdge = [b](int v, int end) { return v % b == 0 || v == end; };
  if (!onEdge(rect.x0, -1) || !onEdge(rect.y0, -1) || !onEdge(rect.x1, image.width()) ||
      !onEdge(rect.y1, image.height()))
    throw Error(ExitCode::Internal, "adaptive antialiasing was given a work item that splits a POV-Ray block");
  AdaptiveSource<E> source(scene, sampler, image, stats);
  for (int y0 = rect.y0; y0 < rect.y1; y0 += b)
    for (int x0 = rect.x0; x0 < rect.x1; x0 += b) {
      const int x1 = std::min(x0 + b, rect.x1), y1 = std::min(y0 + b, rect.y1);
      source.beginBlock();
      if (a.method == 2) antialiasBlockMethod2(x0, y0, x1, y1, depth, test, source);
      else antialiasBlockMethod1(x0, y0, x1, y1, test, source);
    }
}

}  // namespace pvrt
