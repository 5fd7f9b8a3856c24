// Reads pvrt's XML scene format (docs/scene-format.md) into a SceneDesc.
// Every problem is reported as one line, `file:line: error: element: what is wrong`, through
// pvrt::Error with ExitCode::SceneError; nothing is half-loaded.
#pragma once

#include <string>

#include "scene/scene_desc.h"

namespace pvrt {

SceneDesc loadSceneFile(const std::string& path);
// `name` stands for the file name in messages.
SceneDesc loadSceneString(const std::string& xml, const std::string& name = "<string>");

}  // namespace pvrt
