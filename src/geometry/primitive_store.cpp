#include "geometry/primitive_store.h"

#include <variant>

namespace pvrt {

PrimitiveStore::PrimitiveStore(std::vector<Primitive> prims) {
  records.reserve(prims.size());
  for (Primitive& p : prims) records.push_back(compact(std::move(p), others));
}

PrimitiveRecord PrimitiveStore::compact(Primitive&& p, std::vector<Primitive>& others) {
  PrimitiveRecord r;
  r.material = p.material;
  r.object = p.object;
  r.unit = p.unit;
  r.noShadow = p.noShadow;
  r.opaque = p.opaque;
  if (const SphereShape* s = p.transform ? nullptr : std::get_if<SphereShape>(&p.shape)) {
    r.sphere = *s;
    r.kind = PrimitiveRecord::Kind::Sphere;
  } else if (const PlaneShape* s = p.transform ? nullptr : std::get_if<PlaneShape>(&p.shape)) {
    r.plane = *s;
    r.kind = PrimitiveRecord::Kind::Plane;
  } else {
    r.other = uint32_t(others.size());
    if (!p.povBoxKnown) p.povBox = povBBoxOf(p);  // a mesh's triangles come with the mesh's (render/scene.cpp)
    p.povBoxKnown = true;
    others.push_back(std::move(p));
  }
  return r;
}

Primitive primitiveOf(const PrimitiveRecord& r, const std::vector<Primitive>& others) {
  switch (r.kind) {
    case PrimitiveRecord::Kind::Sphere:
      return {r.sphere, nullptr, r.material, r.object, r.noShadow, r.opaque, r.unit, false, std::nullopt};
    case PrimitiveRecord::Kind::Plane:
      return {r.plane, nullptr, r.material, r.object, r.noShadow, r.opaque, r.unit, false, std::nullopt};
    case PrimitiveRecord::Kind::Other:
      break;
  }
  return others[r.other];
}

Bounds boundsOf(const PrimitiveRecord& r, const std::vector<Primitive>& others) {
  switch (r.kind) {
    case PrimitiveRecord::Kind::Sphere:  // as Primitive::bounds() has it
      return {r.sphere.center - Vec3(r.sphere.radius), r.sphere.center + Vec3(r.sphere.radius)};
    case PrimitiveRecord::Kind::Plane:
      return {};
    case PrimitiveRecord::Kind::Other:
      break;
  }
  return others[r.other].bounds();
}

void PrimitiveStore::setUnit(size_t i, float unit) {
  PrimitiveRecord& r = records[i];
  r.unit = unit;
  if (r.kind == PrimitiveRecord::Kind::Other) others[r.other].unit = unit;
}

}  // namespace pvrt
