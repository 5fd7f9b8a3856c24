// A ray with a (not necessarily unit) direction; t measures multiples of |dir|.
#pragma once

#include "core/vec3.h"

namespace pvrt {

struct Ray {
  Vec3 origin;
  Vec3 dir;
  Vec3 at(double t) const { return origin + dir * t; }
};

}  // namespace pvrt
