// Picking the supersampling coefficient c for a time budget (`pvrt render --time-budget`):
// a pilot render at a sixteenth of the pixels measures the time of one camera ray with all
// the rays it spawns, and c is the largest perfect square whose render is predicted to fit
// what is left of the budget. The prediction is linear in camera rays: time(c) =
// pixels x raysPerPixel(c) x secondsPerSample, where raysPerPixel is the sampler's count
// (c + 1 for pov with c > 1: the centre ray; c otherwise).
#pragma once

#include "render/renderer.h"

namespace pvrt {

struct BudgetPlan {
  int samplesPerPixel = 1;        // the chosen c (1 when even c = 1 is predicted not to fit)
  double predictedSeconds = 0;    // render time predicted for the chosen c
  double secondsPerSample = 0;    // per camera ray, measured by the pilot
  double pilotSeconds = 0;        // wall time of the pilot render(s)
  int pilotWidth = 0, pilotHeight = 0, pilotSamplesPerPixel = 1;
  bool fits = true;               // false when c = 1 is predicted to exceed the budget
};

// Predicted render time of a width x height image at c samples per pixel.
double predictRenderSeconds(SamplerKind kind, int samplesPerPixel, long pixels, double secondsPerSample);

// The largest perfect square c <= maxSamplesPerPixel whose predicted time is at most
// budgetSeconds; 1 when none fits. Pure, so it is monotone in the budget by construction.
int chooseSamplesPerPixel(SamplerKind kind, long pixels, double secondsPerSample, double budgetSeconds,
                          int maxSamplesPerPixel = 1 << 16);

// Runs the pilot with `settings` (its sampler kind, backend, threads and schedule) and
// plans c for a render that must finish within budgetSeconds of wall time, the pilot
// included. Throws pvrt::Error(Usage) when budgetSeconds <= 0.
BudgetPlan planForBudget(const Scene& scene, const RenderSettings& settings, double budgetSeconds,
                         int maxSamplesPerPixel = 1 << 16);

}  // namespace pvrt
