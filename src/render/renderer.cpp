#include "render/renderer.h"

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "core/error.h"
#include "core/interrupt.h"
#include "render/kernel.h"
#include "render/pixel_value.h"
#include "render/pov_retrace.h"

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
  kernelFor(effects)(scene, sampler, rect, image, load, stats, nullptr);
}

WorkItem renderArea(const RenderSettings& s) {
  if (!s.region) return {0, 0, s.width, s.height};
  const WorkItem& r = *s.region;
  if (r.x0 < 0 || r.y0 < 0 || r.x1 > s.width || r.y1 > s.height || r.x0 >= r.x1 || r.y0 >= r.y1)
    throw Error(ExitCode::Usage, "pvrt: error: region columns " + std::to_string(r.x0 + 1) + "-" +
                                     std::to_string(r.x1) + ", rows " + std::to_string(r.y0 + 1) + "-" +
                                     std::to_string(r.y1) + " is not a non-empty part of the " +
                                     std::to_string(s.width) + " x " + std::to_string(s.height) + " image");
  return r;
}

WorkPlan planArea(const RenderSettings& s, int workers) {
  const WorkItem area = renderArea(s);
  ScheduleSettings cut = s.schedule;
  cut.granule = PixelSampler(s.sampler).blockGranule();  // adaptive antialiasing renders whole POV-Ray blocks
  WorkPlan plan = makeWorkPlan(cut, area.x1 - area.x0, area.y1 - area.y0, workers);
  for (WorkItem& it : plan.items) it = {it.x0 + area.x0, it.y0 + area.y0, it.x1 + area.x0, it.y1 + area.y0};
  return plan;
}

void cropToArea(RenderResult& r, const RenderSettings& s) {
  if (!s.region) return;
  const WorkItem a = renderArea(s);
  const int w = a.x1 - a.x0, h = a.y1 - a.y0;
  Image image(w, h);
  for (int y = 0; y < h; ++y)
    std::copy_n(r.image.row(a.y0 + y) + size_t(a.x0) * 3, size_t(w) * 3, image.row(y));
  r.image = std::move(image);
  if (r.load.empty()) return;
  std::vector<float> load(size_t(w) * h);
  for (int y = 0; y < h; ++y)
    std::copy_n(r.load.data() + size_t(a.y0 + y) * size_t(s.width) + size_t(a.x0), size_t(w),
                load.data() + size_t(y) * size_t(w));
  r.load = std::move(load);
}

namespace {

RenderResult renderOnce(const Scene& scene, const RenderSettings& settings) {
  const auto t0 = Clock::now();
  RenderResult result;
  // Full size, so that every pixel is traced as in the whole image; the plan covers the
  // area (or a stride of it), and only those pixels are read.
  result.image = Image::unfilled(settings.width, settings.height);
  if (settings.loadMap) result.load.assign(size_t(settings.width) * settings.height, 0.0f);
  const RectKernel kernel = kernelFor(scene.effects);

  const int workers = settings.backend == Backend::Serial
                          ? 1
                          : (settings.threads > 0 ? settings.threads : threadBudget());
  WorkPlan plan = planArea(settings, workers);
  if (settings.itemStride > 1) {  // owners (block, cyclic) are the runtime's then: tiles
    WorkPlan sample;
    for (size_t i = 0; i < plan.items.size(); i += size_t(settings.itemStride)) sample.items.push_back(plan.items[i]);
    plan = std::move(sample);
  }
  result.workers.assign(size_t(workers), WorkerStats{});

  std::atomic<bool> cancelled{false};
  long total = 0;
  for (const WorkItem& it : plan.items) total += it.pixels();
  // Every pixel of the plan once, with `sampler`'s samples.
  auto pass = [&](const PixelSampler& sampler, PassBuffers* buffers) {
    std::atomic<long> done{0};
    // A render in passes is timed by its budget (render/passes.h); one pass's share of
    // the pixels says nothing of when the render ends.
    std::optional<Watchdog> watchdog;
    if (!buffers) watchdog.emplace(settings, done, total, plan.items.size(), workers, t0);
    parallelFor(settings.backend, workers, plan, [&](size_t i, int worker) {
      if (interrupt::requested()) {
        cancelled = true;
        return;
      }
      const WorkItem& item = plan.items[i];
      WorkerStats& ws = result.workers[size_t(worker)];
      const auto start = Clock::now();
      kernel(scene, sampler, item, result.image, settings.loadMap ? result.load.data() : nullptr, ws.counts, buffers);
      ws.seconds += secondsSince(start);
      ws.pixels += item.pixels();
      const long now = done.fetch_add(item.pixels()) + item.pixels();
      if (worker == 0 && settings.progress) settings.progress(now, total);
    });
  };

  int samples = settings.sampler.samplesPerPixel;
  if (!settings.nextPass) {
    pass(PixelSampler(settings.sampler), nullptr);
  } else {
    PassBuffers buffers;
    buffers.nonFinite.assign(size_t(settings.width) * size_t(settings.height), 0);
    PassesSoFar so;
    for (;;) {
      so.seconds = secondsSince(t0);
      const int next = std::min(settings.nextPass(so), settings.sampler.samplesPerPixel);
      if (next <= so.done || cancelled) break;
      SamplerSettings window = settings.sampler;
      window.firstSample = so.done;
      window.samplesPerPixel = next;
      const PixelSampler sampler(window);  // checks that the pass starts at a restart point
      buffers.resume = so.done > 0;
      const auto start = Clock::now();
      pass(sampler, &buffers);
      so.passes.push_back({so.done, next, secondsSince(start)});
      so.done = next;
    }
    if (so.done == 0) throw Error(ExitCode::Internal, "a render in passes rendered no sample");
    samples = so.done;
    result.passes = so.passes;
    // The sums become means, with the checks setPixel() makes, pixel by pixel as in one go.
    parallelFor(settings.backend, workers, plan, [&](size_t i, int worker) {
      const WorkItem& item = plan.items[i];
      RenderStats& counts = result.workers[size_t(worker)].counts;
      for (int y = item.y0; y < item.y1; ++y)
        for (int x = item.x0; x < item.x1; ++x) {
          const float* p = result.image.row(y) + size_t(x) * 3;
          const PixelSum sum{p[0], p[1], p[2]};
          const bool finite = !buffers.nonFinite[size_t(y) * size_t(settings.width) + size_t(x)];
          setPixel(result.image, x, y, sum.mean(size_t(samples)), finite, counts);
        }
    });
  }
  SamplerSettings used = settings.sampler;
  used.samplesPerPixel = samples;
  result.effects = scene.effects | (PixelSampler(used).count() > 1 ? kSupersampling : 0u);
  for (const WorkerStats& ws : result.workers) result.totals += ws.counts;
  result.cancelled = cancelled;
  cropToArea(result, settings);
  result.seconds = secondsSince(t0);
  return result;
}

}  // namespace

RenderResult render(const Scene& scene, const RenderSettings& settings) {
  RenderResult first = renderOnce(scene, settings);
  if (first.cancelled || first.totals.nonFiniteSamples == 0 || !retraceNonFiniteAsPovBlocks(settings.sampler) ||
      settings.loadMap || settings.region)
    return first;
  // POV-Ray leaves pixels whose colour is NaN without supersampling (pov_retrace.h). The block
  // kernel takes neither a load map (it shares a pixel's rays with its neighbours) nor a
  // region (POV-Ray's blocks are the whole image's): with one, the image stays plain.
  RenderSettings blocks = settings;
  blocks.sampler.adaptive.blocks = true;
  RenderResult again = renderOnce(scene, blocks);
  again.seconds += first.seconds;
  return again;
}

}  // namespace pvrt
