#include "render/renderer.h"

#include <algorithm>
#include <chrono>

#include "render/kernel.h"

namespace pvrt {

namespace {
using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}
}  // namespace

void renderRect(const Scene& scene, const PixelSampler& sampler, EffectSet effects, const WorkItem& rect,
                Image& image, float* load, RenderStats& stats) {
  kernelFor(effects)(scene, sampler, rect, image, load, stats);
}

RenderResult render(const Scene& scene, const RenderSettings& settings) {
  const auto t0 = Clock::now();
  RenderResult result;
  result.image = Image::unfilled(settings.width, settings.height);  // the plan covers every pixel
  if (settings.loadMap) result.load.assign(size_t(settings.width) * settings.height, 0.0f);
  const PixelSampler sampler(settings.sampler);
  result.effects = scene.effects | (sampler.count() > 1 ? kSupersampling : 0u);
  const RectKernel kernel = kernelFor(scene.effects);

  const int workers = settings.backend == Backend::Serial
                          ? 1
                          : (settings.threads > 0 ? settings.threads : threadBudget());
  const WorkPlan plan = makeWorkPlan(settings.schedule, settings.width, settings.height, workers);
  result.workers.assign(size_t(workers), WorkerStats{});

  std::atomic<long> done{0};
  std::atomic<bool> cancelled{false};
  const long total = long(settings.width) * settings.height;
  parallelFor(settings.backend, workers, plan, [&](size_t i, int worker) {
    if (settings.cancel && settings.cancel->load(std::memory_order_relaxed)) {
      cancelled = true;
      return;
    }
    const WorkItem& item = plan.items[i];
    WorkerStats& ws = result.workers[size_t(worker)];
    const auto start = Clock::now();
    kernel(scene, sampler, item, result.image, settings.loadMap ? result.load.data() : nullptr, ws.counts);
    ws.seconds += secondsSince(start);
    ws.pixels += item.pixels();
    const long now = done.fetch_add(item.pixels()) + item.pixels();
    if (worker == 0 && settings.progress) settings.progress(now, total);
  });
  for (const WorkerStats& ws : result.workers) result.totals += ws.counts;
  result.cancelled = cancelled;
  result.seconds = secondsSince(t0);
  return result;
}

}  // namespace pvrt
