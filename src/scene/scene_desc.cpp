#include "scene/scene_desc.h"

namespace pvrt {

Affine TransformStep::affine() const {
  switch (kind) {
    case Kind::Scale: return Affine::scale(v);
    case Kind::Rotate: return Affine::rotate(v);
    case Kind::Translate: return Affine::translate(v);
    case Kind::Matrix: return Affine::povMatrix(matrix);
  }
  return {};
}

Affine TransformList::combined() const {
  Affine a;
  for (const TransformStep& s : steps) a = a.then(s.affine());
  return a;
}

const char* shapeName(const ShapeDesc& shape) {
  static const char* names[] = {"sphere", "plane",    "box",      "cylinder", "cone",
                                "disc",   "triangle", "smooth_triangle", "mesh"};
  return names[shape.index()];
}

bool PigmentDesc::hasTransparency() const {
  if (checker)
    return checker->color1.filter > 0 || checker->color1.transmit > 0 ||
           checker->color2.filter > 0 || checker->color2.transmit > 0;
  return color.filter > 0 || color.transmit > 0;
}

}  // namespace pvrt
