// The primitives of a built scene, held compactly. Nearly every primitive of a big scene is
// an untransformed sphere, which a 48-byte record describes whole; a 208-byte Primitive
// for each of a million spheres would be most of the scene's memory. So every primitive has
// a record (what traversal, shadow tests and shading read), and only the other shapes (a
// transformed sphere, a box, a triangle, ...) also keep their full Primitive, which their
// record points to.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "geometry/primitive.h"

namespace pvrt {

struct PrimitiveRecord {
  enum class Kind : uint8_t { Sphere, Plane, Other };  // untransformed spheres and planes are whole here
  union {
    SphereShape sphere;  // Kind::Sphere
    PlaneShape plane;    // Kind::Plane
    uint32_t other;      // Kind::Other: its Primitive in PrimitiveStore::others
  };
  // The same as the Primitive's fields of these names.
  uint32_t material = 0;
  uint32_t object = 0;
  float unit = 1;
  Kind kind = Kind::Other;
  bool noShadow = false;
  bool opaque = true;
  // One of several primitives of its object (a mesh's triangles; set by the Bvh): POV-Ray's
  // shadow cache holds an object, so a cached mesh is tested whole (Bvh::objectHit).
  bool sharesObject = false;
  PrimitiveRecord() : sphere{} {}
};
static_assert(sizeof(PrimitiveRecord) == 48, "a record is what a big scene pays per sphere");

// The world bounds of the primitive that `r` describes (`others` holds its shape when
// r.kind is Other): empty for a plane, and the same as the Primitive's bounds().
Bounds boundsOf(const PrimitiveRecord& r, const std::vector<Primitive>& others);
// The whole Primitive that `r` describes: a copy, made again from the record for a sphere or a plane.
Primitive primitiveOf(const PrimitiveRecord& r, const std::vector<Primitive>& others);

struct PrimitiveStore {
  std::vector<PrimitiveRecord> records;  // one per primitive
  std::vector<Primitive> others;         // the Kind::Other primitives' shapes

  PrimitiveStore() = default;
  // The store of `prims`, in their order.
  explicit PrimitiveStore(std::vector<Primitive> prims);

  size_t size() const { return records.size(); }
  // The record of `p`: `p` itself goes to the end of `others` unless the record says all.
  static PrimitiveRecord compact(Primitive&& p, std::vector<Primitive>& others);
  // Primitive i whole (made again from its record for a sphere or a plane).
  Primitive primitive(size_t i) const { return primitiveOf(records[i], others); }
  Bounds bounds(size_t i) const { return boundsOf(records[i], others); }
  // Sets what record and Primitive both hold.
  void setUnit(size_t i, float unit);
};

}  // namespace pvrt
