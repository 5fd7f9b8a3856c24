// The analytic answer of every hard case, pixel by pixel, worked out in long double from
// the scene as written (the sweep is a similarity, so the image does not change with it).
// Camera rays come from the library's Camera (POV-Ray's pinhole model, checked on its own
// in camera_test.cpp); everything after the camera ray is independent of the renderer.
#pragma once

#include "oracle.h"
#include "render/scene.h"
#include "scene/scene_desc.h"

namespace pvrt::hard {

struct CaseInput {
  const SceneDesc& scene;  // as written: the oracle's coordinates
  double shadowTolerance;  // the renderer's, in those coordinates
  double maxDistance;      // likewise
  int width, height;
};

// Scenes of at most one sphere, one plane (more of either: the first one) and one point
// light, with ambient, emission and diffuse finishes: hit, normal, shadow, colour.
ExpectedImage spheresAndPlanes(const CaseInput& in);
// Seen from inside a glass slab (a box of ior n, transmit 1) against a white background:
// white within the critical angle of the slab's normal, black beyond it.
ExpectedImage tirSlab(const CaseInput& in);
// Likewise inside a glass sphere: white when the ray's line passes within r / n of the centre.
ExpectedImage tirSphere(const CaseInput& in);
// Two facing mirror planes and max_trace_level N: N times the ambient colour everywhere.
ExpectedImage facingMirrors(const CaseInput& in);
// The octahedron |x| + |y| + |z| = 1 (ambient 1): white inside its outline.
ExpectedImage octahedron(const CaseInput& in);
// The unit square in z = 0 lit by the scene's light (diffuse 1): n.l inside it.
ExpectedImage unitSquare(const CaseInput& in);
// Two identical planes, two identical spheres and a disc in the plane (ambient 1):
// the colour the documented tie-break gives (docs/robustness.md). Pixels where the disc
// lies in the plane are marked skip; coplanarDisc() classifies them.
ExpectedImage coplanar(const CaseInput& in);
struct DiscTies {
  long pixels = 0, disc = 0, plane = 0, other = 0;
};
DiscTies coplanarDisc(const CaseInput& in, const Image& got);

}  // namespace pvrt::hard
