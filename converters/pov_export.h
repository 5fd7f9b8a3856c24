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

// How the export is to be rendered: the POV-Ray command line that samples as `pvrt render
// --sampler pov --aa-depth n` does, at the scene's resolution (320 x 240 without <image>),
// reading `povName` (a file name, folders left out).
struct PovRecipe {
  int aaDepth = 0;  // n of +Rn; 0 for -A (pvrt's --spp 1)
  std::string povName = "scene.pov";
};

// `sdl` (exportPov's) with the recipe as two comment lines after its header comment, as
// `pvrt export-pov` writes it. Apart from exportPov() so that the SDL, and its hash in
// reference/manifest.tsv, do not depend on the file's name or the AA depth asked for.
std::string withRecipe(const std::string& sdl, const SceneDesc& scene, const PovRecipe& recipe);

// The POV-Ray command line that renders an export the way pvrt's `pov` sampler does
// (`+A0.0 +AM1 +Rn -J`, or `-A` for one sample per pixel); with `aa`, POV-Ray's adaptive
// antialiasing as `--aa-threshold`, `--aa-method` and `--aa-block` ask for it
// (`+A0.3 +AM2 +R3 -J`, and `+BSb` when the block is not POV-Ray's default 32).
std::string povCommandLine(const std::string& pov, const std::string& png, int width, int height, int aaDepth,
                           const AdaptiveSettings& aa = {});

}  // namespace pvrt
