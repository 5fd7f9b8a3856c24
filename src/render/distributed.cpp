#include "render/distributed.h"

#include <algorithm>
#include <atomic>
#include <deque>
#include <functional>
#include <mutex>
#include <optional>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <string>
#include <thread>

#include "core/error.h"
#include "core/prefault.h"
#include "image/image_io.h"
#include "parallel/cluster.h"
#include "parallel/parallel_for.h"
#include "render/kernel.h"
#include "render/pov_retrace.h"

namespace pvrt {

namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }


// How a pixel travels in a rank's payload: its RGB as 8-bit sRGB or as floats, and its work
// count (a float) with a load map.
struct PayloadLayout {
  bool eightBit = false, loadMap = false;
  size_t rgbBytes() const { return eightBit ? 3 : 3 * sizeof(float); }
  size_t pixelBytes() const { return rgbBytes() + (loadMap ? sizeof(float) : 0); }
};
// The 32-bit words that hold `bytes` bytes.
size_t wordsFor(size_t bytes) { return (bytes + sizeof(uint32_t) - 1) / sizeof(uint32_t); }

// Renders some of the plan's items on this rank, with its OpenMP threads over rows.
class RankRenderer {
 public:
  RankRenderer(const Scene& scene, const RenderSettings& s, const WorkPlan& plan)
      : scene_(scene), s_(s), plan_(plan), sampler_(s.sampler), kernel_(kernelFor(scene.effects)),
        image_(Image::unfilled(s.width, s.height)),  // only this rank's share is written and read
         load_(s.loadMap ? size_t(s.width) * s.height : 0, 0.0f),
        threads_(s.threads > 0 ? s.threads : threadBudget()), perThread_(size_t(threads_)) {}

  void render(const std::vector<int>& items) {
    // The rows of these items (bands of the sampler's granule), handed to the rank's
    // threads one at a time.
    WorkPlan rows;
    rows.strategy = Strategy::Tiles;
    const int g = sampler_.blockGranule();
    for (int i : items) {
      const WorkItem& it = plan_.items[size_t(i)];
      for (int y = it.y0; y < it.y1; y += g) rows.items.push_back({it.x0, y, it.x1, std::min(it.y1, y + g)});
    }
    const auto t0 = Clock::now();
    parallelFor(Backend::OpenMP, threads_, rows, [&](size_t r, int worker) {
      WorkerStats& ws = perThread_[size_t(worker)];
      const auto start = Clock::now();
      // No load map: no per-pixel work to keep, so neighbouring pixels may share packets.
      kernel_(scene_, sampler_, rows.items[r], image_, s_.loadMap ? load_.data() : nullptr, ws.counts, nullptr);
      ws.seconds += secondsSince(start);
      ws.pixels += rows.items[r].pixels();
    });
    compute_ += secondsSince(t0);
    for (int i : items) {
      mine_.push_back(i);
      pixels_ += plan_.items[size_t(i)].pixels();
    }
  }

  // Renders item i whole on one of the rank's threads (the dynamic queue's unit of work);
  // `betweenRows`, when given, runs after each of its rows.
  void renderItem(int i, int worker, const std::function<void()>& betweenRows = {}) {
    WorkerStats& ws = perThread_[size_t(worker)];
    const WorkItem& item = plan_.items[size_t(i)];
    const auto start = Clock::now();
    float* load = s_.loadMap ? load_.data() : nullptr;
    if (betweenRows) {
      const int g = sampler_.blockGranule();  // rows, or bands of whole POV-Ray blocks
      for (int y = item.y0; y < item.y1; y += g) {
        kernel_(scene_, sampler_, {item.x0, y, item.x1, std::min(item.y1, y + g)}, image_, load, ws.counts, nullptr);
        betweenRows();
      }
    } else {
      kernel_(scene_, sampler_, item, image_, load, ws.counts, nullptr);
    }
    ws.seconds += secondsSince(start);
    ws.pixels += item.pixels();
    taken_[size_t(worker)].push_back(i);
  }
  // Runs team(worker) on every thread of the rank (worker 0 is the calling thread, the one
  // that may talk to the other ranks) and books what renderItem rendered.
  void team(const std::function<void(int worker)>& body) {
    taken_.assign(size_t(threads_), {});
    const auto t0 = Clock::now();
    parallelTeam(threads_, body);
    compute_ += secondsSince(t0);
    for (const std::vector<int>& list : taken_)
      for (int i : list) {
        mine_.push_back(i);
        pixels_ += plan_.items[size_t(i)].pixels();
      }
  }
  int threads() const { return threads_; }

  // This rank's share as a self-describing payload: [n, the n item indices (a 32-bit word
  // each), then for each item its rows of RGB (8-bit sRGB, or float), and its rows of work
  // counts (float) when there is a load map, padded to whole words]. Written by all the rank's
  // threads, an item each, into pages they fault in themselves: on the render's critical
  // path, between the last item and the gather. An 8-bit share is encoded here, on every
  // rank's threads, and is a quarter of the float one's bytes (docs/parallel.md).
  std::vector<uint32_t> payload(bool eightBit) const {
    const PayloadLayout layout{eightBit, s_.loadMap};
    std::vector<size_t> at(mine_.size() + 1, sizeof(uint32_t) * (1 + mine_.size()));  // bytes: each item's rows
    for (size_t k = 0; k < mine_.size(); ++k)
      at[k + 1] = at[k] + size_t(plan_.items[size_t(mine_[k])].pixels()) * layout.pixelBytes();
    std::vector<uint32_t> out;
    resizePrefaulted(out, wordsFor(at.back()), threads_);
    out[0] = uint32_t(mine_.size());
    std::copy(mine_.begin(), mine_.end(), out.begin() + 1);
    uint8_t* const bytes = reinterpret_cast<uint8_t*>(out.data());
    parallelIndices(mine_.size(), threads_, [&](size_t k) {
      const WorkItem& it = plan_.items[size_t(mine_[k])];
      const size_t w = size_t(it.x1 - it.x0);
      uint8_t* to = bytes + at[k];
      for (int y = it.y0; y < it.y1; ++y, to += w * layout.rgbBytes()) {
        const float* from = image_.row(y) + size_t(it.x0) * 3;
        if (eightBit) encodeSrgb8(from, 3 * w, to);
        else std::memcpy(to, from, w * layout.rgbBytes());
      }
      if (s_.loadMap)
        for (int y = it.y0; y < it.y1; ++y, to += w * sizeof(float))
          std::memcpy(to, load_.data() + size_t(y) * size_t(s_.width) + size_t(it.x0), w * sizeof(float));
    });
    return out;
  }

  RenderStats counts() const {
    RenderStats t;
    for (const WorkerStats& w : perThread_) t += w.counts;
    return t;
  }
  // Per-thread seconds, pixels and work, as floats that are exact: work is split into
  // 24-bit halves.
  std::vector<float> threadFigures() const {
    std::vector<float> out;
    for (const WorkerStats& w : perThread_) {
      const uint64_t work = w.counts.work();
      out.insert(out.end(), {float(w.seconds), float(w.pixels), float(work >> 24), float(work & 0xFFFFFF)});
    }
    return out;
  }
  double computeSeconds() const { return compute_; }
  long pixels() const { return pixels_; }
  long items() const { return long(mine_.size()); }

 private:
  const Scene& scene_;
  const RenderSettings& s_;
  const WorkPlan& plan_;
  PixelSampler sampler_;
  RectKernel kernel_;
  Image image_;
  std::vector<float> load_;
  int threads_;
  std::vector<WorkerStats> perThread_;
  std::vector<int> mine_;
  std::vector<std::vector<int>> taken_;  // per thread, by renderItem
  double compute_ = 0;
  long pixels_ = 0;
};

// Unpacks concatenated payloads (RankRenderer::payload) into the render area's image (8-bit
// into `rgb8`, else into r.image) and load map: first where each item lies in them, then the
// items copied on up to `threads` threads (the image's pages are first touched there).
void unpack(const std::vector<uint32_t>& all, const WorkPlan& plan, const WorkItem& area, bool eightBit,
            RenderResult& r, std::vector<uint8_t>& rgb8, int threads) {
  struct Placed {
    size_t item, at;  // at: in bytes
  };
  const PayloadLayout layout{eightBit, !r.load.empty()};
  std::vector<Placed> placed;
  size_t word = 0;  // where the next rank's payload starts
  while (word < all.size()) {
    const size_t n = all[word];
    size_t at = (word + 1 + n) * sizeof(uint32_t);
    for (size_t k = 0; k < n; ++k) {
      const size_t item = all[word + 1 + k];
      placed.push_back({item, at});
      at += size_t(plan.items[item].pixels()) * layout.pixelBytes();
    }
    word = wordsFor(at);
  }
  const uint8_t* const bytes = reinterpret_cast<const uint8_t*>(all.data());
  const size_t areaWidth = size_t(area.x1 - area.x0);
  parallelIndices(placed.size(), threads, [&](size_t k) {
    const WorkItem& it = plan.items[placed[k].item];
    const size_t w = size_t(it.x1 - it.x0), x = size_t(it.x0 - area.x0);
    const uint8_t* from = bytes + placed[k].at;
    for (int y = it.y0; y < it.y1; ++y, from += w * layout.rgbBytes()) {
      const size_t row = size_t(y - area.y0);
      if (eightBit) std::memcpy(rgb8.data() + (row * areaWidth + x) * 3, from, w * 3);
      else std::memcpy(r.image.row(int(row)) + x * 3, from, w * layout.rgbBytes());
    }
    if (!r.load.empty())
      for (int y = it.y0; y < it.y1; ++y, from += w * sizeof(float))
        std::memcpy(r.load.data() + size_t(y - area.y0) * areaWidth + x, from, w * sizeof(float));
  });
}

void maybeSlow(const DistributedSettings& d) {
  if (d.slowRank == cluster::rank() && d.slowMillis > 0)
    std::this_thread::sleep_for(std::chrono::milliseconds(d.slowMillis));
}

// A worker rank's items in hand: filled by its thread 0 from rank 0's answers, emptied by
// all its threads.
class HeldItems {
 public:
  enum class Next { Item, Wait, Done };
  void add(const std::vector<int>& batch) {
    std::lock_guard<std::mutex> lock(m_);
    if (batch.empty()) done_ = true;
    items_.insert(items_.end(), batch.begin(), batch.end());
  }
  Next next(int& item) {
    std::lock_guard<std::mutex> lock(m_);
    if (items_.empty()) return done_ ? Next::Done : Next::Wait;
    item = items_.front();
    items_.pop_front();
    return Next::Item;
  }
  size_t size() {
    std::lock_guard<std::mutex> lock(m_);
    return items_.size();
  }
  bool done() {
    std::lock_guard<std::mutex> lock(m_);
    return done_;
  }

 private:
  std::mutex m_;
  std::deque<int> items_;
  bool done_ = false;
};

// The master/worker strategy. Rank 0 holds the queue (an atomic counter over the items):
// its threads render from it (unless --no-master-renders), and its thread 0 answers the
// other ranks' requests between the rows of its own items, sleeping while it has nothing
// else to do, so it never takes a CPU from a worker. A worker asks for as many items as it has threads
// and asks again as soon as it holds no more than that, so the answer comes while it
// renders; every thread renders whole items, as OpenMP's tiles schedule does (thread 0 of
// a rank with several threads a row at a time, minding the messages between rows).
void renderDynamic(RankRenderer& local, int items, const DistributedSettings& d) {
  const int me = cluster::rank(), n = cluster::size();
  if (me == 0) {
    std::atomic<int> next{0};
    const auto take = [&] {
      const int i = next.fetch_add(1, std::memory_order_relaxed);
      return i < items ? i : -1;
    };
    const bool renders = d.masterRenders || n == 1;
    int working = n - 1;  // workers not yet told that nothing is left
    local.team([&](int worker) {
      if (worker != 0) {
        for (int i; renders && (i = take()) >= 0;) {
          maybeSlow(d);
          local.renderItem(i, worker);
        }
        return;
      }
      const auto serve = [&] {
        while (const std::optional<cluster::Request> r = cluster::pollRequest()) {
          std::vector<int> batch;
          for (int i; int(batch.size()) < r->want && (i = take()) >= 0;) batch.push_back(i);
          if (batch.empty()) --working;
          cluster::answer(r->worker, batch);
        }
      };
      for (;;) {
        serve();
        if (const int i = renders ? take() : -1; i >= 0) {
          maybeSlow(d);
          // Row by row, answering between rows: no worker waits for a whole tile.
          local.renderItem(i, 0, serve);
        } else if (working == 0) {
          return;
        } else {
          std::this_thread::sleep_for(std::chrono::microseconds(20));
        }
      }
    });
    return;
  }
  const int want = local.threads();
  cluster::WorkRequest request;
  HeldItems held;
  // Thread 0 takes in answers and asks again; it does so between the rows of its own
  // tiles, so the rank's other threads never wait for it to finish a tile.
  const auto feed = [&] {
    if (request.pending() && request.ready()) held.add(request.take());
    if (!request.pending() && !held.done() && held.size() <= size_t(want)) request.post(want);
  };
  local.team([&](int worker) {
    for (int i = -1;;) {
      if (worker == 0) feed();
      const HeldItems::Next next = held.next(i);
      if (next == HeldItems::Next::Done) return;
      if (next == HeldItems::Next::Item) {
        maybeSlow(d);
        if (worker == 0 && want > 1)
          local.renderItem(i, 0, feed);
        else
          local.renderItem(i, worker);
      } else if (worker == 0) {
        // Nothing to render until the answer comes (none is pending when the other threads
        // emptied the hand since feed() looked: the next feed() asks).
        if (request.pending()) held.add(request.take());
      } else {
        std::this_thread::sleep_for(std::chrono::microseconds(20));
      }
    }
  });
}

}  // namespace

const char* gatherName(GatherMethod g) { return g == GatherMethod::Gatherv ? "gather" : "recursive-doubling"; }

GatherMethod parseGather(const std::string& name) {
  if (name == "gather") return GatherMethod::Gatherv;
  if (name == "recursive-doubling") return GatherMethod::RecursiveDoubling;
  throw Error(ExitCode::Usage, "unknown gather \"" + name + "\" (use gather or recursive-doubling)");
}

DistributedResult renderDistributed(const Scene& scene, const RenderSettings& s, const DistributedSettings& d) {
  const auto t0 = Clock::now();
  const int me = cluster::rank(), n = cluster::size();
  const Strategy strategy = s.schedule.strategy;
  if (strategy != Strategy::Block && strategy != Strategy::Cyclic && strategy != Strategy::Tiles &&
      strategy != Strategy::Dynamic)
    throw Error(ExitCode::Usage, std::string("schedule ") + strategyName(strategy) +
                                     " is an OpenMP schedule; with --backend mpi use block, cyclic, tiles or dynamic");
  // Block and cyclic own rows per rank; tiles (static) deal tiles round robin; dynamic
  // hands the same tiles out on demand.
  ScheduleSettings cut = s.schedule;
  if (strategy == Strategy::Dynamic) cut.strategy = Strategy::Tiles;
  RenderSettings area = s;
  area.schedule = cut;
  const WorkPlan plan = planArea(area, n);

  RankRenderer local(scene, s, plan);
  const double commBefore = cluster::counters().seconds;
  if (strategy == Strategy::Dynamic) {
    renderDynamic(local, int(plan.items.size()), d);
  } else {
    std::vector<int> mine;
    for (size_t i = 0; i < plan.items.size(); ++i) {
      const int owner = plan.owner.empty() ? int(i % size_t(n)) : plan.owner[i];
      if (owner == me) mine.push_back(int(i));
    }
    if (d.slowRank == me)
      for (size_t k = 0; k < mine.size(); ++k) maybeSlow(d);
    local.render(mine);
  }
  const double idle = cluster::barrier();  // waiting here is load imbalance, not communication
  // POV-Ray leaves pixels whose colour is NaN without supersampling (pov_retrace.h): traced
  // again as --pov-blocks when any rank met such a sample, by every rank.
  if (retraceNonFiniteAsPovBlocks(s.sampler) && !s.loadMap && !s.region &&
      cluster::anyFailed(local.counts().nonFiniteSamples > 0)) {
    RenderSettings blocks = s;
    blocks.sampler.adaptive.blocks = true;
    return renderDistributed(scene, blocks, d);
  }

  const std::vector<uint32_t> share = local.payload(d.eightBit);
  const std::vector<uint32_t> all =
      d.gather == GatherMethod::Gatherv ? cluster::gatherv(share) : cluster::gatherRecursiveDoubling(share);

  RankStats mineStats;
  mineStats.computeSeconds = local.computeSeconds();
  mineStats.commSeconds = cluster::counters().seconds - commBefore;
  mineStats.idleSeconds = idle;
  mineStats.wallSeconds = secondsSince(t0);
  const RenderStats c = local.counts();
  const std::vector<double> packed = {mineStats.computeSeconds,   mineStats.commSeconds,
                                      mineStats.idleSeconds,      mineStats.wallSeconds,
                                      double(local.items()),      double(local.pixels()),
                                      double(c.primaryRays),      double(c.shadowRays),
                                      double(c.reflectedRays),    double(c.refractedRays),
                                      double(c.transmittedRays),  double(c.intersectionTests),
                                      double(c.shadingOps),       double(cluster::counters().bytesSent),
                                      double(c.nonFiniteSamples), double(c.nonFinitePixels),
                                      double(c.vistaRays)};
  const std::vector<double> gathered = cluster::gatherFixed(packed);
  // Thread counts may differ between ranks: each rank's figures are prefixed by their count.
  std::vector<float> figures = local.threadFigures();
  figures.insert(figures.begin(), float(figures.size() / 4));
  const std::vector<float> threadFigures = cluster::gatherv(figures);

  DistributedResult out;
  if (me != 0) return out;
  RenderResult& r = out.render;
  const WorkItem areaRect = renderArea(s);
  out.width = areaRect.x1 - areaRect.x0;
  out.height = areaRect.y1 - areaRect.y0;
  // The payloads cover every pixel of the area.
  if (d.eightBit) resizePrefaulted(out.rgb8, size_t(out.width) * size_t(out.height) * 3, local.threads());
  else r.image = Image::unfilled(out.width, out.height);
  if (s.loadMap) r.load.assign(size_t(out.width) * size_t(out.height), 0.0f);
  unpack(all, plan, areaRect, d.eightBit, r, out.rgb8, local.threads());
  r.effects = scene.effects | (PixelSampler(s.sampler).count() > 1 ? kSupersampling : 0u);
  const size_t k = packed.size();
  size_t at = 0;  // into threadFigures
  for (int rank = 0; rank < n; ++rank) {
    const double* g = gathered.data() + size_t(rank) * k;
    RankStats rs;
    rs.computeSeconds = g[0];
    rs.commSeconds = g[1];
    rs.idleSeconds = g[2];
    rs.wallSeconds = g[3];
    rs.items = long(g[4]);
    rs.pixels = long(g[5]);
    rs.counts = {uint64_t(g[6]), uint64_t(g[7]), uint64_t(g[8]), uint64_t(g[9]), uint64_t(g[10]), uint64_t(g[11]),
                 uint64_t(g[12]), uint64_t(g[14]), uint64_t(g[15])};
    rs.counts.vistaRays = uint64_t(g[16]);
    rs.bytesSent = g[13];
    const size_t threads = size_t(threadFigures[at++]);
    for (size_t t = 0; t < threads; ++t, at += 4) {
      WorkerStats ws;
      ws.seconds = threadFigures[at];
      ws.pixels = long(threadFigures[at + 1]);
      // Only the total work is shown per thread; keep it in intersectionTests.
      ws.counts.intersectionTests = (uint64_t(threadFigures[at + 2]) << 24) + uint64_t(threadFigures[at + 3]);
      rs.threads.push_back(ws);
    }
    r.totals += rs.counts;
    WorkerStats ws;
    ws.counts = rs.counts;
    ws.seconds = rs.computeSeconds;
    ws.pixels = rs.pixels;
    r.workers.push_back(ws);
    out.ranks.push_back(rs);
  }
  r.seconds = secondsSince(t0);
  return out;
}

}  // namespace pvrt
