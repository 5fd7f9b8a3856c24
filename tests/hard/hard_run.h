// Running one hard case: load scenes/hard/CASE.xml, move it by a sweep, render it with
// the backend under test, check the float image against the case's exact answer
// (cases.h) and put the measured figures on one line.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "render/renderer.h"

namespace pvrt::hard {

// Renders a built scene at w x h with the backend under test (collective under MPI).
using RenderFn = std::function<RenderResult(const Scene&, int w, int h)>;

// Serial, or OpenMP with two threads ("serial" / "openmp"): the renders the checks compare against.
RenderResult renderOn(const Scene& scene, int w, int h, const std::string& backend);

struct CaseResult {
  bool pass = true;
  std::string line;  // "HARD CASE SWEEP BACKEND: PASS|FAIL figures..."
};

// The cases: the scenes of scenes/hard/, sorted.
std::vector<std::string> caseNames();
// Their sweeps as hard_case takes them: 0..3 for kSweeps (sweep.h), tN for a translation by N.
std::vector<std::string> sweepsOf(const std::string& name);

// On every backend but serial the image must also be bit-identical to a serial render.
// Only `root` checks (the others just take part in the render); `dump` names a PFM file for the float image.
CaseResult runCase(const std::string& name, const std::string& sweep, const std::string& backend,
                   const RenderFn& render, bool root = true, const std::string& dump = "");

}  // namespace pvrt::hard
