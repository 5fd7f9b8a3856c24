// Running a golden suite: every selected reference rendered by pvrt on each backend and
// compared with it, several renders at once; or another renderer's images compared instead.
#pragma once

#include <string>
#include <vector>

#include "golden/outcome.h"
#include "golden/suite.h"

namespace pvrt::golden {

struct RunOptions {
  std::vector<std::string> backends{"serial", "openmp"};  // serial, openmp, mpi
  int threads = 2;   // of an openmp render
  int ranks = 3;     // of an mpi render (one thread each)
  int jobs = 0;      // renders at once; 0: half the CPUs
  std::string mpirun = "mpirun";
  std::vector<std::string> renderOptions;  // appended to every `pvrt render`
  std::vector<std::string> scenes, variants;  // empty: all
  std::string skipList;  // a file of `scene.variant` names to leave out (tested elsewhere)
  std::string out = "golden-out";  // OUT/images, OUT/logs, OUT/results
  bool ignoreStale = false;  // bless: a changed scene is what is being blessed
};

// The manifest entries the options select, and the scenes they select that have none.
struct Selection {
  std::vector<ManifestEntry> entries;
  std::vector<std::string> unreferenced;
};
Selection select(const Suite& suite, const RunOptions& o);

// Renders and compares; each outcome is also saved under OUT/results.
std::vector<Outcome> runSuite(const Suite& suite, const RunOptions& o);
// Compares IMAGES/<reference's file name> with each selected reference ("external" backend).
std::vector<Outcome> compareFolder(const Suite& suite, const std::string& images, const RunOptions& o);

// Half the CPUs, at least 1: renders at once when --jobs is not given.
int defaultJobs();

}  // namespace pvrt::golden
