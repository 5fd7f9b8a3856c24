// `pvrt render --stats-json FILE`: every figure that --stats prints, as one JSON object, for
// programs (bench/*.py read it). The keys are listed in docs/cli.md; times are in seconds,
// sizes in bytes, counts as integers.
#pragma once

#include <string>
#include <vector>

#include "core/stage_clock.h"
#include "render/distributed.h"
#include "render/time_budget.h"

namespace pvrt::cli {

// What the run knows besides the render's own result.
struct RunFigures {
  std::string scene, output, backend, gather;  // gather: MPI only
  StageTime load, build, render, write;  // wall and CPU time of each stage (core/stage_clock.h)
  size_t peakBytes = 0, loadPeakBytes = 0, buildPeakBytes = 0;  // rank 0's under MPI
  const BudgetPlan* budget = nullptr;                           // with --time-budget and pilots
  double timeBudget = 0;                                        // --time-budget's seconds, or 0
};

// `ranks` is empty except under MPI (then one entry per rank, with its threads).
std::string statsJson(const RunFigures& run, const RenderSettings& settings, const Scene& scene,
                      const RenderResult& result, const std::vector<RankStats>& ranks);

}  // namespace pvrt::cli
