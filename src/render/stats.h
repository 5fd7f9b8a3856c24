// Counters of the work a render did, like POV-Ray's render statistics. Each thread
// counts into its own copy; copies are summed after the render.
#pragma once

#include <cstdint>

namespace pvrt {

struct RenderStats {
  uint64_t primaryRays = 0;
  uint64_t shadowRays = 0;       // one per light test (per area-light sample)
  uint64_t reflectedRays = 0;    // mirror rays, including total internal reflection
  uint64_t refractedRays = 0;    // transmitted rays that bend (ior != 1)
  uint64_t transmittedRays = 0;  // transmitted rays that go straight on (ior == 1)
  uint64_t intersectionTests = 0;
  uint64_t shadingOps = 0;       // surface hits shaded (one per hit, lights included)
  // The NaN census: camera samples whose colour was not finite and pixels that had one
  // (a NaN channel written as 0, as POV-Ray writes it), or whose value overflowed a float
  // (written as +-FLT_MAX).
  uint64_t nonFiniteSamples = 0;
  uint64_t nonFinitePixels = 0;
  // Camera rays (counted in primaryRays too) that the vista found to meet nothing, so that
  // they were given the background without being made or traced (render/vista.h).
  uint64_t vistaRays = 0;

  uint64_t totalRays() const {
    return primaryRays + shadowRays + reflectedRays + refractedRays + transmittedRays;
  }
  // The deterministic work measure of the load map: rays traced, intersection tests and
  // shading operations (a pixel of empty background still costs its camera rays).
  uint64_t work() const { return totalRays() + intersectionTests + shadingOps; }

  RenderStats& operator+=(const RenderStats& o) {
    primaryRays += o.primaryRays;
    shadowRays += o.shadowRays;
    reflectedRays += o.reflectedRays;
    refractedRays += o.refractedRays;
    transmittedRays += o.transmittedRays;
    intersectionTests += o.intersectionTests;
    shadingOps += o.shadingOps;
    nonFiniteSamples += o.nonFiniteSamples;
    nonFinitePixels += o.nonFinitePixels;
    vistaRays += o.vistaRays;
    return *this;
  }
};

}  // namespace pvrt
