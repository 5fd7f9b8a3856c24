#include "render/time_budget.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "core/error.h"

namespace pvrt {

namespace {
// A pilot renders every kPilotStride-th tile of kPilotTile pixels: a seventeenth of the
// image, spread over it (17 shares no factor with the usual tile counts per row, so the
// tiles fall on diagonals, not in columns).
constexpr int kPilotStride = 17;
constexpr int kPilotTile = 16;
// At most this many pilots; and none that could cost more than this share of what is left
// (bounded by the dearest so far, in proportion to the rays).
constexpr int kMaxPilots = 6;
constexpr double kPilotShareOfLeft = 0.25;
constexpr double kPilotMinSeconds = 0.05;
constexpr int kPilotMaxRepeats = 8;
// Beyond the largest measured c, a ray costs at least this share of that c's cost per ray (on
// paper1, user time: a ray added from c = 16 to 64 costs 0.98 of the mean at 64).
constexpr double kMinSlopeShare = 0.5;

// Sorted by rays, one point per ray count (the last measured), and made non-decreasing in
// cost, so that the prediction is monotone in c.
std::vector<CostPoint> ordered(std::vector<CostPoint> points) {
  std::stable_sort(points.begin(), points.end(),
                   [](const CostPoint& a, const CostPoint& b) { return a.rays < b.rays; });
  std::vector<CostPoint> out;
  for (const CostPoint& p : points) {
    if (!out.empty() && out.back().rays == p.rays)
      out.back() = p;
    else
      out.push_back(p);
  }
  for (size_t i = 1; i < out.size(); ++i)
    out[i].secondsPerPixel = std::max(out[i].secondsPerPixel, out[i - 1].secondsPerPixel);
  return out;
}

double along(const CostPoint& a, const CostPoint& b, double rays) {
  return a.secondsPerPixel + (b.secondsPerPixel - a.secondsPerPixel) * (rays - a.rays) / (b.rays - a.rays);
}

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }
}  // namespace

double cameraRaysPerPixel(SamplerKind kind, int samplesPerPixel) {
  return kind == SamplerKind::Pov && samplesPerPixel > 1 ? samplesPerPixel + 1.0 : double(samplesPerPixel);
}

double predictSecondsPerPixel(const std::vector<CostPoint>& unordered, double rays) {
  const std::vector<CostPoint> p = ordered(unordered);
  if (p.empty()) return 0;
  const CostPoint& last = p.back();
  if (p.size() == 1 || rays <= p.front().rays) return p.front().secondsPerPixel * rays / p.front().rays;
  if (rays >= last.rays) {
    const CostPoint& before = p[p.size() - 2];
    // Between half and all of the last point's cost per ray: measured on a shared machine, two
    // close points can give any slope, and a flat one would send the next pilot to c = 65536.
    const double perRay = last.secondsPerPixel / last.rays;
    const double slope = std::clamp((last.secondsPerPixel - before.secondsPerPixel) / (last.rays - before.rays),
                                    kMinSlopeShare * perRay, perRay);
    return last.secondsPerPixel + slope * (rays - last.rays);
  }
  const auto hi = std::lower_bound(p.begin(), p.end(), rays, [](const CostPoint& q, double r) { return q.rays < r; });
  return along(*(hi - 1), *hi, rays);
}

bool takesAnyCount(SamplerKind kind) { return kind == SamplerKind::Jitter; }

int nextSmallerCount(SamplerKind kind, int samplesPerPixel) {
  if (samplesPerPixel <= 1) return 1;
  if (takesAnyCount(kind)) return samplesPerPixel - std::max(1, samplesPerPixel / 4);
  const int n = int(std::lround(std::sqrt(double(samplesPerPixel))));
  return (n - 1) * (n - 1);
}

int chooseSamplesPerPixel(SamplerKind kind, long pixels, const std::vector<CostPoint>& points, double budgetSeconds,
                          int maxSamplesPerPixel) {
  // c = step(k) for k = 1, 2, ...: every whole number for jitter, the squares for pov and grid.
  const bool any = takesAnyCount(kind);
  auto step = [&](int k) { return any ? k : k * k; };
  auto fits = [&](int k) {
    return double(pixels) * predictSecondsPerPixel(points, cameraRaysPerPixel(kind, step(k))) <= budgetSeconds;
  };
  // Binary search on k: the predicted time grows with it.
  int lo = 1, hi = std::max(1, any ? maxSamplesPerPixel : int(std::floor(std::sqrt(double(maxSamplesPerPixel)))));
  while (step(hi) > maxSamplesPerPixel) --hi;
  if (!fits(lo)) return 1;
  while (lo < hi) {
    const int mid = lo + (hi - lo + 1) / 2;
    if (fits(mid))
      lo = mid;
    else
      hi = mid - 1;
  }
  return step(lo);
}

BudgetPlan planForBudget(const Scene& scene, const RenderSettings& settings, double budgetSeconds, double spentSeconds,
                         int maxSamplesPerPixel) {
  if (!(budgetSeconds > 0) || !std::isfinite(budgetSeconds))
    throw Error(ExitCode::Usage,
                "--time-budget must be a positive number of seconds, got " + std::to_string(budgetSeconds));
  const SamplerKind kind = settings.sampler.kind;
  const WorkItem area = renderArea(settings);
  const long pixels = area.pixels();
  RenderSettings pilot = settings;
  pilot.itemStride = kPilotStride;
  pilot.schedule.strategy = Strategy::Tiles;
  pilot.schedule.tileSize = kPilotTile;
  pilot.loadMap = false;
  pilot.progress = nullptr;
  pilot.announce = nullptr;

  BudgetPlan plan;
  double dearest = 0;  // wall seconds of one repetition of the pilot with the most rays
  // A pilot is repeated until it has lasted kPilotMinSeconds: a few milliseconds of wall time
  // on a shared machine say more of the other programs than of the render.
  auto run = [&](int c) {
    pilot.sampler.samplesPerPixel = c;
    double seconds = 0;
    long rendered = 0;
    bool cancelled = false;
    int reps = 0;
    for (; reps < kPilotMaxRepeats && seconds < kPilotMinSeconds && !cancelled; ++reps) {
      const auto t0 = Clock::now();
      const RenderResult r = render(scene, pilot);
      seconds += since(t0);
      for (const WorkerStats& w : r.workers) rendered += w.pixels;
      cancelled = r.cancelled;
    }
    plan.pilotSeconds += seconds;
    plan.pilotShare = double(rendered) / double(reps) / double(pixels);
    plan.pilotSamples.push_back(c);
    plan.points.push_back({cameraRaysPerPixel(kind, c), seconds / double(std::max(rendered, 1L))});
    dearest = seconds / reps;  // one repetition's
    return !cancelled;
  };
  auto left = [&] { return budgetSeconds - spentSeconds - plan.pilotSeconds; };

  bool going = run(1);
  while (going && int(plan.pilotSamples.size()) < kMaxPilots) {
    const double measured = plan.points.back().rays;  // pilots go up in rays
    int c = chooseSamplesPerPixel(kind, pixels, plan.points, left(), maxSamplesPerPixel);
    // One point says nothing of how the cost grows with c (proportionally, it would say c = 1
    // where c = 4 fits: a ray at c = 1 costs about 3 of one at c >= 4); a second comes from c >= 4.
    if (plan.points.size() == 1 && maxSamplesPerPixel >= 4) c = std::max(c, 4);
    // A pilot no dearer than its share of what is left, even if the cost were proportional.
    while (c > 1 && dearest * cameraRaysPerPixel(kind, c) / measured > kPilotShareOfLeft * left())
      c = nextSmallerCount(kind, c);
    if (cameraRaysPerPixel(kind, c) <= measured) break;  // between measured points: read off them
    going = run(c);
  }
  plan.samplesPerPixel = chooseSamplesPerPixel(kind, pixels, plan.points, left(), maxSamplesPerPixel);
  plan.predictedSeconds =
      double(pixels) * predictSecondsPerPixel(plan.points, cameraRaysPerPixel(kind, plan.samplesPerPixel));
  plan.fits = plan.predictedSeconds <= left();
  return plan;
}

}  // namespace pvrt
