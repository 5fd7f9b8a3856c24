#include "render/material.h"

#include <cmath>

#include "geometry/primitive.h"

namespace pvrt {

FilterColor Pigment::at(const Vec3& worldPoint) const {
  if (!checker) return color;
  const Vec3 p = worldToPattern ? worldToPattern->applyPoint(worldPoint) : worldPoint;
  // POV-Ray nudges each coordinate by +1e-10 so that points a rounding error below an
  // integer plane still fall in the upper cell.
  const double k = std::floor(p.x + kPovEpsilon) + std::floor(p.y + kPovEpsilon) +
                   std::floor(p.z + kPovEpsilon);
  // k is a whole number: even when half of it is whole too (fmod(|k|, 2) == 0, without
  // the library call; an infinite or NaN k gives color2, as fmod's NaN does).
  const double half = std::fabs(k) * 0.5;
  return std::isfinite(half) && half == std::floor(half) ? color : color2;
}

Material buildMaterial(const MaterialDesc& desc, const Affine& objectToWorld) {
  Material m;
  const PigmentDesc& pd = desc.pigment;
  if (pd.checker) {
    m.pigment.checker = true;
    m.pigment.color = pd.checker->color1;
    m.pigment.color2 = pd.checker->color2;
    const Affine toWorld = pd.transforms.combined().then(objectToWorld);
    if (!toWorld.isIdentity()) m.pigment.worldToPattern = toWorld.inverse();
  } else {
    m.pigment.color = pd.color;
    m.pigment.color2 = pd.color;
  }
  m.finish = desc.finish;
  m.interior = desc.interior;
  m.specularExponent = 1.0 / desc.finish.roughness;
  auto clear = [](const FilterColor& c) { return c.filter == 0 && c.transmit == 0; };
  m.opaque = clear(m.pigment.color) && clear(m.pigment.color2);
  m.reflective = !desc.finish.reflection.isZero();
  m.highlights = desc.finish.phong > 0 || desc.finish.specular > 0;
  return m;
}

}  // namespace pvrt
