// The effects a scene calls for. Derived once from the built scene; the renderer runs a
// kernel compiled for the set's ray-making effects, so a scene without mirrors has no
// reflection code in its kernel at all (and its counters prove it).
#pragma once

#include <cstdint>
#include <string>

namespace pvrt {

enum Effect : uint32_t {
  // The kernel is specialised on these: they decide which rays exist at all.
  kShadows = 1u << 0,       // at least one light that casts shadows
  kReflection = 1u << 1,    // a finish with reflection
  kTransmission = 1u << 2,  // a pigment with filter or transmit (refraction when ior != 1)
  kHighlights = 1u << 3,    // phong or specular lit by a shadow-casting light
  kAreaLights = 1u << 4,    // an area light with more than one sample
  kKernelEffects = (1u << 5) - 1,  // the bits a kernel is specialised on (32 kernels)
  // Shading branches the tracer takes at run time (one predictable test each): specialising
  // on them as well measured no faster and made four times the kernels to compile.
  kLightShaping = 1u << 5,  // spotlight cones or distance fade
  kTextures = 1u << 6,      // patterned pigments (checker)
  kSupersampling = 1u << 7,  // more than one sample per pixel (pixel loop, not kernel)
};

using EffectSet = uint32_t;

// "shadows reflection ..." in bit order, or "none".
std::string effectNames(EffectSet effects);

}  // namespace pvrt
