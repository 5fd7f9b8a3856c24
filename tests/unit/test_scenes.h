// Small helpers shared by the tests: load inline XML and render it with the library.
#pragma once

#include <string>

#include "render/renderer.h"
#include "scene/xml_loader.h"

namespace pvrt::test {

inline RenderResult renderXml(const std::string& xml, RenderSettings s = {}) {
  const Scene scene = buildScene(loadSceneString(xml, "test.xml"));
  return render(scene, s);
}

inline RenderSettings settings(int w, int h, Backend b = Backend::Serial, int threads = 1) {
  RenderSettings s;
  s.width = w;
  s.height = h;
  s.backend = b;
  s.threads = threads;
  return s;
}

}  // namespace pvrt::test
