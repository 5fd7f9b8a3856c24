// POV-Ray 3.7 keeps colours, finishes, interiors, light colours and mesh data in single
// precision; pvrt keeps doubles but rounds each such value through a float where POV-Ray
// stores it (docs/fidelity.md), so that its arithmetic starts from POV-Ray's numbers.
#pragma once

#include "core/color.h"
#include "core/vec3.h"

namespace pvrt {

// v rounded to the nearest float. The empty asm makes the float a value the optimiser
// cannot see through: GCC 12's SLP vectoriser, with -march=x86-64-v3, turns two or four
// roundings of neighbouring doubles (a colour's r and g, an interior's ior and fades) into a
// plain vector copy and the rounding is lost (1.33 stayed 1.33 instead of
// 1.3300000429153442; docs/fidelity.md, tests/unit/single_test.cpp).
inline double single(double v) {
#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
  float f = float(v);
  asm("" : "+x"(f));
#else
  volatile float f = float(v);
#endif
  return double(f);
}
inline Color single(const Color& c) { return {single(c.r), single(c.g), single(c.b)}; }
inline FilterColor single(const FilterColor& c) { return {single(c.rgb), single(c.filter), single(c.transmit)}; }
inline Vec3 single(const Vec3& v) { return {single(v.x), single(v.y), single(v.z)}; }

}  // namespace pvrt
