#include "render/time_budget.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"

namespace pvrt {

namespace {
// The pilot renders this share of the pixels (a quarter of each side), and is rendered
// again at four times the samples until it lasts long enough to be timed.
constexpr int kPilotDivisor = 4;
constexpr double kPilotMinSeconds = 0.02;
constexpr int kPilotMaxSamples = 64;
}  // namespace

double predictRenderSeconds(SamplerKind kind, int samplesPerPixel, long pixels, double secondsPerSample) {
  const PixelSampler sampler(SamplerSettings{kind, samplesPerPixel, 0});
  return double(pixels) * double(sampler.count()) * secondsPerSample;
}

int chooseSamplesPerPixel(SamplerKind kind, long pixels, double secondsPerSample, double budgetSeconds,
                          int maxSamplesPerPixel) {
  auto fits = [&](int n) { return predictRenderSeconds(kind, n * n, pixels, secondsPerSample) <= budgetSeconds; };
  // Binary search on the side n of the grid: the predicted time grows with n.
  int lo = 1, hi = std::max(1, int(std::floor(std::sqrt(double(maxSamplesPerPixel)))));
  while (hi * hi > maxSamplesPerPixel) --hi;
  if (!fits(lo)) return 1;
  while (lo < hi) {
    const int mid = lo + (hi - lo + 1) / 2;
    if (fits(mid)) lo = mid;
    else hi = mid - 1;
  }
  return lo * lo;
}

BudgetPlan planForBudget(const Scene& scene, const RenderSettings& settings, double budgetSeconds,
                         int maxSamplesPerPixel) {
  if (!(budgetSeconds > 0) || !std::isfinite(budgetSeconds))
    throw Error(ExitCode::Usage, "--time-budget must be a positive number of seconds, got " +
                                     std::to_string(budgetSeconds));
  BudgetPlan plan;
  RenderSettings pilot = settings;
  pilot.width = std::max(1, settings.width / kPilotDivisor);
  pilot.height = std::max(1, settings.height / kPilotDivisor);
  pilot.loadMap = false;
  pilot.progress = nullptr;
  plan.pilotWidth = pilot.width;
  plan.pilotHeight = pilot.height;
  // Rays per pixel at c = 1 and 4 differ by the pov sampler's centre ray; the time per
  // camera ray is what carries over, so the pilot divides by the sampler's count.
  for (int c = 1;; c *= 4) {
    pilot.sampler.samplesPerPixel = c;
    const RenderResult r = render(scene, pilot);
    plan.pilotSeconds += r.seconds;
    plan.pilotSamplesPerPixel = c;
    plan.secondsPerSample = r.seconds / (double(pilot.width) * pilot.height * PixelSampler(pilot.sampler).count());
    if (r.cancelled || r.seconds >= kPilotMinSeconds || c >= kPilotMaxSamples ||
        plan.pilotSeconds >= budgetSeconds / 4)
      break;
  }
  const long pixels = long(settings.width) * settings.height;
  const double left = budgetSeconds - plan.pilotSeconds;
  const SamplerKind kind = settings.sampler.kind;
  plan.samplesPerPixel = chooseSamplesPerPixel(kind, pixels, plan.secondsPerSample, left, maxSamplesPerPixel);
  plan.predictedSeconds = predictRenderSeconds(kind, plan.samplesPerPixel, pixels, plan.secondsPerSample);
  plan.fits = plan.predictedSeconds <= left;
  return plan;
}

}  // namespace pvrt
