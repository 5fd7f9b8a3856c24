// Making and storing references: POV-Ray's render of each scene's export (the oracle), or
// pvrt's own render (bless: "this output is right; keep it"). Both record in the manifest
// what made each image, and write every image and the manifest together or not at all.
#pragma once

#include <string>
#include <vector>

#include "golden/outcome.h"
#include "golden/suite.h"

namespace pvrt::golden {

struct MakeOptions {
  std::vector<std::string> scenes;  // empty: every scene of the folder
  std::string variant;              // empty: each scene's variants in the manifest (aa for a new scene)
  std::string antialiasing;         // empty: the manifest's, or +A0.0 +AM1 +R3 -J for a new entry
  int width = 160;                  // of a new entry; its height keeps the scene's aspect ratio
  std::string povray = "povray";
  int jobs = 0;                     // POV-Ray renders at once (0: half the CPUs)
  bool verify = false;              // render again and demand the stored pixels; store nothing
};

// Returns the number of references that failed (POV-Ray failed, or --verify found a change).
int makeReferences(Suite& suite, const MakeOptions& o);

// The manifest entries a make or bless would write for `scene` (existing ones updated).
std::vector<ManifestEntry> plannedEntries(const Suite& suite, const std::string& scene, const std::string& variant,
                                          const std::string& antialiasing, int width);

// Stores pvrt's renders (the outcomes' images) as the references of their entries, with a
// manifest line saying which pvrt command made each.
void storeBlessed(Suite& suite, const std::vector<ManifestEntry>& entries, const std::vector<Outcome>& outcomes);

}  // namespace pvrt::golden
