#include "render/light.h"

#include <cmath>
#include <numbers>

#include "core/single.h"
#include "geometry/primitive.h"

namespace pvrt {

namespace {
double cosDegrees(double deg) { return std::cos(deg * std::numbers::pi / 180.0); }
}  // namespace

// The most samples of an area light whose positions are worked out once (24 bytes each).
constexpr size_t kMaxKeptGrid = 4096;

Light buildLight(const LightDesc& d) {
  Light l;
  l.location = d.location;
  // A light's colour is a float colour in POV-Ray (LightSource::colour), as pigments are.
  l.color = single(d.color);
  l.shadowless = d.shadowless;
  // In POV-Ray `shadowless` and `spotlight` both set the light's type (Parse_Light_Source:
  // FILL_LIGHT_SOURCE, SPOT_SOURCE) and the exporter writes `shadowless` last, so a shadowless
  // spotlight is a shadowless point light there: Attenuate_Light shapes only SPOT_SOURCE lights.
  if (d.spot && !d.shadowless) {
    l.spot = true;
    l.spotAxis = unitDirection(d.spot->pointAt - d.location);
    l.cosRadius = cosDegrees(d.spot->radius);
    l.cosFalloff = cosDegrees(d.spot->falloff);
    l.tightness = d.spot->tightness;
  }
  l.fadeDistance = d.fadeDistance;
  l.fadePower = d.fadePower;
  if (d.area && d.area->size1 * d.area->size2 > 1) {
    l.area = true;
    l.axis1 = d.area->axis1;
    l.axis2 = d.area->axis2;
    l.size1 = d.area->size1;
    l.size2 = d.area->size2;
    l.adaptive = d.area->adaptive;
    l.circular = d.area->circular || d.area->orient;  // POV-Ray makes an oriented light circular
    l.orient = d.area->orient;
    if (!l.orient && size_t(l.size1) * size_t(l.size2) <= kMaxKeptGrid) {
      for (int j = 0; j < l.size2; ++j)
        for (int i = 0; i < l.size1; ++i) l.grid.push_back(l.areaSample(i, j, Vec3(0.0)));
    }
  }
  return l;
}

double Light::attenuation(const Vec3& toLight, double dist) const {
  double k = 1.0;
  if (spot) {
    const double c = -dot(toLight, spotAxis);
    if (c <= 0) return 0.0;
    if (tightness != 0) k = std::pow(c, tightness);
    if (c < cosRadius) {
      if (c < cosFalloff) return 0.0;
      // Smoothstep over cosines, as POV-Ray does (not over angles).
      const double u = (c - cosFalloff) / (cosRadius - cosFalloff);
      k *= u * u * (3.0 - 2.0 * u);
    }
  }
  if (fadePower > 0 && fadeDistance != 0)
    k *= 2.0 / (1.0 + std::pow(dist / fadeDistance, fadePower));
  return k;
}

Vec3 Light::areaSample(int i, int j, const Vec3& toLight) const {
  Vec3 a1 = axis1, a2 = axis2;
  if (orient) {
    // Turn the light's grid to face the shaded point, keeping |axis1| as its size.
    // As POV-Ray: axis1 is perpendicular to the point-to-light direction and to z (to y
    // when that direction is within 0.01 of vertical in z).
    const Vec3& l = toLight;
    Vec3 o1 = std::fabs(std::fabs(l.z) - 1.0) < 0.01 ? cross(l, Vec3{0, 1, 0}) : cross(l, Vec3{0, 0, 1});
    o1 = normalize(o1);
    const Vec3 o2 = normalize(cross(l, o1));
    a1 = o1 * length(axis1);
    a2 = o2 * length(axis1);
  }
  double u = size1 > 1 ? double(i) / (size1 - 1) - 0.5 : 0.0;
  double v = size2 > 1 ? double(j) / (size2 - 1) - 0.5 : 0.0;
  if (circular) {
    u += 0.001;
    v += 0.001;
    const double r = std::sqrt(u * u + v * v);
    const double s = std::fmax(std::fabs(u), std::fabs(v)) / r;
    u *= s;
    v *= s;
  }
  // As ComputeOneWhiteLightRay: the two offsets summed first, then added to the centre.
  return location + (a1 * u + a2 * v);
}

}  // namespace pvrt
