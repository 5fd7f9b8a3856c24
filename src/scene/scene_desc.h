// The neutral scene description: what a scene file says, with nothing computed yet.
// The XML loader fills it; the renderer and the POV-Ray exporter both read it, so each
// attribute is parsed in exactly one place. Every concept maps one-to-one onto POV-Ray's
// scene language; defaults are POV-Ray 3.7's.
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "core/color.h"
#include "core/shared_value.h"
#include "core/source_loc.h"
#include "core/transform.h"
#include "core/vec3.h"

namespace pvrt {

// One transform as written; kept (not only the product) so exporters can reproduce it.
struct TransformStep {
  enum class Kind { Scale, Rotate, Translate, Matrix } kind;
  Vec3 v;                          // scale, rotate (degrees) or translate
  std::array<double, 12> matrix{}; // POV-Ray's row-vector matrix <a..l>
  SourceLoc loc;
  Affine affine() const;
};

struct TransformList {
  std::vector<TransformStep> steps;
  Affine combined() const;  // steps applied in the order written
  bool empty() const { return steps.empty(); }
};

// ---------------------------------------------------------------- camera, globals

struct CameraDesc {
  Vec3 location{0, 0, 0};
  Vec3 direction{0, 0, 1};
  Vec3 up{0, 1, 0};
  Vec3 right{1.33, 0, 0};
  Vec3 sky{0, 1, 0};
  std::optional<Vec3> lookAt;
  std::optional<double> angle;  // degrees; only rescales direction when written
  TransformList transforms;
  SourceLoc loc;
};

struct GlobalSettings {
  int maxTraceLevel = 5;
  double adcBailout = 1.0 / 255.0;
  Color ambientLight{1, 1, 1};
  SourceLoc loc;
};

// Default image settings a scene may carry (POV-Ray keeps these on its command line).
struct ImageDesc {
  // Most pixels an image may have (2^28): the colour buffer alone is then 6 GiB.
  static constexpr long long kMaxPixels = 1LL << 28;
  int width = 320;
  int height = 240;
  SourceLoc loc;
};

// ---------------------------------------------------------------- lights

struct SpotlightDesc {
  Vec3 pointAt{0, 0, 1};
  double radius = 30;   // degrees
  double falloff = 45;  // degrees
  double tightness = 0;
};

struct AreaLightDesc {
  Vec3 axis1, axis2;
  int size1 = 1, size2 = 1;
  int adaptive = 100;  // POV-Ray's default: the full grid, with its recursive weights
  bool circular = false;
  bool orient = false;
};

struct LightDesc {
  Vec3 location;
  Color color{1, 1, 1};
  std::optional<SpotlightDesc> spot;
  std::optional<AreaLightDesc> area;
  double fadeDistance = 0;
  double fadePower = 0;
  bool shadowless = false;
  SourceLoc loc;
};

// ---------------------------------------------------------------- materials

struct CheckerDesc {
  FilterColor color1{{0, 0, 1}, 0, 0};
  FilterColor color2{{0, 1, 0}, 0, 0};
};

struct PigmentDesc {
  FilterColor color{{0, 0, 0}, 0, 0};
  // When set, `color` is unused. Held apart: most pigments are plain colours, and a scene
  // of a million of them should not carry room for two more colours each.
  std::shared_ptr<const CheckerDesc> checker;
  TransformList transforms;            // pattern space, applied before the object's
  bool hasTransparency() const;
  SourceLoc loc;
};

struct ReflectionDesc {
  Color min{0, 0, 0};  // at normal incidence ("a")
  Color max{0, 0, 0};  // at grazing incidence ("b")
  double falloff = 1;
  bool fresnel = false;
  double exponent = 1;
  double metallic = 0;
  bool isZero() const { return min.isBlack() && max.isBlack(); }
  bool operator==(const ReflectionDesc&) const = default;
};

struct FinishDesc {
  Color ambient{0.1, 0.1, 0.1};
  Color emission{0, 0, 0};
  double diffuse = 0.6;
  double brilliance = 1;
  double phong = 0;
  double phongSize = 40;
  double specular = 0;
  double roughness = 0.05;
  double metallic = 0;
  bool conserveEnergy = false;
  ReflectionDesc reflection;
  bool operator==(const FinishDesc&) const = default;
};

struct InteriorDesc {
  double ior = 1;
  double fadeDistance = 0;
  double fadePower = 0;
  Color fadeColor{0, 0, 0};
  bool operator==(const InteriorDesc&) const = default;
};

// Finishes and interiors are shared values (core/shared_value.h): a scene has few of each,
// and the loader gives equal ones one copy, so an object's material costs ~150 bytes, not
// ~490 (a million spheres: 10^6 x 712 bytes of description before, docs/parallel.md).
// They carry no location of their own: nothing reports one, and equal ones written on
// different lines could not then be shared; the material's `loc` says where it was written.
struct MaterialDesc {
  std::string name;  // empty for an inline material
  PigmentDesc pigment;
  SharedValue<FinishDesc> finish;
  SharedValue<InteriorDesc> interior;
  SourceLoc loc;
};

// ---------------------------------------------------------------- shapes

struct SphereDesc { Vec3 center; double radius = 1; };
struct PlaneDesc { Vec3 normal{0, 1, 0}; double distance = 0; };
struct BoxDesc { Vec3 corner1, corner2; };
struct CylinderDesc { Vec3 base, cap; double radius = 1; bool open = false; };
struct ConeDesc { Vec3 base; double baseRadius = 1; Vec3 cap; double capRadius = 0; bool open = false; };
struct DiscDesc { Vec3 center; Vec3 normal{0, 1, 0}; double radius = 1; double holeRadius = 0; };
struct TriangleDesc { Vec3 p1, p2, p3; SourceLoc loc; };
struct SmoothTriangleDesc { Vec3 p1, n1, p2, n2, p3, n3; SourceLoc loc; };
struct MeshDesc {
  std::vector<TriangleDesc> triangles;
  std::vector<SmoothTriangleDesc> smoothTriangles;
};

// A lone smooth triangle is held apart (shared, core/shared_value.h): at 160 bytes it would
// make every object's shape, spheres included, that big (a million spheres: 69 MiB more).
using SmoothTriangleRef = SharedValue<SmoothTriangleDesc>;
using ShapeDesc = std::variant<SphereDesc, PlaneDesc, BoxDesc, CylinderDesc, ConeDesc, DiscDesc,
                               TriangleDesc, SmoothTriangleRef, MeshDesc>;

const char* shapeName(const ShapeDesc& shape);

struct ObjectDesc {
  ShapeDesc shape;
  // Index into SceneDesc::materials of a named material, or -1 for the inline one.
  int namedMaterial = -1;
  MaterialDesc material;  // the inline material (the named one, copied, when referenced)
  TransformList transforms;
  bool noShadow = false;
  SourceLoc loc;
};

struct SceneDesc {
  std::string path;
  CameraDesc camera;
  GlobalSettings globals;
  Color background{0, 0, 0};
  std::optional<ImageDesc> image;
  std::vector<LightDesc> lights;
  std::vector<MaterialDesc> materials;  // named materials, in file order
  std::vector<ObjectDesc> objects;
};

}  // namespace pvrt
