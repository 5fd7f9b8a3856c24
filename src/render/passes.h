// A time budget met by rendering in passes (`pvrt render --time-budget` with the sequence
// sampler, its default there).
//
// Pilots that measure a sample of the image and predict c (render/time_budget.h) miss by
// what the machine does meanwhile: on the shared 2-core VM the render took 0.71-1.27 times
// its prediction. The sequence sampler's sample k of a pixel does not depend on c, so the
// image can be rendered a pass at a time (samples [done, next) of every pixel, their sums
// kept between passes) and stopped between passes: each decision is taken from the time
// the whole image's latest passes took, just before it, and only the last pass is a
// prediction. The image is --spp c's bit for bit (render/kernel_impl.h).
#pragma once

#include "render/renderer.h"

namespace pvrt {

struct PassBudget {
  double budgetSeconds = 0;  // for the whole run
  double spentSeconds = 0;   // before the render began (loading, building)
  double writeSeconds = 0;   // foreseen for writing the outputs
  int maxSamples = 1 << 16;
};

// Seconds a pass of `samples` samples per pixel is predicted to take, from the passes so far:
// the line through the latest two of different sizes (a pass has a part that does not grow
// with its samples: the pixels' first hits, the sums), its slope kept between half and all
// of the latest pass's cost per sample; in proportion to the latest pass when there is one
// size. 0 before any pass.
double predictPassSeconds(const std::vector<PassRecord>& passes, int samples);

// Where a whole pass after `done` samples ends: 1, 2, 4, ..., 64, then every 64 (each pass
// as long as the samples so far, until a pass is long enough to measure well).
int wholePassEnd(int done);

// Where the next pass ends (RenderSettings::nextPass): samples [so.done, next) of every
// pixel. The first pass is one sample; then whole passes (wholePassEnd()) while one is
// predicted to fit in what is left of the budget, then a shorter pass of as many samples as
// bring the end nearest to the budget (over it by at most kMaxOvershoot of it), and again
// while that leaves time for a sample; so.done to stop.
int nextPassEnd(const PassBudget& budget, const PassesSoFar& so);

// Where one sample a pixel costs a good share of the budget (10^5 spheres at 2 s: 0.6 s of
// it), stopping short misses as far as going over; but a budget is also a limit, so the
// nearer end is taken only up to this far past it.
inline constexpr double kMaxOvershoot = 0.10;

}  // namespace pvrt
