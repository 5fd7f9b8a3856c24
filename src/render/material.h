// Materials ready for shading: a pigment that can be evaluated at a world point, the
// finish with its derived constants, and the interior.
#pragma once

#include <optional>

#include "core/transform.h"
#include "scene/scene_desc.h"

namespace pvrt {

struct Pigment {
  FilterColor color;                   // solid colour, or the checker's first colour
  FilterColor color2;                  // the checker's second colour
  bool checker = false;
  std::optional<Affine> worldToPattern;  // inverse of (pigment transforms, then object's)

  FilterColor at(const Vec3& worldPoint) const;
};

struct Material {
  Pigment pigment;
  FinishDesc finish;
  InteriorDesc interior;
  double specularExponent = 20;  // 1/roughness, as POV-Ray stores it
  bool opaque = true;            // no filter or transmit anywhere in the pigment
  bool reflective = false;
  bool highlights = false;
};

Material buildMaterial(const MaterialDesc& desc, const Affine& objectToWorld);

}  // namespace pvrt
