// The scale sweep of the hard cases: every point x of a scene goes to scale * x + offset
// (the offset on all three axes). Applied to the scene description as a whole: objects
// (their pigments move with them), the camera, the lights and every length in between.
#pragma once

#include <string>

#include "scene/scene_desc.h"

namespace pvrt::hard {

struct Sweep {
  double offset = 0, scale = 1;
};

// The sweep of issue 5: (offset, scale).
inline constexpr Sweep kSweeps[] = {{0, 1}, {1e3, 1}, {0, 1e-3}, {1e4, 1e3}};

inline void appendStep(TransformList& t, TransformStep::Kind kind, const Vec3& v) {
  TransformStep step{};
  step.kind = kind;
  step.v = v;
  t.steps.push_back(step);
}

inline void appendSweep(TransformList& t, const Sweep& s) {
  if (s.scale != 1) appendStep(t, TransformStep::Kind::Scale, Vec3(s.scale));
  if (s.offset != 0) appendStep(t, TransformStep::Kind::Translate, Vec3(s.offset));
}

inline Vec3 sweepPoint(const Vec3& p, const Sweep& s) { return p * s.scale + Vec3(s.offset); }

inline SceneDesc applySweep(SceneDesc d, const Sweep& s) {
  for (ObjectDesc& o : d.objects) {
    appendSweep(o.transforms, s);
    o.material.interior.edit([&](InteriorDesc& v) { v.fadeDistance *= s.scale; });
  }
  appendSweep(d.camera.transforms, s);
  for (LightDesc& l : d.lights) {
    l.location = sweepPoint(l.location, s);
    if (l.spot) l.spot->pointAt = sweepPoint(l.spot->pointAt, s);
    if (l.area) {
      l.area->axis1 *= s.scale;
      l.area->axis2 *= s.scale;
    }
    l.fadeDistance *= s.scale;
  }
  return d;
}

}  // namespace pvrt::hard
