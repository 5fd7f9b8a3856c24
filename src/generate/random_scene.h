// The paper's random scenes (section 2): N spheres and L point lights placed in given
// boxes from a seed, with materials drawn from a small palette. The generator uses a
// portable 64-bit LCG so a seed gives the same scene on every machine and compiler.
#pragma once

#include <cstdint>

#include "scene/scene_desc.h"

namespace pvrt {

// Relative weights of the material kinds a sphere may get.
struct Palette {
  double matte = 0.5;   // diffuse only
  double shiny = 0.3;   // diffuse with a phong highlight
  double mirror = 0.1;  // mostly reflective
  double glass = 0.1;   // filtering, refracting (ior 1.5)
};

struct GenerateOptions {
  int spheres = 100;
  int lights = 5;
  uint64_t seed = 1;
  Vec3 sphereBoxLo{-8, 0, -4}, sphereBoxHi{8, 6, 12};  // sphere centres
  double radiusMin = 0.2, radiusMax = 0.8;
  Vec3 lightBoxLo{-12, 8, -12}, lightBoxHi{12, 16, 4};
  bool floor = true;  // a checkered plane y = 0 under the spheres
  Palette palette;
  int width = 1280, height = 800;  // stored in the scene's <image>
};

SceneDesc generateScene(const GenerateOptions& options);

// The factor on the default radii that keeps N spheres' total volume that of the paper's
// 100 in the same box: (100 / N)^(1/3), and 1 up to 100 spheres. With the paper's radii
// unscaled, 10^6 spheres would fill the box hundreds of spheres deep.
double radiusScaleFor(int spheres);

// Paper scene 1: 100 spheres and 5 lights, load spread over the whole image.
GenerateOptions paperScene1();
// Paper scene 2: 20 spheres and 5 lights, load concentrated in the upper-right quarter.
GenerateOptions paperScene2();

}  // namespace pvrt
