#include "render/renderer.h"

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>

#include "core/interrupt.h"
#include "render/kernel.h"

namespace pvrt {

namespace {
using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}
// Predicts the render's time each second (LongRender) and announces it once, when it is
// at least settings.announceSeconds. Stopped and joined when the render ends.
class Watchdog {
 public:
  Watchdog(const RenderSettings& s, const std::atomic<long>& done, long total, size_t tiles, int workers,
           Clock::time_point t0) {
    if (!s.announce) return;
    thread_ = std::thread([=, &s, &done, this] {
      std::unique_lock<std::mutex> lock(mutex_);
      while (!stop_) {
        wake_.wait_for(lock, std::chrono::seconds(1));
        if (stop_) return;
        LongRender r;
        r.elapsedSeconds = secondsSince(t0);
        r.shareDone = double(done.load()) / double(total);
        r.atLeast = r.shareDone == 0;
        r.predictedSeconds = r.atLeast ? r.elapsedSeconds * double(tiles) / double(std::max(workers, 1))
                                       : r.elapsedSeconds / r.shareDone;
        if (r.predictedSeconds >= s.announceSeconds) {
          s.announce(r);
          return;
        }
      }
    });
  }
  ~Watchdog() {
    if (!thread_.joinable()) return;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    thread_.join();
  }

 private:
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::thread thread_;
};

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
  ScheduleSettings cut = settings.schedule;
  cut.granule = sampler.blockGranule();  // adaptive antialiasing renders whole POV-Ray blocks
  const WorkPlan plan = makeWorkPlan(cut, settings.width, settings.height, workers);
  result.workers.assign(size_t(workers), WorkerStats{});

  std::atomic<long> done{0};
  std::atomic<bool> cancelled{false};
  const long total = long(settings.width) * settings.height;
  Watchdog watchdog(settings, done, total, plan.items.size(), workers, t0);
  parallelFor(settings.backend, workers, plan, [&](size_t i, int worker) {
    if (interrupt::requested()) {
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
