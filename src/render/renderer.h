// The render stage: a built Scene in, a linear float image (and its statistics) out.
#pragma once

#include <atomic>
#include <functional>
#include <vector>

#include "image/image.h"
#include "parallel/parallel_for.h"
#include "parallel/schedule.h"
#include "render/sampler.h"
#include "render/scene.h"
#include "render/stats.h"

namespace pvrt {

struct RenderSettings {
  int width = 320;
  int height = 240;
  SamplerSettings sampler;
  Backend backend = Backend::OpenMP;
  int threads = 0;  // 0: OpenMP's default
  ScheduleSettings schedule;
  bool loadMap = false;  // record the work of every pixel
  // Called now and then from one worker with the pixels finished so far; may be empty.
  std::function<void(long done, long total)> progress;
  // Set from a signal handler to stop a render early (the result is then incomplete).
  const std::atomic<bool>* cancel = nullptr;
};

// Aligned to a cache line: workers update their own counters per ray.
struct alignas(64) WorkerStats {
  RenderStats counts;
  double seconds = 0;  // time spent rendering items
  long pixels = 0;
};

struct RenderResult {
  Image image;
  std::vector<float> load;  // width*height work counts when settings.loadMap
  RenderStats totals;
  std::vector<WorkerStats> workers;
  EffectSet effects = 0;  // the kernel's effects (plus supersampling)
  double seconds = 0;
  bool cancelled = false;
};

RenderResult render(const Scene& scene, const RenderSettings& settings);

// Renders the pixels of one rectangle into `image` with the kernel for `effects`;
// `load` (may be null) receives per-pixel work. Used by every backend.
void renderRect(const Scene& scene, const PixelSampler& sampler, EffectSet effects, const WorkItem& rect,
                Image& image, float* load, RenderStats& stats);

}  // namespace pvrt
