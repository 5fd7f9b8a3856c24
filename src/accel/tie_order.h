// Which of two objects POV-Ray keeps when a ray meets both at exactly the same depth. Its
// trace keeps the first hit it finds and replaces it only by a strictly nearer one, so the
// order it tests objects in decides: with fewer than Bounding_Threshold (3) objects and
// lights it walks them in declaration order; from there on its bounding tree pops boxes in
// order of the float depth where the ray enters them (geometry/pov_bbox.h), so the object
// whose box the ray enters first wins. Equal keys fall to the tree's heap, which pvrt does
// not reproduce: those ties, and those of objects whose POV-Ray box pvrt does not know,
// keep whichever hit pvrt's own walk found first (docs/fidelity.md).
#pragma once

#include <cstddef>
#include <cstdint>

namespace pvrt {

enum class TieRule : uint8_t {
  FirstFound,   // no rule: the hit found first is kept (a tree built without a scene)
  Declaration,  // the object declared first
  BoxEntry,     // the object whose POV-Ray box the ray enters first
};

// POV-Ray's rule for a scene of this many objects and lights (both count against
// Bounding_Threshold: its parser links every light into the frame's objects).
inline TieRule povTieRule(size_t objectsAndLights) {
  constexpr size_t kBoundingThreshold = 3;  // POV-Ray's default
  return objectsAndLights < kBoundingThreshold ? TieRule::Declaration : TieRule::BoxEntry;
}

}  // namespace pvrt
