// The `pvrt render` options that reproduce a reference: read from the manifest's command, so
// that a reference made with other antialiasing settings is rendered with those settings.
//   povray ... +A0.0 +AM1 +Rn -J   ->  --sampler pov --spp n*n   (POV-Ray's grid, bit for bit)
//   povray ... -A                  ->  --sampler pov --spp 1
//   pvrt render S.xml -o S.png ARGS ->  ARGS (a blessed pvrt output)
// A POV-Ray setting pvrt has no equivalent for is an error naming it, not a guess.
#pragma once

#include <string>
#include <vector>

#include "golden/manifest.h"

namespace pvrt::golden {

// Throws pvrt::Error(SceneError) `manifest.tsv:LINE: error: ...` for a setting it cannot map.
std::vector<std::string> renderSettings(const ManifestEntry& e, const std::string& manifestPath);

// The POV-Ray options of a command after `-D +FN` (its antialiasing), e.g. `+A0.0 +AM1 +R3 -J`.
std::string povrayAntialiasing(const std::string& command);
// The antialiasing depth the manifest's aa_depth column records for those options.
int aaDepthOf(const std::string& antialiasing);

}  // namespace pvrt::golden
