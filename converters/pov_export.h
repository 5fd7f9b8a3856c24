// Exports a scene description to POV-Ray 3.7 scene language (SDL). The output is
// byte-stable: a fixed order, and numbers printed so that they read back exactly.
// It follows the recipe of shared/povray-semantics.md section 0: `#version 3.7;`,
// `assumed_gamma 1.0`, and a camera that states right and up explicitly.
#pragma once

#include <string>
#include <vector>

#include "render/adaptive.h"
#include "scene/scene_desc.h"

namespace pvrt {

struct PovExport {
  std::string sdl;
  // `file:line: warning: ... not exported`, one per thing POV-Ray cannot be told.
  std::vector<std::string> warnings;
};

PovExport exportPov(const SceneDesc& scene);

// The POV-Ray command line that renders an export the way pvrt's `pov` sampler does
// (`+A0.0 +AM1 +Rn -J`, or `-A` for one sample per pixel); with `aa`, POV-Ray's adaptive
// antialiasing as `--aa-threshold`, `--aa-method` and `--aa-block` ask for it
// (`+A0.3 +AM2 +R3 -J`, and `+BSb` when the block is not POV-Ray's default 32).
std::string povCommandLine(const std::string& pov, const std::string& png, int width, int height, int aaDepth,
                           const AdaptiveSettings& aa = {});

}  // namespace pvrt
