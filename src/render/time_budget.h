// Picking the supersampling coefficient c for a time budget (`pvrt render --time-budget`).
//
// The cost of a pixel is not proportional to its camera rays: a part of it does not grow
// with c (the pixel's first hits, shared packets, the film), and the rays of one pixel get
// cheaper as they get more coherent. On paper1 at 1280 x 800 the old model (seconds per
// camera ray at c = 1, times the rays) predicted 9.45 s for c = 25 that took 2.47 s. So c is
// found by measuring: pilot renders of a sample of the image's own tiles (every 17th, at
// the image's resolution, with its sampler, backend and threads) give the seconds per pixel
// at a few c, and the time of another c is read off the line through the nearest two. A
// pilot is made at each c the search would otherwise extrapolate to, so the c chosen lies
// among measured ones.
#pragma once

#include <vector>

#include "render/renderer.h"

namespace pvrt {

// Measured: wall seconds per pixel when every pixel traces `rays` camera rays.
struct CostPoint {
  double rays = 0;
  double secondsPerPixel = 0;
};

// PixelSampler(kind, c).count() without building the sampler's offsets (the search asks for
// c up to 65536): c, and c + 1 for pov with c > 1 (its centre ray).
double cameraRaysPerPixel(SamplerKind kind, int samplesPerPixel);

// Seconds per pixel at `rays` camera rays from measured points (any order): the line through
// the two nearest measured ray counts around it, the last two beyond the largest (rising by
// half to all of the largest's cost per ray, whatever noise says), and in proportion to the
// rays when there is one point.
double predictSecondsPerPixel(const std::vector<CostPoint>& points, double rays);

// Whether the sampler takes any whole c (jitter), not only perfect squares (pov, grid).
bool takesAnyCount(SamplerKind kind);
// A c the sampler takes below `samplesPerPixel` (> 1): the next smaller square for pov and
// grid, about three quarters of it for jitter; 1 for 1.
int nextSmallerCount(SamplerKind kind, int samplesPerPixel);

// The largest c <= maxSamplesPerPixel that the sampler takes (any whole number for jitter, a
// perfect square for pov and grid) whose predicted time (pixels x seconds per pixel at the
// sampler's rays for c) is at most budgetSeconds; 1 when none fits. Pure, and monotone in
// the budget.
int chooseSamplesPerPixel(SamplerKind kind, long pixels, const std::vector<CostPoint>& points, double budgetSeconds,
                          int maxSamplesPerPixel = 1 << 16);

struct BudgetPlan {
  int samplesPerPixel = 1;        // the chosen c (1 when even c = 1 is predicted not to fit)
  double predictedSeconds = 0;    // render time predicted for the chosen c
  double pilotSeconds = 0;        // wall time of the pilot renders together
  double pilotShare = 0;          // of the image's pixels that each pilot rendered
  std::vector<int> pilotSamples;  // c of each pilot, in order
  std::vector<CostPoint> points;  // what they measured
  bool fits = true;               // false when c = 1 is predicted to exceed what was left
};

// Plans c for a render that must end within budgetSeconds of wall time, of which
// spentSeconds are gone already (loading, building); the pilots count too. Runs the pilots
// with `settings` (region, sampler kind, backend, threads). Throws pvrt::Error(Usage) when
// budgetSeconds <= 0.
BudgetPlan planForBudget(const Scene& scene, const RenderSettings& settings, double budgetSeconds,
                         double spentSeconds = 0, int maxSamplesPerPixel = 1 << 16);

}  // namespace pvrt
