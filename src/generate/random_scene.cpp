#include "generate/random_scene.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"

namespace pvrt {

namespace {

// Knuth's MMIX LCG; 53 high bits give a double in [0, 1).
class Lcg {
 public:
  explicit Lcg(uint64_t seed) : state_(seed ^ 0x9E3779B97F4A7C15ull) { next(); }
  double next() {
    state_ = state_ * 6364136223846793005ull + 1442695040888963407ull;
    return double(state_ >> 11) * 0x1.0p-53;
  }
  double in(double lo, double hi) { return lo + (hi - lo) * next(); }

 private:
  uint64_t state_;
};

enum class Kind { Matte, Shiny, Mirror, Glass };

Kind pick(const Palette& p, double u) {
  const double total = p.matte + p.shiny + p.mirror + p.glass;
  double x = u * total;
  if ((x -= p.matte) < 0) return Kind::Matte;
  if ((x -= p.shiny) < 0) return Kind::Shiny;
  if ((x -= p.mirror) < 0) return Kind::Mirror;
  return p.glass > 0 ? Kind::Glass : (p.mirror > 0 ? Kind::Mirror : (p.shiny > 0 ? Kind::Shiny : Kind::Matte));
}

// Equal finishes and interiors share one copy (core/shared_value.h): a million spheres
// have four finishes between them.
struct Shared {
  SharingPool<FinishDesc> finishes;
  SharingPool<InteriorDesc> interiors;
};

MaterialDesc material(Kind kind, const Color& c, Shared& shared) {
  MaterialDesc m;
  m.pigment.color = {c, 0, 0};
  FinishDesc f;
  InteriorDesc interior;
  f.ambient = Color(0.1);
  f.diffuse = 0.7;
  switch (kind) {
    case Kind::Matte: break;
    case Kind::Shiny:
      f.phong = 0.5;
      f.phongSize = 40;
      break;
    case Kind::Mirror:
      f.ambient = Color(0.05);
      f.diffuse = 0.2;
      f.phong = 0.8;
      f.phongSize = 80;
      f.reflection.min = f.reflection.max = Color(0.75);
      break;
    case Kind::Glass:
      m.pigment.color = {{1, 1, 1}, 0.9, 0};
      f.ambient = Color(0);
      f.diffuse = 0.1;
      f.phong = 0.9;
      f.phongSize = 120;
      f.reflection.min = f.reflection.max = Color(0.1);
      interior.ior = 1.5;
      break;
  }
  m.finish = shared.finishes.share(f);
  m.interior = shared.interiors.share(interior);
  return m;
}

}  // namespace

double radiusScaleFor(int spheres) { return spheres <= 100 ? 1.0 : std::cbrt(100.0 / spheres); }

SceneDesc generateScene(const GenerateOptions& o) {
  if (o.spheres < 0 || o.lights < 0) throw Error(ExitCode::Usage, "counts must not be negative");
  if (!(o.radiusMin > 0) || o.radiusMax < o.radiusMin)
    throw Error(ExitCode::Usage, "need 0 < radius-min <= radius-max");
  const Palette& p = o.palette;
  if (p.matte < 0 || p.shiny < 0 || p.mirror < 0 || p.glass < 0 || p.matte + p.shiny + p.mirror + p.glass <= 0)
    throw Error(ExitCode::Usage, "palette weights must be non-negative and not all zero");

  SceneDesc s;
  s.image = ImageDesc{o.width, o.height, {}};
  s.camera.location = {0, 6, -14};
  s.camera.lookAt = Vec3{0, 1, 2};
  s.camera.right = {double(o.width) / o.height, 0, 0};
  s.camera.up = {0, 1, 0};
  s.background = {0.02, 0.02, 0.05};

  Lcg rng(o.seed);
  // Lights share a fixed total so a scene is equally bright whatever their number.
  for (int i = 0; i < o.lights; ++i) {
    LightDesc l;
    l.location = {rng.in(o.lightBoxLo.x, o.lightBoxHi.x), rng.in(o.lightBoxLo.y, o.lightBoxHi.y),
                  rng.in(o.lightBoxLo.z, o.lightBoxHi.z)};
    const double k = 1.6 / o.lights;
    l.color = {k * rng.in(0.8, 1.0), k * rng.in(0.8, 1.0), k * rng.in(0.8, 1.0)};
    s.lights.push_back(l);
  }
  if (o.floor) {
    ObjectDesc floor;
    floor.shape = PlaneDesc{{0, 1, 0}, 0};
    floor.material.pigment.checker =
        std::make_shared<const CheckerDesc>(CheckerDesc{{{0.85, 0.85, 0.85}, 0, 0}, {{0.25, 0.3, 0.4}, 0, 0}});
    floor.material.finish.edit([](FinishDesc& f) { f.diffuse = 0.7; });
    s.objects.push_back(floor);
  }
  Shared shared;
  for (int i = 0; i < o.spheres; ++i) {
    const double x = rng.in(o.sphereBoxLo.x, o.sphereBoxHi.x);
    double y = rng.in(o.sphereBoxLo.y, o.sphereBoxHi.y);
    const double z = rng.in(o.sphereBoxLo.z, o.sphereBoxHi.z);
    const double r = rng.in(o.radiusMin, o.radiusMax);
    const Color c{rng.in(0.1, 1), rng.in(0.1, 1), rng.in(0.1, 1)};
    const Kind kind = pick(p, rng.next());
    if (o.floor) y = std::max(y, r);  // rest on the floor rather than sink into it
    ObjectDesc sphere;
    sphere.shape = SphereDesc{{x, y, z}, r};
    sphere.material = material(kind, c, shared);
    s.objects.push_back(sphere);
  }
  return s;
}

GenerateOptions paperScene1() { return GenerateOptions{}; }

GenerateOptions paperScene2() {
  GenerateOptions o;
  o.spheres = 20;
  o.seed = 2;
  o.floor = false;
  // Seen from the default camera this box fills the image's upper-right quarter only.
  o.sphereBoxLo = {2.5, 4.5, 2};
  o.sphereBoxHi = {8, 8.5, 8};
  return o;
}

}  // namespace pvrt
