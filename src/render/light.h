// Light sources after the build stage, with POV-Ray's attenuation (spotlight cone and
// distance fade) and the sample grid of regular area lights.
#pragma once

#include <vector>

#include "scene/scene_desc.h"

namespace pvrt {

struct Light {
  Vec3 location;
  Color color;
  bool shadowless = false;

  bool spot = false;
  Vec3 spotAxis;            // unit, from the light toward point_at
  double cosRadius = 1, cosFalloff = 1, tightness = 0;

  double fadeDistance = 0, fadePower = 0;

  bool area = false;
  Vec3 axis1, axis2;
  int size1 = 1, size2 = 1, adaptive = 100;
  bool circular = false, orient = false;

  // Spotlight and fade factor for a point seen along unit `toLight` at `dist`.
  double attenuation(const Vec3& toLight, double dist) const;
  // World position of area-light sample (i, j); `toLight` is the unit direction from the
  // shaded point to the light centre (used by `orient`).
  Vec3 areaSample(int i, int j, const Vec3& toLight) const;
  // areaSample(i, j) at [j * size1 + i] when it does not depend on the point (no `orient`)
  // and the grid is small enough to keep; else empty.
  std::vector<Vec3> grid;
};

Light buildLight(const LightDesc& desc);

}  // namespace pvrt
