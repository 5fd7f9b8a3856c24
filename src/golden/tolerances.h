// reference/tolerances.tsv: thresholds looser than the default, each with its reason.
//   scene  max_levels  max_fraction_over_1  [max_off_by_1]  reason
// (the max_off_by_1 column is there when the header line names it; without it, any number of
// channels may be off by 1).
// A line whose scene is `*` sets the suite's own default. A line without a reason is an
// error: a tolerance nobody can explain is a bug hidden, not a threshold.
#pragma once

#include <map>
#include <string>

#include "image/compare.h"

namespace pvrt::golden {

struct Tolerance {
  CompareThresholds limits{2, 0.0};  // no channel off by more than 1 level; see reference/README.md
  std::string reason;                // empty for the built-in default
  std::string origin;                // `tolerances.tsv:4`, or empty
};

struct Tolerances {
  Tolerance suite;  // `*`, or the built-in default
  std::map<std::string, Tolerance> scenes;

  // A line for SCENE.VARIANT holds for that variant alone, before the scene's own line.
  const Tolerance& of(const std::string& scene, const std::string& variant = "") const {
    auto it = variant.empty() ? scenes.end() : scenes.find(scene + "." + variant);
    if (it == scenes.end()) it = scenes.find(scene);
    return it == scenes.end() ? suite : it->second;
  }
};

// An absent file gives the defaults. Throws pvrt::Error(SceneError) `FILE:LINE: error: what`.
Tolerances readTolerances(const std::string& path);

}  // namespace pvrt::golden
