// Materials ready for shading. A scene has few finishes and interiors but, in a generated
// scene, a pigment per object; so each object gets a one-cache-line Material (its colour
// and where the rest is), and objects with equal finishes and interiors share one Surface.
// A million objects' materials are read in random order: one cache miss each, while the
// handful of Surfaces stay in cache.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <unordered_map>
#include <vector>

#include "core/transform.h"
#include "scene/scene_desc.h"

namespace pvrt {

// How a surface takes light: its finish and interior, with the constants derived from them.
struct Surface {
  FinishDesc finish;
  InteriorDesc interior;
  double specularExponent = 20;  // 1/roughness, as POV-Ray stores it
  bool reflective = false;
  bool highlights = false;
  bool operator==(const Surface&) const = default;
};

// A checker pigment's second colour and the map from world to pattern space (none for
// the identity); its first colour is the Material's.
struct Checker {
  FilterColor color2;
  std::optional<Affine> worldToPattern;
};

// What shading reads of one object.
struct alignas(64) Material {
  FilterColor color;     // the solid colour, or the checker's first colour
  uint32_t surface = 0;  // into MaterialTable::surface()
  int32_t checker = -1;  // into MaterialTable's checkers; -1 for a solid colour
  bool opaque = true;    // no filter or transmit anywhere in the pigment
};
static_assert(sizeof(Material) == 64);

class MaterialTable {
 public:
  // Adds the material of the next object; its index is the number added before.
  void add(const MaterialDesc& desc, const Affine& objectToWorld);
  // add() for each object's material in turn, on up to `threads` threads (0: threadBudget()):
  // the same table. A signal stops it part way (core/interrupt.h): callers check after it.
  void addObjects(std::span<const ObjectDesc> objects, int threads = 0);
  void reserve(size_t objects) { materials_.reserve(objects); }

  size_t size() const { return materials_.size(); }
  bool empty() const { return materials_.empty(); }
  const Material& operator[](size_t object) const { return materials_[object]; }
  const Surface& surface(const Material& m) const { return surfaces_[m.surface]; }
  const std::vector<Surface>& surfaces() const { return surfaces_; }
  bool anyChecker() const { return !checkers_.empty(); }
  const Checker& checker(const Material& m) const { return checkers_[size_t(m.checker)]; }

  // The pigment's colour at a world point.
  FilterColor pigmentAt(const Material& m, const Vec3& worldPoint) const {
    return m.checker < 0 ? m.color : checkerAt(m, worldPoint);
  }

 private:
  FilterColor checkerAt(const Material& m, const Vec3& worldPoint) const;

  std::vector<Material> materials_;
  std::vector<Surface> surfaces_;
  std::vector<Checker> checkers_;
  std::unordered_multimap<size_t, uint32_t> surfaceIndex_;  // a few fields' hash -> surfaces
};

}  // namespace pvrt
