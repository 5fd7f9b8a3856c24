// Writes a SceneDesc back as pvrt XML that loads to an equal SceneDesc (numbers are
// printed so they read back exactly). Used by `pvrt generate` and `--save-scene`.
#pragma once

#include <string>

#include "scene/scene_desc.h"

namespace pvrt {

std::string sceneToXml(const SceneDesc& scene);

}  // namespace pvrt
