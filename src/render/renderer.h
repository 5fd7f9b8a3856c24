// The render stage: a built Scene in, a linear float image (and its statistics) out.
#pragma once

#include <atomic>
#include <functional>
#include <optional>
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
  // Only these pixels of the width x height image are rendered, each exactly as in the
  // whole image (`pvrt render --region`); the result is the region's size. Empty: all.
  std::optional<WorkItem> region;
  // Renders only every itemStride-th work item of the plan (the time budget's pilot: a
  // sample of the image at its own resolution); the other pixels are left unset.
  int itemStride = 1;
  // A render in passes (the sequence sampler): called before each pass with what the passes
  // so far did, it says where the next one ends: samples [done, next) of every pixel; done
  // (or less) to stop. sampler.samplesPerPixel is then only the most it may say. Empty: one go. The
  // image is that of --spp done (render/passes.h).
  std::function<int(const struct PassesSoFar&)> nextPass;
  // Called now and then from one worker with the pixels finished so far; may be empty.
  std::function<void(long done, long total)> progress;
  // Called at most once, from a watchdog thread, when the render is predicted to take at
  // least announceSeconds in all (see LongRender); may be empty.
  std::function<void(const struct LongRender&)> announce;
  double announceSeconds = 3600;
};

// A prediction of a render's wall time, made each second from the pixels finished so far:
// elapsed / (share done), or, before any tile is done, at least elapsed x (tiles / workers)
// (each worker's first tile has taken that long already).
struct LongRender {
  double predictedSeconds = 0;
  bool atLeast = false;  // a lower bound: no tile was finished yet
  double elapsedSeconds = 0;
  double shareDone = 0;  // of the pixels
};

// One pass of a render in passes: samples [first, last) of every pixel.
struct PassRecord {
  int first = 0, last = 0;
  double seconds = 0;  // wall time of the pass
};
struct PassesSoFar {
  int done = 0;  // samples per pixel traced
  std::vector<PassRecord> passes;
  double seconds = 0;  // since the render began
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
  bool cancelled = false;  // by a signal (core/interrupt.h): the image is incomplete
  std::vector<PassRecord> passes;  // a render in passes: each pass (the last one's end is c)
};

RenderResult render(const Scene& scene, const RenderSettings& settings);

// The pixels a render computes: settings.region, or the whole image. Throws
// pvrt::Error(Usage) when the region is empty or leaves the image.
WorkItem renderArea(const RenderSettings& settings);
// The schedule's plan over renderArea(), its items in the whole image's coordinates, so
// that every pixel is traced as it is in the whole image.
WorkPlan planArea(const RenderSettings& settings, int workers);
// A full-size result cut down to renderArea() (image and load map); nothing without a region.
void cropToArea(RenderResult& result, const RenderSettings& settings);

// Renders the pixels of one rectangle into `image` with the kernel for `effects`;
// `load` (may be null) receives per-pixel work. Used by every backend.
void renderRect(const Scene& scene, const PixelSampler& sampler, EffectSet effects, const WorkItem& rect,
                Image& image, float* load, RenderStats& stats);

}  // namespace pvrt
