// POV-Ray 3.7's highlight formulas (shared/povray-semantics.md section 3), as small pure
// functions so they can be tested one by one; the reflectivity, filter and fade of lit rays are
// POV-Ray's float colour operations (render/pov_secondary.h).
#pragma once

#include <cmath>

#include "core/color.h"
#include "core/vec3.h"
#include "scene/scene_desc.h"

namespace pvrt::shading {

// Phong highlight strength for unit view direction d, flipped normal n, unit light dir l.
inline double phong(const FinishDesc& f, const Vec3& d, const Vec3& n, const Vec3& l) {
  const Vec3 r = d - n * (2.0 * dot(d, n));
  const double c = dot(r, l);
  if (c <= 0) return 0.0;
  if (f.phongSize >= 60 && c <= 0.0008) return 0.0;  // POV-Ray's underflow guard
  return f.phong * std::pow(c, f.phongSize);
}

// Blinn specular highlight; `exponent` is 1/roughness.
inline double specular(const FinishDesc& f, double exponent, const Vec3& d, const Vec3& n,
                       const Vec3& l) {
  const Vec3 h = (l - d) * 0.5;
  const double hl = length(h);
  if (hl == 0) return 0.0;
  const double c = dot(h, n) / hl;
  if (c <= 0) return 0.0;
  return f.specular * std::pow(c, exponent);
}

// Interior fade after travelling `d` inside the object, in double: the shadow rays' (their
// light is still multiplied in double; render/pov_secondary.h has the float form of lit rays).
inline Color interiorFade(const InteriorDesc& in, double d) {
  if (in.fadePower >= 1000) {
    const double k = d / in.fadeDistance;
    return {std::exp(-(1.0 - in.fadeColor.r) * k), std::exp(-(1.0 - in.fadeColor.g) * k),
            std::exp(-(1.0 - in.fadeColor.b) * k)};
  }
  const double s = 1.0 / (1.0 + std::pow(d / in.fadeDistance, in.fadePower));
  return {in.fadeColor.r + (1.0 - in.fadeColor.r) * s, in.fadeColor.g + (1.0 - in.fadeColor.g) * s,
          in.fadeColor.b + (1.0 - in.fadeColor.b) * s};
}

}  // namespace pvrt::shading
