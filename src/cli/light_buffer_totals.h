// What a scene's valid light buffers hold together, as --stats and --stats-json report it.
#pragma once

#include <algorithm>
#include <cstddef>

#include "render/scene.h"

namespace pvrt {

struct LightBufferTotals {
  size_t buffers = 0, entries = 0, bytes = 0;
  int cells = 0;  // the most cells a side of any buffer's faces
};

inline LightBufferTotals lightBufferTotals(const Scene& scene) {
  LightBufferTotals t;
  for (const LightBuffer& lb : scene.lightBuffers) {
    if (!lb.valid()) continue;
    ++t.buffers;
    t.entries += lb.entries();
    t.bytes += lb.bytes();
    t.cells = std::max(t.cells, lb.resolution());
  }
  return t;
}

}  // namespace pvrt
