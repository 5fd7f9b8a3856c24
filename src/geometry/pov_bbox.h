// POV-Ray 3.7's bounding box of an object (frame.h's BBOX: a float corner and float
// lengths), as each shape's Compute_BBox makes it, and the key its bounding tree sorts a
// ray's boxes by (bbox.cpp, Check_And_Enqueue): the depth, in float arithmetic, where the
// ray enters the box. Two bounded objects that a ray meets at exactly one depth are
// decided by these keys in POV-Ray (docs/fidelity.md, "Bounded objects tying").
#pragma once

#include <optional>

#include "core/ray.h"
#include "core/transform.h"

namespace pvrt {

struct Primitive;

// How far from the origin pvrt follows POV-Ray's float boxes (the tie keys, the box test after
// a hit). Beyond, a float is coarser than a tenth of a unit (1/16 at 1e6): POV-Ray's order and
// cuts there are its rounding's, not the scene's, and pvrt keeps its own exact answer, which
// stays the same under translation (docs/robustness.md; hard.translate_base).
constexpr double kPovFloatReach = 1e6;

struct PovBBox {
  float lowerLeft[3] = {0, 0, 0};
  float lengths[3] = {0, 0, 0};
};

// Make_BBox: each value rounded to a float as it is passed.
PovBBox makePovBBox(double llx, double lly, double llz, double lex, double ley, double lez);
// Make_BBox_from_min_max with double corners: the lengths are differences of doubles.
PovBBox povBBoxFromMinMax(const Vec3& mins, const Vec3& maxs);
// Recompute_BBox: the eight corners through `toWorld` (MTransPoint's order of terms),
// their range clipped at BOUND_HUGE / 2, made a box again.
PovBBox povRecomputed(const PovBBox& box, const Affine& toWorld);

// Sphere::Compute_BBox of an untransformed sphere: the centre minus the radius, 2r.
PovBBox povSphereBBox(const Vec3& center, double radius);

// The box POV-Ray keeps for the object whose only primitive is `p`, where pvrt holds that
// primitive in POV-Ray's own form: untransformed spheres, boxes, discs, cylinders, cones and
// lone triangles. None for planes (unbounded) and for the shapes pvrt holds otherwise; a
// mesh's triangles are given their mesh's box when the scene is built (Primitive::povBox).
std::optional<PovBBox> povBBoxOf(const Primitive& p);

// Whether POV-Ray tests the object's float box (povBBoxDirHits) before the object itself:
// ObjectBase::Intersect_BBox does, but Box, Sphere, Triangle (so SmoothTriangle) and Plane
// override it to return true (boxes.cpp, spheres.cpp, triangle.cpp, planes.cpp). Of the
// shapes with a box here, cones, cylinders, discs and a mesh's triangles (with the mesh's box)
// are tested.
bool povTestsBBoxFirst(const Primitive& p);

// Inside_BBox: whether point p lies in the box (its far corner summed in double).
bool povBBoxHolds(const PovBBox& box, const Vec3& p);

// ObjectBase::Intersect_BBox, which Trace::FindIntersection and Find_Intersection call before
// they test an object (objects.cpp, Intersect_BBox_Dir): the box's corners, the ray's origin and
// 1 / direction as floats, the slabs in float; true when the ray's span in the box starts
// before HUGE_VAL and ends beyond MIN_ISECT_DEPTH. Far from the origin a float box can lie
// inside its object, and a float origin beside the ray, so POV-Ray misses slivers there.
bool povBBoxDirHits(const PovBBox& box, const Ray& ray);

// Bounding tree's Rayinfo: the ray's origin and reciprocal direction as floats, made once for
// all the boxes one ray meets.
struct PovRayInfo {
  explicit PovRayInfo(const Ray& ray);
  float num[3], den[3];
  bool nonzero[3], positive[3];
};

// Check_And_Enqueue's dmin for `ray`: the float depth where the ray enters the box (negative
// when it starts inside), or +infinity where POV-Ray would not enqueue the box at all.
double povBBoxKey(const PovBBox& box, const PovRayInfo& ray);
inline double povBBoxKey(const PovBBox& box, const Ray& ray) { return povBBoxKey(box, PovRayInfo(ray)); }

}  // namespace pvrt
