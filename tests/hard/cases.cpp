#include "cases.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "render/camera.h"

namespace pvrt::hard {

namespace {

using LD = long double;

struct V {
  LD x = 0, y = 0, z = 0;
  V() = default;
  V(LD a, LD b, LD c) : x(a), y(b), z(c) {}
  explicit V(const Vec3& v) : x(v.x), y(v.y), z(v.z) {}
  V operator+(const V& o) const { return {x + o.x, y + o.y, z + o.z}; }
  V operator-(const V& o) const { return {x - o.x, y - o.y, z - o.z}; }
  V operator*(LD s) const { return {x * s, y * s, z * s}; }
  V operator-() const { return {-x, -y, -z}; }
};
LD dot(const V& a, const V& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V cross(const V& a, const V& b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
LD len(const V& a) { return std::sqrt(dot(a, a)); }
V unit(const V& a) { return a * (1 / len(a)); }

struct PixelRay {
  V o, d;  // d unit
};

// Every pixel's centre ray, as the renderer forms it at one sample per pixel.
template <class F>
ExpectedImage forEachPixel(const CaseInput& in, F&& f) {
  const Camera cam(in.scene.camera);
  ExpectedImage e(in.width, in.height);
  for (int y = 0; y < in.height; ++y)
    for (int x = 0; x < in.width; ++x) {
      const Ray r = cam.ray(x, y, 0, 0, in.width, in.height);
      e.at(x, y) = f(PixelRay{V(r.origin), unit(V(r.dir))});
    }
  return e;
}

Color toColor(const V& v) { return {double(v.x), double(v.y), double(v.z)}; }
V fromColor(const Color& c) { return {c.r, c.g, c.b}; }
V mul(const V& a, const V& b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }

struct Surface {
  bool sphere = false;
  V center;
  LD radius = 0;
  V normal;  // plane
  LD distance = 0;
  const MaterialDesc* material = nullptr;
};

// Both roots of the ray with a sphere (NaN when it misses) and the line's distance from the centre.
struct SphereRoots {
  LD t1, t2, perp, along;
};
SphereRoots sphereRoots(const V& o, const V& d, const V& c, LD r) {
  const V oc = c - o;
  const LD along = dot(oc, d);
  const LD perp = len(cross(oc, d));
  if (perp >= r) return {NAN, NAN, perp, along};
  const LD half = std::sqrt((r - perp) * (r + perp));
  return {along - half, along + half, perp, along};
}

}  // namespace

ExpectedImage spheresAndPlanes(const CaseInput& in) {
  std::optional<Surface> sphere, plane;
  for (const ObjectDesc& o : in.scene.objects) {
    if (const auto* s = std::get_if<SphereDesc>(&o.shape); s && !sphere)
      sphere = Surface{true, V(s->center), s->radius, {}, 0, &o.material};
    if (const auto* p = std::get_if<PlaneDesc>(&o.shape); p && !plane)
      plane = Surface{false, {}, 0, unit(V(p->normal)), p->distance, &o.material};
  }
  const LightDesc* light = in.scene.lights.empty() ? nullptr : &in.scene.lights.front();
  const V ambientLight = fromColor(in.scene.globals.ambientLight);
  const LD tol = in.shadowTolerance;

  return forEachPixel(in, [&](const PixelRay& ray) {
    Expected e;
    const LD scale = std::max<LD>(1e-300L, sphere ? sphere->radius : 1.0L);
    std::optional<LD> tS, tP;
    if (sphere) {
      const SphereRoots s = sphereRoots(ray.o, ray.d, sphere->center, sphere->radius);
      const bool outside = len(sphere->center - ray.o) > sphere->radius * (1 + 1e-12L);
      if (outside && s.along > 0) e.margin[0] = double((s.perp - sphere->radius) / sphere->radius);  // silhouette
      const LD eps = 1e-9L * scale;
      if (!std::isnan(s.t1)) {
        if (s.t1 > eps) tS = s.t1;
        else if (s.t2 > eps) tS = s.t2;
      }
    }
    if (plane) {
      const LD nd = dot(plane->normal, ray.d);
      e.margin[1] = double(nd);  // the horizon
      if (std::fabs(nd) >= 1e-10L) {
        const LD t = (plane->distance - dot(plane->normal, ray.o)) / nd;
        if (t > 0) {
          e.margin[2] = double((t - in.maxDistance) / in.maxDistance);  // hits beyond the maximum distance are dropped
          if (t < in.maxDistance) tP = t;
        }
      }
    }
    if (tS && tP) e.margin[3] = double((*tS - *tP) / std::max(*tS, *tP));
    const Surface* hit = nullptr;
    LD t = 0;
    if (tS && (!tP || *tS < *tP)) hit = &*sphere, t = *tS;
    else if (tP) hit = &*plane, t = *tP;
    if (!hit) {
      e.c = in.scene.background;
      return e;
    }
    const V p = ray.o + ray.d * t;
    V n = hit->sphere ? unit(p - hit->center) : hit->normal;
    if (dot(n, ray.d) > 0) n = -n;
    const MaterialDesc& m = *hit->material;
    const V pig = fromColor(m.pigment.color.rgb);
    const LD alpha = 1 - m.pigment.color.filter - m.pigment.color.transmit;
    V c = mul(mul(pig, fromColor(m.finish->ambient)), ambientLight) * alpha + mul(pig, fromColor(m.finish->emission)) * alpha;
    if (light) {
      const V toLight = V(light->location) - p;
      const LD dist = len(toLight);
      if (dist > 1e-12L * scale) {
        const V l = toLight * (1 / dist);
        const LD nl = dot(n, l);
        bool blocked = false;
        if (sphere) {
          const SphereRoots s = sphereRoots(p, l, sphere->center, sphere->radius);
          for (LD r : {s.t1, s.t2})
            if (!std::isnan(r) && r > tol && r < dist - tol) blocked = true;
          // The shadow's edge: the segment grazes the sphere.
          if (s.along > tol && s.along < dist - tol) e.margin[4] = double((s.perp - sphere->radius) / sphere->radius);
        }
        if (plane && hit != &*plane) {
          const LD nd = dot(plane->normal, l);
          if (nd != 0) {
            const LD s = (plane->distance - dot(plane->normal, p)) / nd;
            if (s > tol && s < dist - tol) blocked = true;
          }
        }
        if (nl >= 1e-10L && !blocked) {
          const LD k = m.finish->diffuse * nl * alpha;
          c = c + mul(pig, fromColor(light->color)) * k;
          e.litTerm = double(k * std::max({pig.x, pig.y, pig.z}));
        }
      }
    }
    e.c = toColor(c);
    return e;
  });
}

namespace {
const MaterialDesc& firstMaterial(const SceneDesc& s) { return s.objects.front().material; }
}  // namespace

ExpectedImage tirSlab(const CaseInput& in) {
  const LD n = firstMaterial(in.scene).interior->ior;
  const LD cosCritical = std::sqrt(1 - 1 / (n * n));
  return forEachPixel(in, [&](const PixelRay& ray) {
    Expected e;
    const LD c = std::fabs(ray.d.y);  // the faces are horizontal
    e.margin[0] = double(c - cosCritical);
    e.c = c > cosCritical ? in.scene.background : Color(0.0);
    return e;
  });
}

ExpectedImage tirSphere(const CaseInput& in) {
  const auto& s = std::get<SphereDesc>(in.scene.objects.front().shape);
  const LD n = firstMaterial(in.scene).interior->ior;
  return forEachPixel(in, [&](const PixelRay& ray) {
    Expected e;
    const LD p = len(cross(V(s.center) - ray.o, ray.d));
    const LD limit = s.radius / n;  // sin(incidence) = p / r reaches 1 / n
    e.margin[0] = double((limit - p) / s.radius);
    e.c = p < limit ? in.scene.background : Color(0.0);
    return e;
  });
}

ExpectedImage facingMirrors(const CaseInput& in) {
  const MaterialDesc& m = firstMaterial(in.scene);
  const Color each = m.pigment.color.rgb * m.finish->ambient * in.scene.globals.ambientLight;
  return forEachPixel(in, [&](const PixelRay&) {
    Expected e;
    e.c = each * double(in.scene.globals.maxTraceLevel);
    return e;
  });
}

ExpectedImage octahedron(const CaseInput& in) {
  return forEachPixel(in, [&](const PixelRay& ray) {
    Expected e;
    // The smallest L1 norm along the ray (t >= 0): the function is convex and piecewise
    // linear, so its minimum is at t = 0 or where a coordinate crosses zero.
    auto l1 = [&](LD t) {
      const V p = ray.o + ray.d * t;
      return std::fabs(p.x) + std::fabs(p.y) + std::fabs(p.z);
    };
    LD best = l1(0);
    const LD o[3] = {ray.o.x, ray.o.y, ray.o.z}, d[3] = {ray.d.x, ray.d.y, ray.d.z};
    for (int i = 0; i < 3; ++i)
      if (d[i] != 0 && -o[i] / d[i] > 0) best = std::min(best, l1(-o[i] / d[i]));
    e.margin[0] = double(best - 1);
    e.c = best < 1 ? Color(1.0) : in.scene.background;
    // From inside, a ray that leaves exactly through an edge or a vertex (a coordinate of
    // its exit point 0) is not compared: POV-Ray's mesh test (shape/mesh.cpp), which pvrt's
    // is (docs/fidelity.md), lets some of those through, where the hit point rounds just
    // outside both triangles that meet there (POV-Ray 3.7.0.10's own render of
    // closed_mesh_inside shows the background at 11 pixels of its middle column).
    if (l1(0) < 1) {
      LD lo = 0, hi = 1;
      while (l1(hi) < 1) hi *= 2;
      for (int i = 0; i < 200; ++i) {
        const LD mid = (lo + hi) / 2;
        (l1(mid) < 1 ? lo : hi) = mid;
      }
      const V p = ray.o + ray.d * hi;
      if (std::min({std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)}) < 1e-9L) e.skip = true;
    }
    return e;
  });
}

ExpectedImage unitSquare(const CaseInput& in) {
  const LightDesc& light = in.scene.lights.front();
  return forEachPixel(in, [&](const PixelRay& ray) {
    Expected e;
    e.c = in.scene.background;
    if (ray.d.z == 0) return e;
    const LD t = -ray.o.z / ray.d.z;
    if (t <= 0) return e;
    const V p = ray.o + ray.d * t;
    const LD inside = std::min({p.x, 1 - p.x, p.y, 1 - p.y});
    e.margin[0] = double(inside);
    if (inside <= 0) return e;
    const V n = ray.d.z > 0 ? V(0, 0, -1) : V(0, 0, 1);
    const V toLight = V(light.location) - p;
    const LD nl = dot(n, toLight) / len(toLight);
    if (nl >= 1e-10L) e.c = toColor(V(1, 1, 1) * nl), e.litTerm = double(nl);
    else e.c = Color(0.0);
    return e;
  });
}

namespace {
struct CoplanarParts {
  const SphereDesc* sphere = nullptr;
  const PlaneDesc* plane = nullptr;
  const DiscDesc* disc = nullptr;
  Color sphereColor, planeColor, discColor;
};
CoplanarParts coplanarParts(const SceneDesc& s) {
  CoplanarParts c;
  for (const ObjectDesc& o : s.objects) {
    const Color col = o.material.pigment.color.rgb * o.material.finish->ambient;
    // Of the two identical spheres POV-Ray shows the second: their boxes are one box, so the
    // ray enters both at one float depth and its bounding heap pops the second first (the
    // planes' node, then the spheres and the disc in the root's order; accel/pov_heap_order.h).
    if (const auto* p = std::get_if<SphereDesc>(&o.shape)) c.sphere = p, c.sphereColor = col;
    if (const auto* p = std::get_if<PlaneDesc>(&o.shape); p && !c.plane) c.plane = p, c.planeColor = col;
    if (const auto* p = std::get_if<DiscDesc>(&o.shape); p && !c.disc) c.disc = p, c.discColor = col;
  }
  return c;
}
}  // namespace

ExpectedImage coplanar(const CaseInput& in) {
  const CoplanarParts parts = coplanarParts(in.scene);
  return forEachPixel(in, [&](const PixelRay& ray) {
    Expected e;
    const SphereRoots s = sphereRoots(ray.o, ray.d, V(parts.sphere->center), parts.sphere->radius);
    e.margin[0] = double((s.perp - parts.sphere->radius) / parts.sphere->radius);
    if (!std::isnan(s.t1) && s.t1 > 0) {
      e.c = parts.sphereColor;  // exact tie: the sphere POV-Ray's heap pops first (above)
      return e;
    }
    const V n = unit(V(parts.plane->normal));
    const LD t = (parts.plane->distance - dot(n, ray.o)) / dot(n, ray.d);
    e.c = in.scene.background;
    if (!(t > 0)) return e;
    const V p = ray.o + ray.d * t;
    const LD r = len(p - V(parts.disc->center));
    e.margin[1] = double((r - parts.disc->radius) / parts.disc->radius);
    e.c = parts.planeColor;  // exact tie: the first plane in the file
    if (r < parts.disc->radius) e.skip = true;  // the disc against the plane: coplanarDisc()
    return e;
  });
}

DiscTies coplanarDisc(const CaseInput& in, const Image& got) {
  const CoplanarParts parts = coplanarParts(in.scene);
  const ExpectedImage want = coplanar(in);
  DiscTies d;
  auto same = [](const float* g, const Color& c) {
    return std::fabs(g[0] - c.r) < 1e-6 && std::fabs(g[1] - c.g) < 1e-6 && std::fabs(g[2] - c.b) < 1e-6;
  };
  for (int y = 0; y < in.height; ++y)
    for (int x = 0; x < in.width; ++x) {
      if (!want.at(x, y).skip) continue;
      ++d.pixels;
      const float* g = got.row(y) + size_t(x) * 3;
      if (same(g, parts.discColor)) ++d.disc;
      else if (same(g, parts.planeColor)) ++d.plane;
      else ++d.other;
    }
  return d;
}

}  // namespace pvrt::hard
