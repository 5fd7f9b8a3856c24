// One golden test's result: what was compared, the figures, the verdict. A run keeps one
// file per test in OUT/results/ so that tests run apart (one CTest test each) can still
// make one report together (`pvrt golden report OUT`).
#pragma once

#include <string>
#include <vector>

#include "golden/tolerances.h"
#include "image/compare.h"

namespace pvrt::golden {

struct Outcome {
  std::string name;  // scene.variant.backend
  std::string scene, variant, backend;
  bool passed = false;
  std::string message;  // why it failed, or what it checked
  bool compared = false;  // stats hold a comparison
  CompareResult stats;
  Tolerance tolerance;
  std::string image, reference;  // paths; image may be absent when the render failed
  double seconds = 0;
};

void saveOutcome(const Outcome& o, const std::string& resultsDir);
std::vector<Outcome> loadOutcomes(const std::string& resultsDir);  // sorted by name

// Compares `o.image` with `o.reference` under `o.tolerance`, filling stats, passed and message.
void judge(Outcome& o);

}  // namespace pvrt::golden
