#include "render/material.h"

#include <cmath>
#include <functional>

#include "geometry/primitive.h"

namespace pvrt {

namespace {

// A hash of the fields that most often tell surfaces apart; equal surfaces hash equal,
// and operator== settles the rest.
size_t hashOf(const Surface& s) {
  size_t h = 0;
  for (double v : {s.finish.diffuse, s.finish.phong, s.finish.specular, s.finish.reflection.max.r,
                   s.finish.ambient.r, s.interior.ior})
    h = h * 1000003u ^ std::hash<double>{}(v);
  return h;
}

}  // namespace

void MaterialTable::add(const MaterialDesc& desc, const Affine& objectToWorld) {
  Material m;
  const PigmentDesc& pd = desc.pigment;
  if (pd.checker) {
    m.color = pd.checker->color1;
    Checker c{pd.checker->color2, std::nullopt};
    const Affine toWorld = pd.transforms.combined().then(objectToWorld);
    if (!toWorld.isIdentity()) c.worldToPattern = toWorld.inverse();
    m.checker = int32_t(checkers_.size());
    checkers_.push_back(c);
  } else {
    m.color = pd.color;
  }
  auto clear = [](const FilterColor& c) { return c.filter == 0 && c.transmit == 0; };
  m.opaque = clear(m.color) && (m.checker < 0 || clear(checkers_.back().color2));

  Surface s;
  s.finish = desc.finish;
  s.interior = desc.interior;
  s.finish.loc = s.interior.loc = {};  // where it was written does not change how it shades
  s.specularExponent = 1.0 / desc.finish.roughness;
  s.reflective = !desc.finish.reflection.isZero();
  s.highlights = desc.finish.phong > 0 || desc.finish.specular > 0;
  const size_t h = hashOf(s);
  const auto [first, last] = surfaceIndex_.equal_range(h);
  auto found = first;
  while (found != last && !(surfaces_[found->second] == s)) ++found;
  if (found != last) {
    m.surface = found->second;
  } else {
    m.surface = uint32_t(surfaces_.size());
    surfaces_.push_back(s);
    surfaceIndex_.emplace(h, m.surface);
  }
  materials_.push_back(m);
}

FilterColor MaterialTable::checkerAt(const Material& m, const Vec3& worldPoint) const {
  const Checker& c = checkers_[size_t(m.checker)];
  const Vec3 p = c.worldToPattern ? c.worldToPattern->applyPoint(worldPoint) : worldPoint;
  // POV-Ray nudges each coordinate by +1e-10 so that points a rounding error below an
  // integer plane still fall in the upper cell.
  const double k = std::floor(p.x + kPovEpsilon) + std::floor(p.y + kPovEpsilon) +
                   std::floor(p.z + kPovEpsilon);
  // k is a whole number: even when half of it is whole too (fmod(|k|, 2) == 0, without
  // the library call; an infinite or NaN k gives color2, as fmod's NaN does).
  const double half = std::fabs(k) * 0.5;
  return std::isfinite(half) && half == std::floor(half) ? m.color : c.color2;
}

}  // namespace pvrt
