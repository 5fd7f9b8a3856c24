#include "render/material.h"

#include <cmath>
#include <functional>

#include "core/interrupt.h"
#include "core/single.h"
#include "core/prefault.h"
#include "geometry/primitive.h"
#include "parallel/parallel_for.h"

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

// POV-Ray 3.7 stores pigments, finishes and interiors in single precision (SNGL fields
// and float colours, frame.h): every value it reads passes through a float, and so does
// each here (core/single.h), so that the arithmetic starts from the same numbers (an ior
// of 1.33 refracts as 1.3300000429153442). docs/fidelity.md lists the fields.
using pvrt::single;
FinishDesc single(FinishDesc f) {
  f.ambient = single(f.ambient);
  f.emission = single(f.emission);
  for (double* v : {&f.diffuse, &f.brilliance, &f.phong, &f.phongSize, &f.specular, &f.roughness, &f.metallic,
                    &f.reflection.falloff, &f.reflection.exponent, &f.reflection.metallic})
    *v = single(*v);
  f.reflection.min = single(f.reflection.min);
  f.reflection.max = single(f.reflection.max);
  return f;
}

InteriorDesc single(InteriorDesc in) {
  in.ior = single(in.ior);
  // POV-Ray's Post_Process: an interior whose (float) IOR is 0 takes the atmosphere's, 1; a
  // positive ior below the float range (1e-46) is such a one.
  if (in.ior == 0) in.ior = 1;
  in.fadeDistance = single(in.fadeDistance);
  in.fadePower = single(in.fadePower);
  in.fadeColor = single(in.fadeColor);
  return in;
}

}  // namespace

namespace {

// What add() makes of an object's material before its surface is looked up among the
// table's and its checker (if any) given its index.
struct Made {
  Material material;
  Surface surface;
  std::optional<Checker> checker;
};

Made make(const MaterialDesc& desc, const Affine& objectToWorld) {
  Made made;
  Material& m = made.material;
  const PigmentDesc& pd = desc.pigment;
  if (pd.checker) {
    m.color = single(pd.checker->color1);
    made.checker = Checker{single(pd.checker->color2), std::nullopt};
    const Affine toWorld = pd.transforms.combined().then(objectToWorld);
    if (!toWorld.isIdentity()) made.checker->worldToPattern = toWorld.inverse();
  } else {
    m.color = single(pd.color);
  }
  auto clear = [](const FilterColor& c) { return c.filter == 0 && c.transmit == 0; };
  m.opaque = clear(m.color) && (!made.checker || clear(made.checker->color2));

  Surface& s = made.surface;
  s.finish = single(*desc.finish);
  s.interior = single(*desc.interior);
  s.specularExponent = single(1.0 / s.finish.roughness);  // Parse_Finish stores 1/roughness as a float
  s.reflective = !desc.finish->reflection.isZero();
  s.highlights = desc.finish->phong > 0 || desc.finish->specular > 0;
  return made;
}

// The index of `s` among `surfaces` (indexed by `index`), added at the end if it is new.
uint32_t surfaceIndex(const Surface& s, std::vector<Surface>& surfaces,
                      std::unordered_multimap<size_t, uint32_t>& index) {
  const size_t h = hashOf(s);
  const auto [first, last] = index.equal_range(h);
  for (auto found = first; found != last; ++found)
    if (surfaces[found->second] == s) return found->second;
  surfaces.push_back(s);
  index.emplace(h, uint32_t(surfaces.size() - 1));
  return uint32_t(surfaces.size() - 1);
}

}  // namespace

void MaterialTable::add(const MaterialDesc& desc, const Affine& objectToWorld) {
  Made made = make(desc, objectToWorld);
  if (made.checker) {
    made.material.checker = int32_t(checkers_.size());
    checkers_.push_back(std::move(*made.checker));
  }
  made.material.surface = surfaceIndex(made.surface, surfaces_, surfaceIndex_);
  materials_.push_back(made.material);
}

void MaterialTable::addObjects(std::span<const ObjectDesc> objects, int threads) {
  // A block of objects at a time, each block with surfaces and checkers of its own, in the
  // order it meets them; those then join the table's block by block, which puts each where
  // add() would have.
  if ((threads > 0 ? threads : threadBudget()) <= 1) {
    materials_.reserve(materials_.size() + objects.size());
    for (size_t i = 0; i < objects.size(); ++i) {
      if ((i & 4095) == 0 && interrupt::requested()) return;  // the caller checks
      add(objects[i].material, objects[i].transforms.combined());
    }
    return;
  }
  const size_t before = materials_.size();
  resizePrefaulted(materials_, before + objects.size(), threads);
  struct Part {
    std::vector<Surface> surfaces;
    std::vector<Checker> checkers;
  };
  const Blocks blocks(objects.size(), threads, 1024);
  std::vector<Part> parts(blocks.count);
  parallelBlocks(blocks, threads, [&](size_t b, size_t lo, size_t hi) {
    Part& part = parts[b];
    std::unordered_multimap<size_t, uint32_t> index;
    for (size_t i = lo; i < hi; ++i) {
      if ((i & 4095) == 0 && interrupt::requested()) return;  // the caller checks
      Made made = make(objects[i].material, objects[i].transforms.combined());
      if (made.checker) {
        made.material.checker = int32_t(part.checkers.size());
        part.checkers.push_back(std::move(*made.checker));
      }
      made.material.surface = surfaceIndex(made.surface, part.surfaces, index);
      materials_[before + i] = made.material;
    }
  });
  std::vector<std::vector<uint32_t>> surfaceOf(blocks.count);  // a block's surface's index in the table
  std::vector<int32_t> firstChecker(blocks.count);
  for (size_t b = 0; b < blocks.count; ++b) {
    for (const Surface& s : parts[b].surfaces) surfaceOf[b].push_back(surfaceIndex(s, surfaces_, surfaceIndex_));
    firstChecker[b] = int32_t(checkers_.size());
    checkers_.insert(checkers_.end(), parts[b].checkers.begin(), parts[b].checkers.end());
  }
  parallelBlocks(blocks, threads, [&](size_t b, size_t lo, size_t hi) {
    for (size_t i = lo; i < hi; ++i) {
      Material& m = materials_[before + i];
      m.surface = surfaceOf[b][m.surface];
      if (m.checker >= 0) m.checker += firstChecker[b];
    }
  });
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
