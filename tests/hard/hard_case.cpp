// One hard case through one sweep on the serial or OpenMP backend (the MPI backend runs
// them all at once: hard_case_mpi.cpp). Prints the measured figures on one line; exit
// status 0 when every check passes.
//
//   hard_case CASE SWEEP BACKEND [--dump FILE.pfm]
//     SWEEP    0..3: (offset, scale) = (0, 1), (1e3, 1), (0, 1e-3), (1e4, 1e3);
//              tN: translated by N along every axis (compared with the untranslated image)
//     BACKEND  serial | openmp (2 threads)
#include <cstdio>
#include <exception>
#include <string>

#include "hard_run.h"

using namespace pvrt;

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: hard_case CASE SWEEP serial|openmp [--dump FILE.pfm]\n");
    return 2;
  }
  const std::string name = argv[1], sweep = argv[2], backend = argv[3];
  const std::string dump = argc >= 6 && std::string(argv[4]) == "--dump" ? argv[5] : "";
  auto renderWith = [&](const Scene& scene, int w, int h) {
    return hard::renderOn(scene, w, h, backend == "serial" ? "serial" : "openmp");
  };
  try {
    const hard::CaseResult r = hard::runCase(name, sweep, backend, renderWith, true, dump);
    std::printf("%s\n", r.line.c_str());
    return r.pass ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hard_case: %s\n", e.what());
    return 1;
  }
}
