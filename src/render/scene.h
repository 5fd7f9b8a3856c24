// The built scene: everything the renderer needs, immutable after buildScene() and
// shared read-only by every thread (and rebuilt identically on every MPI rank).
#pragma once

#include <cstdint>
#include <vector>

#include "accel/bvh.h"
#include "core/memory_limit.h"
#include "render/camera.h"
#include "render/effects.h"
#include "render/light.h"
#include "render/material.h"
#include "render/spawn.h"
#include "render/vista.h"
#include "scene/scene_desc.h"

namespace pvrt {

// The interiors a ray is inside, innermost last (object indices). Small and fixed so
// rays carry it by value without allocating.
struct InteriorList {
  static constexpr int kMax = 16;
  uint32_t ids[kMax];
  int count = 0;

  int find(uint32_t id) const {
    for (int i = count - 1; i >= 0; --i)
      if (ids[i] == id) return i;
    return -1;
  }
  void push(uint32_t id) {
    if (count < kMax) ids[count++] = id;
  }
  void remove(int index) {
    for (int i = index; i + 1 < count; ++i) ids[i] = ids[i + 1];
    --count;
  }
};

struct Scene {
  Camera camera;
  GlobalSettings globals;
  Color background;
  MaterialTable materials;  // one per object, indexed by Primitive::material
  std::vector<Light> lights;
  Bvh bvh;
  // Per light, its light buffer: for the point lights that cast shadows, when the scene has
  // shadows; an empty one (resolution() 1, no cells) otherwise.
  std::vector<LightBuffer> lightBuffers;
  double lightBufferSeconds = 0;
  // The memory limit the acceleration structures were built under (BuildOptions; the BVH's
  // bytes and the light buffers' budget when that was smaller), and how many lights that
  // would have had a buffer went without, to stay within it.
  size_t memoryLimit = SIZE_MAX;
  bool memoryLimitScaled = false;  // memoryLimit is the BVH's bytes and lightBufferBudget()
  size_t lightsOverMemoryLimit = 0;
  // Whether the buffers are too big for the caches, so that shading should start fetching
  // a point's cells for all lights at once (it costs more than it saves on small ones).
  bool prefetchLightBuffers = false;
  // Whether the shadow segments of a packet (the samples of a pixel or of a few) are
  // answered one by one from the light buffers instead of together by one walk of the tree:
  // in a scene of many primitives the walk goes deep (see kPacketShadowsFromBuffers in
  // scene.cpp).
  bool packetShadowsFromBuffers = false;
  InteriorList cameraInteriors;  // objects whose inside contains the camera
  Vista vista;                   // which camera rays surely meet nothing (render/vista.h)
  EffectSet effects = 0;         // kernel effects (supersampling is added per render)
  RayTolerances tol;             // minimum depths and maximum distance, in the scene's unit
};

struct BuildOptions {
  // Bytes the BVH and the light buffers may take together (core/memory_limit.h): the BVH is
  // always built, with leaves of up to 16, 64 or 255 primitives instead of 4 when the usual
  // tree would not fit (far fewer nodes; the same image bits, slower rays); the light buffers
  // take what it leaves, in light order, and the lights beyond it get none (their shadow
  // segments walk the BVH: the same image bits).
  size_t memoryLimit = defaultMemoryLimit();
  // Whether memoryLimit was chosen by the user (`--memory-limit`). When it was not, the light
  // buffers also take at most a share of memory that grows with the scene (see
  // lightBufferBudget), not with the scene times its lights.
  bool memoryLimitGiven = false;
};

// The bytes the light buffers may take by default beside a BVH of `bvhBytes` (with the
// occluders' copy): kLightBufferShare times as much, and at least kLightBufferFloor.
// 10^5 spheres under 1000 lights took 156 s and 4.9 GB to build a buffer for every light;
// with this, about a dozen of them get one, built in about a second, and the others' shadow
// segments walk the BVH (the same image).
inline constexpr size_t kLightBufferShare = 4;
inline constexpr size_t kLightBufferFloor = size_t(64) << 20;
inline size_t lightBufferBudget(size_t bvhBytes) {
  return bvhBytes > kLightBufferFloor / kLightBufferShare ? kLightBufferShare * bvhBytes : kLightBufferFloor;
}

// Both throw interrupt::error() when a signal is caught (core/interrupt.h) while building.
Scene buildScene(const SceneDesc& desc, const BuildOptions& options = {});
// The same scene, with desc.objects freed as soon as the primitives and materials are made
// from them, before the BVH and the light buffers are built: a scene of a million objects
// then never holds both its descriptions (0.7 GB) and its acceleration structures. The
// rest of desc is left as it was.
Scene buildScene(SceneDesc&& desc, const BuildOptions& options = {});
// Builds scene.lightBuffers for its lights and primitives (buildScene does it), within
// memoryLimit less the BVH's bytes, and with `scaled`, within lightBufferBudget() too.
void buildLightBuffers(Scene& scene, size_t memoryLimit = SIZE_MAX, bool scaled = false);

}  // namespace pvrt
