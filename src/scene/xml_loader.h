// Reads pvrt's XML scene format (docs/scene-format.md) into a SceneDesc.
// Every problem is reported as one line, `file:line: error: element: what is wrong`, through
// pvrt::Error with ExitCode::SceneError; nothing is half-loaded.
#pragma once

#include <cstddef>
#include <string>

#include "scene/scene_desc.h"

namespace pvrt {

struct LoadOptions {
  // Files larger than this are parsed in pieces of at most this size (scene/xml_split.h),
  // smaller when many threads read them (threadBudget()), instead of as one tree. Every
  // thread parses and reads pieces; the scene and the errors are the same either way, and
  // for any number of threads.
  size_t pieceBytes = size_t(4) << 20;
  // When set, receives how many pieces were read (0: the file was parsed whole).
  size_t* piecesRead = nullptr;
};

SceneDesc loadSceneFile(const std::string& path, const LoadOptions& options = {});
// `name` stands for the file name in messages.
SceneDesc loadSceneString(const std::string& xml, const std::string& name = "<string>",
                          const LoadOptions& options = {});

}  // namespace pvrt
