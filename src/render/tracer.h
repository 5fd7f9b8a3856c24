// The Whitted ray tracer, compiled once per effect set E: code for an effect the scene
// does not call for is removed at compile time (`if constexpr`), not skipped per ray.
// Follows POV-Ray 3.7's trace (shared/povray-semantics.md sections 3-5, 7, 8, 12).
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <optional>
#include <utility>
#include <vector>

#include "core/interrupt.h"
#include "core/lanes.h"
#include "core/square_bound.h"
#include "render/effects.h"
#include "render/scene.h"
#include "render/pov_colour.h"
#include "render/pov_secondary.h"
#include "render/shading.h"
#include "render/spawn.h"
#include "render/stats.h"

namespace pvrt {

template <EffectSet E>
class Tracer {
  static constexpr uint8_t kUnknown = 0xff;  // no shadow answer known beforehand
  // What tracePacket found about one light from one hit: its direction and distance, as
  // lightContribution computes them, and the shadow segment's occlusion (or kUnknown).
  struct KnownLight {
    Vec3 dir;
    double dist = 0;
    bool lit = false;  // neither at the point nor behind the surface: lightContribution goes on
    uint8_t occlusion = kUnknown;
    // When Transparent: the segment's nearest see-through hit (its walk's first step) and
    // the light buffer's cell of its direction (or -1), as the packet's query found them.
    const ClosestHit* nearest = nullptr;
    int cell = -1;
  };
  // A hit point's segment toward one area-light sample (made when first asked for), and
  // the full shadow test's answer (kUnknown until traceSamples finds it) with its blocker.
  struct AreaSegment {
    Vec3 dir;
    double dist = 0;
    bool made = false;
    uint8_t found = kUnknown;
    uint32_t blocker = 0;
  };
  // The same for every ray of a packet and one light, a component per array, so that
  // four rays are done at once (the divisions and square roots are most of the cost).
  struct PacketLight {
    double dirX[kMaxPacket], dirY[kMaxPacket], dirZ[kMaxPacket], dist[kMaxPacket];
    uint64_t lit;                    // a bit per ray
    uint8_t occlusion[kMaxPacket];  // set by resolveShadows for the lit rays
    uint64_t noted = 0;              // the rays whose see-through segments have `nearest` noted
    int cell = -1;                   // the buffer's cell of every noted segment's direction, or -1
    PacketNearest nearest;
    bool isLit(int k) const { return (lit >> k & 1u) != 0; }
    KnownLight at(int k) const {
      const bool see = (noted >> k & 1u) != 0 && occlusion[k] == uint8_t(Occlusion::Transparent);
      return {{dirX[k], dirY[k], dirZ[k]}, dist[k], isLit(k), occlusion[k], see ? &nearest.hit[k] : nullptr,
              see ? cell : -1};
    }
  };

 public:
  Tracer(const Scene& scene, RenderStats& stats)
      : scene_(scene),
        stats_(stats),
        servesSquared_(squareBound(servesBound(scene.tol.shadow))),
        shadowSlabLimit_(shadowSlabLimit(scene.tol)),
        pointCellsFirst_(std::any_of(scene.lightBuffers.begin(), scene.lightBuffers.end(),
                                     [](const LightBuffer& b) { return b.valid(); })),
        textures_((scene.effects & kTextures) != 0),
        lightShaping_((scene.effects & kLightShaping) != 0) {}

  // A spawned ray's weight as POV-Ray passes it to TraceRay: a float (COLC), compared with
  // adc_bailout (a double) on entry. Rounded here, before the comparison, so that a weight
  // on the edge of the bailout takes POV-Ray's side of it.
  static double rayWeight(double w) { return double(float(w)); }

  // Colour seen along a unit-direction ray that enters at trace `level` with `weight`;
  // a camera ray unless `spawned` (then it starts on a surface, render/spawn.h).
  Color trace(const Ray& ray, int level, double weight, const InteriorList& inside, bool spawned = false) {
    // A deep trace (max_trace_level 256 among glass) may take hours a pixel: once a signal is
    // caught every tree is cut short, and the image is thrown away.
    if (spawned && interrupt::requested()) return {};
    const double tMin = spawned ? scene_.tol.minDepth : scene_.tol.primaryMinDepth;
    return shadeFound(ray, scene_.bvh.closest(ray, tMin, scene_.tol.maxDistance, stats_.intersectionTests), level,
                      weight, inside);
  }

  // The primary rays of a pixel or of a few neighbours, all from the camera: their closest
  // hits and the shadow segments of those hits are found a packet at a time
  // (accel/packet.h); the shading is then exactly trace()'s, four rays at a time where
  // setUpFour and shadeFour allow it, else ray by ray. `out[k]` receives ray k's colour.
  void tracePacket(const Ray* rays, int count, const InteriorList& inside, Color* out) {
    std::optional<ClosestHit>* hits = hits_;
    scene_.bvh.closestPacket(rays, count, scene_.tol.primaryMinDepth, scene_.tol.maxDistance, hits,
                             stats_.intersectionTests);
    const size_t lights = scene_.lights.size();
    known_.resize(lights);
    // Bit k set where ray k hit: a group of four misses (the sky of most scenes) has no
    // light to find, nor shadows, so its lanes skip the square roots and divisions below.
    uint64_t hitBits = 0;
    for (int k = 0; k < count; ++k) hitBits |= uint64_t(hits[k].has_value()) << k;
    if (hitBits == 0) {
      // A packet of misses has nothing to set up or shade: its rays see the background,
      // and the shadow cache ends as the shading loop below would leave it.
      std::fill(out, out + count, scene_.background);
      const uint64_t rays = count == 64 ? ~uint64_t(0) : (uint64_t(1) << count) - 1;
      if (pixelStarts_ & rays & ~uint64_t(1)) {
        beginPixel();  // as the shading loop does at a pixel starting after ray 0
      } else if constexpr ((E & kShadows) != 0) {
        // applyShadowCache empties a light's level-1 entry where ray 0 starts a pixel
        // (resolveShadows calls it for the lights it tests as a packet).
        if (pixelStarts_ & 1)
          for (size_t j = 0; j < lights; ++j) {
            const Light& light = scene_.lights[j];
            if (!light.shadowless && !((E & kAreaLights) != 0 && light.area)) cacheEntry(j, true) = kNoCache;
          }
      }
      pixelStarts_ = 1;
      return;
    }
    // The hit points and normals a component per array (zeros for misses and for the
    // lanes past `count`, whose answers are never read).
    const int padded = (count + 3) & ~3;
    for (int k = 0; k < padded; ++k) {
      if (k % 4 == 0 && k + 4 <= count && setUpFour(rays, k)) {
        k += 3;
        continue;
      }
      if (k >= count || !hits[k]) {
        px_[k] = py_[k] = pz_[k] = nx_[k] = ny_[k] = nz_[k] = pointError_[k] = 0;
        shadowX_[k] = shadowY_[k] = shadowZ_[k] = 0;
        continue;
      }
      // Exactly what shade() and lightContribution() compute for this hit, done once.
      const uint32_t prim = hits[k]->primitive;
      points_[k] = scene_.bvh.surfacePoint(prim, rays[k], hits[k]->hit);
      normals_[k] = scene_.bvh.normal(prim, rays[k], hits[k]->hit);
      if (dot(normals_[k], rays[k].dir) > 0) normals_[k] = -normals_[k];
      // Every segment toward a light that lightContribution traces leaves on the side the
      // normal points to (it asks dot(n, l) >= kPovEpsilon first), so all of this hit's
      // segments start here.
      if constexpr ((E & kShadows) != 0)
        setShadowOrigin(k, shadowSegmentOrigin(points_[k], normals_[k], shadowSlabLimit_));
      px_[k] = points_[k].p.x, py_[k] = points_[k].p.y, pz_[k] = points_[k].p.z;
      nx_[k] = normals_[k].x, ny_[k] = normals_[k].y, nz_[k] = normals_[k].z;
      pointError_[k] = length(points_[k].error);
    }
    if constexpr ((E & kShadows) != 0) measureShadowShifts(padded, hitBits);
    for (size_t j = 0; j < lights; ++j) {
      using namespace lanes;
      PacketLight& pl = known_[j];
      const Vec3& at = scene_.lights[j].location;
      const Double4 lx = splat(at.x), ly = splat(at.y), lz = splat(at.z), eps = splat(kPovEpsilon);
      pl.lit = 0;
      for (int k = 0; k < padded; k += 4) {
        if (((hitBits >> k) & 0xFu) == 0) {
          // What the arithmetic below gives a miss's zero point and normal, but the
          // direction and distance: never lit, so never read but by masked lanes.
          const Double4 zero = splat(0.0);
          store(pl.dirX + k, zero), store(pl.dirY + k, zero), store(pl.dirZ + k, zero), store(pl.dist + k, zero);
          continue;
        }
        // Lane by lane the operations of length(), the reciprocal and dot(), in their order.
        const Double4 tx = lx - load(px_ + k), ty = ly - load(py_ + k), tz = lz - load(pz_ + k);
        const Double4 dist = lanes::sqrt(tx * tx + ty * ty + tz * tz);
        const Double4 inv = splat(1.0) / dist;  // ComputeOneWhiteLightRay: VInverseScaleEq
        const Double4 dx = tx * inv, dy = ty * inv, dz = tz * inv;
        const Double4 nl = load(nx_ + k) * dx + load(ny_ + k) * dy + load(nz_ + k) * dz;
        const unsigned lit = less(load(pointError_ + k), dist) & lessEqual(eps, nl);
        store(pl.dirX + k, dx), store(pl.dirY + k, dy), store(pl.dirZ + k, dz), store(pl.dist + k, dist);
        pl.lit |= uint64_t(lit) << k;
      }
    }
    if constexpr ((E & kShadows) != 0) {
      for (size_t j = 0; j < lights; ++j) resolveShadows(count, j);
    }
    if constexpr ((E & (kReflection | kTransmission)) != 0) traceSpawnedAhead(rays, count, hitBits, inside);
    for (int k = 0; k < count; ++k) {
      // Every pixel's secondary rays start with an empty shadow cache, as when it is traced
      // alone (shadeFour's lanes use no cache, so a pixel starting inside them resets after).
      if (k > 0 && ((pixelStarts_ >> k) & 1)) beginPixel();
      if (k % 4 == 0 && k + 4 <= count && shadeFour(rays, k, out)) {
        if ((pixelStarts_ >> (k + 1)) & 7) beginPixel();
        k += 3;
        continue;
      }
      if (!hits[k]) {
        out[k] = scene_.background;
        continue;
      }
      ++stats_.shadingOps;
      knownRay_ = k;
      out[k] = shadeAt(rays[k], hits[k]->primitive, hits[k]->hit, points_[k], normals_[k],
                       1, 1.0, inside);
    }
    pixelStarts_ = 1;
  }

  // Forgets the shadow cache; called at every pixel so that the work counted for a
  // pixel never depends on which pixel the thread rendered before it.
  void beginPixel() { std::fill(shadowCache_.begin(), shadowCache_.end(), kNoCache); }
  // The cache entry of light `slot` written by the shadow tests of a level-1 hit or of a
  // deeper one, and the object such a test tries first: a level-1 test borrows the deeper
  // tests' object while its own entry is empty, as TracePointLightShadowRay does.
  uint32_t& cacheEntry(size_t slot, bool levelOne) { return shadowCache_[levelOne ? slot : slot + shadowCache_.size() / 2]; }
  uint32_t cachedBlocker(size_t slot, bool levelOne) {
    const uint32_t own = cacheEntry(slot, levelOne);
    return levelOne && own == kNoCache ? cacheEntry(slot, false) : own;
  }
  // Bit k set where ray k of the next tracePacket() starts a pixel (by default only ray 0):
  // the shadow cache is kept within a pixel.
  void setPixelStarts(uint64_t bits) { pixelStarts_ = bits; }

 private:
  // The rays that shading a packet's hits will spawn at level 1, with their closest hits
  // found ahead together (traceSpawnedAhead): a bit in `live` per packet ray that has one.
  struct SpawnedAhead {
    PacketRays rays;
    uint64_t live = 0;
    std::optional<ClosestHit> hits[kMaxPacket];
  };

  Color shadeFound(const Ray& ray, const std::optional<ClosestHit>& found, int level, double weight,
                   const InteriorList& inside) {
    if (!found) return scene_.background;
    ++stats_.shadingOps;
    return shade(ray, found->primitive, found->hit, level + 1, weight, inside);
  }

  // trace() of a ray spawned at the hit of packet ray `lane` (-1: of no packet ray), with
  // the hit found ahead when `ahead` holds this very ray, bit for bit.
  Color traceSpawned(const Ray& ray, int level, double weight, const InteriorList& inside, int lane,
                     const SpawnedAhead& ahead) {
    if (lane < 0 || !(ahead.live >> lane & 1u) || !sameBits(ahead.rays.ray(lane), ray))
      return trace(ray, level, weight, inside, true);
    if (interrupt::requested()) return {};
    return shadeFound(ray, ahead.hits[lane], level, weight, inside);
  }
  static bool sameBits(const Ray& a, const Ray& b) {
    const auto bits = [](double x) { return std::bit_cast<uint64_t>(x); };
    for (int i = 0; i < 3; ++i)
      if (bits(a.origin[i]) != bits(b.origin[i]) || bits(a.dir[i]) != bits(b.dir[i])) return false;
    return true;
  }

  // How light passes a surface that lets it through (transmit): straight on when the
  // interiors' iors match, back as a mirror ray in total internal reflection, else bent.
  enum class Passage { Straight, Reflected, Bent };
  Passage passage(const Ray& ray, const SurfacePoint& sp, const Vec3& n, double eta, Ray& out) const {
    if (std::fabs(eta - 1.0) < kPovEpsilon) {
      out = spawnRay(sp, n, ray.dir, scene_.tol.minDepth);
      return Passage::Straight;
    }
    const double c1 = -dot(ray.dir, n);
    const double k = 1.0 + eta * eta * (c1 * c1 - 1.0);
    if (k < 0) {
      out = spawnRay(sp, n, mirror(ray.dir, n), scene_.tol.minDepth);
      return Passage::Reflected;
    }
    // Heckbert's formula; unit length in exact arithmetic and, as in POV-Ray, not renormalised.
    const Vec3 dir = ray.dir * eta + n * (eta * c1 - std::sqrt(k));
    out = spawnRay(sp, n, dir, scene_.tol.minDepth);
    return Passage::Bent;
  }

  // The level-1 rays that shading the packet's hits may spawn (a mirror ray where the
  // surface reflects or bends light back, the ray through it where it may let light
  // through), each made as shadeAt and transmit make it, and their closest hits found as
  // two packets of rays from their own origins: neighbouring rays meet the same surface,
  // so the rays they spawn walk much the same part of the tree. A ray that shading does
  // not trace after all (a weight below the bailout) costs only its share of the walk.
  void traceSpawnedAhead(const Ray* rays, int count, uint64_t hitBits, const InteriorList& inside) {
    mirrorAhead_.live = throughAhead_.live = 0;
    if (scene_.globals.maxTraceLevel <= 1) return;
    for (uint64_t b = hitBits; b != 0; b &= b - 1) {
      const int k = __builtin_ctzll(b);
      const uint32_t prim = hits_[k]->primitive;
      const Material& m = scene_.materials[scene_.bvh.material(prim)];
      bool reflective = false, see = false;
      if constexpr ((E & kReflection) != 0) reflective = scene_.materials.surface(m).reflective;
      if constexpr ((E & kTransmission) != 0) see = !m.opaque;
      if (reflective) {
        const Ray r = spawnRay(points_[k], normals_[k], mirror(rays[k].dir, normals_[k]), scene_.tol.minDepth);
        mirrorAhead_.rays.set(k, r.origin, r.dir);
        mirrorAhead_.live |= uint64_t(1) << k;
      }
      if (see) {
        Ray r;
        const double eta = refractionEta(scene_.bvh.object(prim), inside);
        SpawnedAhead& a = passage(rays[k], points_[k], normals_[k], eta, r) == Passage::Reflected ? mirrorAhead_
                                                                                                  : throughAhead_;
        a.rays.set(k, r.origin, r.dir);
        a.live |= uint64_t(1) << k;
      }
    }
    for (SpawnedAhead* a : {&mirrorAhead_, &throughAhead_}) {
      // A lone ray walks faster alone.
      if (__builtin_popcountll(a->live) < kMinSpread) {
        a->live = 0;
        continue;
      }
      a->rays.count = count;
      a->rays.groups = (count + 3) / 4;
      for (int k = 0; k < 4 * a->rays.groups; ++k)
        if (!(a->live >> k & 1u)) a->rays.set(k, Vec3(NAN), Vec3(NAN));
      scene_.bvh.closestSpread(a->rays, a->live, scene_.tol.minDepth, scene_.tol.maxDistance, a->hits,
                               stats_.intersectionTests);
    }
  }
  static constexpr int kMinSpread = 2;

  // `level` is the level this hit runs at: 1 for the primary ray's hit.
  Color shade(const Ray& ray, uint32_t prim, const ShapeHit& hit, int level, double weight,
              const InteriorList& inside) {
    const SurfacePoint sp = scene_.bvh.surfacePoint(prim, ray, hit);
    Vec3 n = scene_.bvh.normal(prim, ray, hit);
    if (dot(n, ray.dir) > 0) n = -n;  // every surface is shaded on the side the ray sees
    return shadeAt(ray, prim, hit, sp, n, level, weight, inside);
  }

  // shade() once the hit point sp and the ray-facing normal n are known.
  // `prim` is an index into the BVH's primitives.
  Color shadeAt(const Ray& ray, uint32_t prim, const ShapeHit& hit, const SurfacePoint& sp, const Vec3& n,
                int level, double weight, const InteriorList& inside) {
    const Vec3& p = sp.p;
    const uint32_t object = scene_.bvh.object(prim);
    // In a big scene the object's material is a cache miss: started before the light-buffer
    // prefetch below, which waits on misses of its own, so that the two overlap.
    const Material& m = scene_.materials[scene_.bvh.material(prim)];
    if constexpr ((E & kShadows) != 0) {
      __builtin_prefetch(&m);
      // A packet's primary hit has its shadows answered already (tracePacket): no cells to read.
      if (pointCellsFirst_ && knownRay_ < 0) findShadowCells(p, n);
    }
    const Surface& s = scene_.materials.surface(m);
    const FinishDesc& f = s.finish;

    FilterColor pig = m.color;
    if (textures_) pig = scene_.materials.pigmentAt(m, p);
    const double alpha = 1.0 - pig.filter - pig.transmit;

    povcolour::FloatColour lit = povcolour::ambient(pig.rgb, f.ambient, scene_.globals.ambientLight, f.emission, alpha);
    // Shadow answers found beforehand for this hit by tracePacket (only for a primary hit).
    const int known = std::exchange(knownRay_, -1);
    // The cells found above answer the shadow segments from p, with no second lookup (see
    // shadowFactor); nested shading, after this loop, finds its own.
    pointCells_ = pointCellsFirst_ && known < 0;
    pointShadowOrigin_.reset();
    levelOneShadows_ = level == 1;
    const povcolour::WideColour pigment = povcolour::widened(povcolour::rounded(pig.rgb));  // for every light
    for (size_t j = 0; j < scene_.lights.size(); ++j) {
      const KnownLight kl = known >= 0 ? known_[j].at(known) : KnownLight{};
      lit = lit + lightContribution(scene_.lights[j], s, pig, pigment, alpha, ray, sp, n, inside,
                                    known >= 0 ? &kl : nullptr);
    }
    pointCells_ = false;

    // What the surface passes on is added to its own light in POV-Ray's float colours
    // (render/pov_secondary.h): the transmitted share first, then the reflected one.
    povcolour::FloatColour result = lit;
    const double cosI = -dot(ray.dir, n);
    bool totalInternal = false;
    povcolour::Reflectivity rho{};
    if constexpr ((E & kReflection) != 0) {
      if (s.reflective) {
        rho = povcolour::reflectivity(f.reflection, cosI, fresnelIor(object, inside));
        if (f.reflection.metallic != 0)
          rho.colour = povcolour::metallicReflection(rho.colour, f.reflection.metallic, cosI,
                                                     povcolour::toColor(povcolour::rounded(pig.rgb)));
      }
    }
    if constexpr ((E & kTransmission) != 0) {
      if (!m.opaque && (pig.filter != 0 || pig.transmit != 0))
        result =
            result + transmit(ray, hit.t, object, s, pig, rho.colour, sp, n, level, weight, inside, totalInternal, known);
    }
    if constexpr ((E & kReflection) != 0) {
      const Color reflec = povcolour::toColor(rho.colour);
      if (s.reflective && !totalInternal && !reflec.isBlack()) {
        const double w = rayWeight(weight * rho.weightFactor);
        if (level < scene_.globals.maxTraceLevel && w >= scene_.globals.adcBailout) {
          ++stats_.reflectedRays;
          const Color c = traceSpawned(spawnRay(sp, n, mirror(ray.dir, n), scene_.tol.minDepth), level, w, inside,
                                       known, mirrorAhead_);
          povcolour::FloatColour reflected = povcolour::rounded(c);
          // Reflect_Exp is the float 1/exponent, raised to on the float colour as it is: a
          // negative channel gives pow()'s answer (NaN unless the power is whole), not 0.
          const float e = float(1.0 / f.reflection.exponent);
          if (e != 1.0f) reflected = {std::pow(float(c.r), e), std::pow(float(c.g), e), std::pow(float(c.b), e)};
          result = result + rho.colour * reflected;
        }
      }
    }
    return povcolour::toColor(result);
  }

  // tracePacket's per-hit set-up (hit point, normal, shadow origin) for packet rays k0 ..
  // k0+3 at once, when all four hit untransformed spheres or all four planes; false, with
  // nothing done, otherwise. Each lane does the operations of sphereHitPoint or
  // planeHitPoint, the normal, its flip and shadowSegmentOrigin in their order: the same bits.
  bool setUpFour(const Ray* rays, int k0) {
    using namespace lanes;
    const std::optional<ClosestHit>* hits = hits_ + k0;
    if (!hits[0] || !hits[1] || !hits[2] || !hits[3]) return false;
    const Bvh& bvh = scene_.bvh;
    const SphereShape* sphere[4];
    const PlaneShape* plane[4];
    for (int i = 0; i < 4; ++i) {
      sphere[i] = bvh.sphere(hits[i]->primitive);
      plane[i] = sphere[i] ? nullptr : bvh.plane(hits[i]->primitive);
    }
    const bool spheres = sphere[0] && sphere[1] && sphere[2] && sphere[3];
    if (!spheres && !(plane[0] && plane[1] && plane[2] && plane[3])) return false;
    auto gather = [](auto&& f) { return set(f(0), f(1), f(2), f(3)); };
    const Double4 t = gather([&](int i) { return hits[i]->hit.t; });
    const Double4 dx = gather([&](int i) { return rays[k0 + i].dir.x; });
    const Double4 dy = gather([&](int i) { return rays[k0 + i].dir.y; });
    const Double4 dz = gather([&](int i) { return rays[k0 + i].dir.z; });
    // Ray::at: origin + dir * t.
    const Double4 px = gather([&](int i) { return rays[k0 + i].origin.x; }) + dx * t;
    const Double4 py = gather([&](int i) { return rays[k0 + i].origin.y; }) + dy * t;
    const Double4 pz = gather([&](int i) { return rays[k0 + i].origin.z; }) + dz * t;
    Double4 qx, qy, qz, ex, ey, ez, nx, ny, nz;
    if (spheres) {
      const Double4 cx = gather([&](int i) { return sphere[i]->center.x; });
      const Double4 cy = gather([&](int i) { return sphere[i]->center.y; });
      const Double4 cz = gather([&](int i) { return sphere[i]->center.z; });
      const Double4 r = gather([&](int i) { return sphere[i]->radius; });
      const Double4 vx = px - cx, vy = py - cy, vz = pz - cz;
      const Double4 len = lanes::sqrt(vx * vx + vy * vy + vz * vz);
      if (less(splat(0.0), len) != 0xFu) return false;  // a point at a centre: the scalar code's case
      const Double4 scale = r / len;
      qx = cx + vx * scale, qy = cy + vy * scale, qz = cz + vz * scale;
      const Double4 g6 = splat(errorGamma(6));
      ex = (abs(qx - cx) + abs(qx)) * g6, ey = (abs(qy - cy) + abs(qy)) * g6, ez = (abs(qz - cz) + abs(qz)) * g6;
      const Double4 inv = splat(1.0) / r;
      nx = vx * inv, ny = vy * inv, nz = vz * inv;
    } else {
      nx = gather([&](int i) { return plane[i]->normal.x; });
      ny = gather([&](int i) { return plane[i]->normal.y; });
      nz = gather([&](int i) { return plane[i]->normal.z; });
      const Double4 d = gather([&](int i) { return plane[i]->distance; });
      const Double4 ax = nx * d, ay = ny * d, az = nz * d;
      const Double4 along = nx * (px - ax) + ny * (py - ay) + nz * (pz - az);
      qx = px - nx * along, qy = py - ny * along, qz = pz - nz * along;
      const Double4 g8 = splat(errorGamma(8));
      ex = (abs(qx) + abs(ax)) * g8, ey = (abs(qy) + abs(ay)) * g8, ez = (abs(qz) + abs(az)) * g8;
    }
    // hitPointNear: the hit point is POV-Ray's, bounded by its distance from q.
    const Double4 g2 = splat(1 + errorGamma(2));
    ex = (abs(px - qx) + ex) * g2, ey = (abs(py - qy) + ey) * g2, ez = (abs(pz - qz) + ez) * g2;
    // Every surface is shaded on the side the ray sees.
    const unsigned away = less(splat(0.0), nx * dx + ny * dy + nz * dz);
    const Double4 flip = splat(-1.0);  // -x exactly, zeros included
    nx = select(away, nx * flip, nx), ny = select(away, ny * flip, ny), nz = select(away, nz * flip, nz);
    double qs[3][4], es[3][4], ns[3][4], error[4];
    store(qs[0], px), store(qs[1], py), store(qs[2], pz);
    store(es[0], ex), store(es[1], ey), store(es[2], ez);
    store(ns[0], nx), store(ns[1], ny), store(ns[2], nz);
    store(error, lanes::sqrt(ex * ex + ey * ey + ez * ez));
    if constexpr ((E & kShadows) != 0) {
      // shadowSegmentOrigin: the hit point below the slab limit, else offsetRayOrigin along n.
      const Double4 shift = abs(nx) * ex + abs(ny) * ey + abs(nz) * ez;
      const unsigned thin = less(shift, splat(shadowSlabLimit_));
      double off[3][4], o[3][4];
      store(off[0], nx * shift), store(off[1], ny * shift), store(off[2], nz * shift);
      store(o[0], px + nx * shift), store(o[1], py + ny * shift), store(o[2], pz + nz * shift);
      double* origin[3] = {shadowX_ + k0, shadowY_ + k0, shadowZ_ + k0};
      for (int i = 0; i < 4; ++i) {
        for (int a = 0; a < 3; ++a) {
          const double v = o[a][i];
          origin[a][i] = (thin >> i & 1u)  ? qs[a][i]
                         : off[a][i] > 0 ? nextUp(v)
                         : off[a][i] < 0 ? nextDown(v)
                                         : v;
        }
      }
    }
    for (int i = 0; i < 4; ++i) {
      const int k = k0 + i;
      points_[k] = {{qs[0][i], qs[1][i], qs[2][i]}, {es[0][i], es[1][i], es[2][i]}};
      normals_[k] = {ns[0][i], ns[1][i], ns[2][i]};
      px_[k] = qs[0][i], py_[k] = qs[1][i], pz_[k] = qs[2][i];
      nx_[k] = ns[0][i], ny_[k] = ns[1][i], nz_[k] = ns[2][i];
      pointError_[k] = error[i];
    }
    return true;
  }

  // MaterialTable::checkerAt for packet hits k0 .. k0+3 at once, when all four materials are
  // one checker in world space: bit i of `second` is set where lane i gets the checker's
  // second colour. False, leaving pigments to pigmentAt, otherwise.
  bool fourChecker(const Material* const* m, int k0, unsigned& second) const {
    if (!textures_) return false;
    using namespace lanes;
    for (int i = 0; i < 4; ++i)
      if (m[i]->checker < 0 || m[i]->checker != m[0]->checker) return false;
    if (scene_.materials.checker(*m[0]).worldToPattern) return false;
    const Double4 eps = splat(kPovEpsilon);
    const Double4 k = lanes::floor(load(px_ + k0) + eps) + lanes::floor(load(py_ + k0) + eps) +
                      lanes::floor(load(pz_ + k0) + eps);
    const Double4 half = abs(k) * splat(0.5);
    second = ~(equal(half, lanes::floor(half)) & less(half, splat(INFINITY))) & 0xFu;
    return true;
  }

  // Whether shadeAt would give a hit of this surface no more than its ambient term and its
  // lights' diffuse and highlight terms: no mirror, no brilliance or metallic tint, and no
  // spotlight, fading or area light in the scene. (Its pigment must also let nothing through.)
  bool plainSurface(const Surface& s) const {
    if constexpr ((E & kAreaLights) != 0) return false;
    if (lightShaping_) return false;
    if constexpr ((E & kReflection) != 0) {
      if (s.reflective) return false;
    }
    return s.finish.brilliance == 1 && (!s.highlights || s.finish.metallic == 0);
  }

  // shadeAt for packet rays k0 .. k0+3 at once, when all four hit plain surfaces (above) of
  // one Surface and every shadow answer they need is Clear or Blocked; false, with nothing
  // done, otherwise. Each lane does shadeAt's operations in shadeAt's order (a light that
  // gives nothing adds zeros, as there), so out[] gets the same bits and the counters the
  // same counts.
  bool shadeFour(const Ray* rays, int k0, Color* out) {
    using namespace lanes;
    const std::optional<ClosestHit>* hits = hits_ + k0;
    if (!hits[0] || !hits[1] || !hits[2] || !hits[3]) return false;
    const Material* m[4];
    for (int i = 0; i < 4; ++i) m[i] = &scene_.materials[scene_.bvh.material(hits[i]->primitive)];
    const Surface& s = scene_.materials.surface(*m[0]);
    for (int i = 1; i < 4; ++i)
      if (m[i]->surface != m[0]->surface) return false;
    if (!plainSurface(s)) return false;
    const size_t lights = scene_.lights.size();
    if constexpr ((E & kShadows) != 0) {
      for (size_t j = 0; j < lights; ++j) {
        if (scene_.lights[j].shadowless) continue;
        const PacketLight& pl = known_[j];
        for (int i = 0; i < 4; ++i)
          if (pl.isLit(k0 + i) && pl.occlusion[k0 + i] == uint8_t(Occlusion::Transparent)) return false;
      }
    }
    const FinishDesc& f = s.finish;
    // Initialised from the materials at once: default-constructed, these arrays were zeroed
    // first (a rep stos that took 8% of this function).
    FilterColor pig[4] = {m[0]->color, m[1]->color, m[2]->color, m[3]->color};
    double alpha[4];
    povcolour::FloatColour lit[4];  // each lane's colour: its ambient, then each light's term added
    povcolour::WideColour pigment[4];  // each lane's pigment rounded to floats, for every light
    unsigned secondColour = 0;  // lanes on a checker's second colour, when fourChecker() found them
    const bool checkered = fourChecker(m, k0, secondColour);
    for (int i = 0; i < 4; ++i) {
      if (textures_) {
        if (checkered) {
          if (secondColour >> i & 1u) pig[i] = scene_.materials.checker(*m[i]).color2;
        } else {
          pig[i] = scene_.materials.pigmentAt(*m[i], points_[k0 + i].p);
        }
      }
      if constexpr ((E & kTransmission) != 0) {
        if (!m[i]->opaque && (pig[i].filter != 0 || pig[i].transmit != 0)) return false;
      }
      alpha[i] = 1.0 - pig[i].filter - pig[i].transmit;
      lit[i] = povcolour::ambient(pig[i].rgb, f.ambient, scene_.globals.ambientLight, f.emission, alpha[i]);
      pigment[i] = povcolour::widened(povcolour::rounded(pig[i].rgb));
    }
    stats_.shadingOps += 4;
    // diffuse x attenuation, POV-Ray's inner product of the diffuse intensity, is the same
    // for every light: formed once.
    const bool diffuses = f.diffuse > 0;
    const lanes::Double4 diffuseAlpha =
        lanes::splat(f.diffuse) * lanes::set(alpha[0], alpha[1], alpha[2], alpha[3]);
    for (size_t j = 0; j < lights; ++j) {
      const Light& light = scene_.lights[j];
      const PacketLight& pl = known_[j];
      // lightContribution: nothing unless lit (which holds dot(n, l) >= kPovEpsilon).
      unsigned gives = unsigned(pl.lit >> k0) & 0xFu;
      const Color& intensity = light.color;
      if constexpr ((E & kShadows) != 0) {
        if (!light.shadowless && gives != 0) {
          stats_.shadowRays += uint64_t(__builtin_popcount(gives));
          for (int i = 0; i < 4; ++i)
            if (pl.occlusion[k0 + i] == uint8_t(Occlusion::Blocked)) gives &= ~(1u << i);
          // A clear segment leaves the intensity as it is (times 1): nothing when that is dark.
          if (std::fabs(intensity.r) < kPovEpsilon && std::fabs(intensity.g) < kPovEpsilon &&
              std::fabs(intensity.b) < kPovEpsilon)
            gives = 0;
        }
      }
      if (gives == 0) continue;
      // POV-Ray's float colour operations, lane by lane as lightContribution does them; the
      // light's colour rounded and widened once for the four.
      const povcolour::FloatColour lightColour = povcolour::rounded(intensity);
      const povcolour::WideColour lightWide = povcolour::widened(lightColour);
      // The four lanes' cos x (diffuse x attenuation), each lane lightContribution's operations.
      double intensities[4];
      if (diffuses) {
        using namespace lanes;
        const Double4 nl = load(nx_ + k0) * load(pl.dirX + k0) + load(ny_ + k0) * load(pl.dirY + k0) +
                           load(nz_ + k0) * load(pl.dirZ + k0);
        store(intensities, nl * diffuseAlpha);
      }
      bool phong = false, specular = false;
      if constexpr ((E & kHighlights) != 0) {
        phong = s.highlights && !light.shadowless && f.phong > 0;
        specular = s.highlights && !light.shadowless && f.specular > 0;
      }
      for (int i = 0; i < 4; ++i) {
        if (!(gives >> i & 1u)) continue;
        const int k = k0 + i;
        povcolour::FloatColour c;
        if (diffuses) c = povcolour::diffuse(pigment[i], intensities[i], lightColour);
        if (phong || specular) {
          const Vec3 l{pl.dirX[k], pl.dirY[k], pl.dirZ[k]};
          if (phong) c = c + highlight(lightWide, shading::phong(f, rays[k].dir, normals_[k], l));
          if (specular)
            c = c + highlight(lightWide, shading::specular(f, s.specularExponent, rays[k].dir, normals_[k], l));
        }
        lit[i] = lit[i] + c;
      }
    }
    for (int i = 0; i < 4; ++i) out[k0 + i] = povcolour::toColor(lit[i]);
    return true;
  }

  // Finds the light-buffer cells that the shadow segments from p will read, all lights' at
  // once, so that their lookups (two divisions each) overlap instead of each waiting at the
  // head of its segment's query; in a big scene also starts fetching them, so that their
  // cache misses overlap too. A light behind the surface (normal n) gets none (-1): it has no
  // segment (and a segment without a cell would find its own).
  void findShadowCells(const Vec3& p, const Vec3& n) {
    const size_t lights = std::min(scene_.lights.size(), scene_.lightBuffers.size());
    cells_.resize(lights);
    for (size_t j = 0; j < lights; ++j) {
      const Vec3 fromLight = p - scene_.lights[j].location;
      cells_[j] = dot(n, fromLight) >= 0 ? -1 : scene_.lightBuffers[j].cellIndexOf(fromLight);
      if (scene_.prefetchLightBuffers) scene_.lightBuffers[j].prefetchCell(cells_[j]);
    }
    if (scene_.prefetchLightBuffers)
      for (size_t j = 0; j < lights; ++j) scene_.lightBuffers[j].prefetchList(cells_[j]);
  }

  // Light j's buffer, when it has one that was built.
  const LightBuffer* bufferOf(size_t j) const {
    return j < scene_.lightBuffers.size() && scene_.lightBuffers[j].valid() ? &scene_.lightBuffers[j] : nullptr;
  }
  // Whether a shadow segment that starts `shift` off its surface point (along the direction
  // from that point to the light) stays within LightBuffer::kMargin of the light's ray, so
  // that the light's buffer may answer it; and how far from the light it then reaches, for a
  // point `dist` from the light.
  static double servesBound(double shadowTolerance) { return 0.5 * LightBuffer::kMargin * shadowTolerance; }
  bool bufferServes(double shift) const { return shift <= servesBound(scene_.tol.shadow); }
  // bufferServes(length(v)), decided without the square root (core/square_bound.h).
  bool bufferServesOffset(const Vec3& v) const { return dot(v, v) <= servesSquared_; }
  static double bufferReach(double dist, double shift) { return (dist + shift) * (1 + 1e-9); }

  // ComputeReflection: d + n * (-2 d.n), normalised by VNormalizeEq (times 1/length).
  static Vec3 mirror(const Vec3& d, const Vec3& n) {
    const Vec3 r = d + n * (-2.0 * dot(d, n));
    return r * (1.0 / length(r));
  }

  double iorOf(uint32_t object) const { return scene_.materials.surface(scene_.materials[object]).interior.ior; }

  // n_to / n_from at the surface of `object`, for the fresnel reflectivity. POV-Ray's
  // ComputeRelativeIOR: when leaving an object that is nested in another it divides the
  // innermost interior's ior by the object's own, which gives 1; we match that.
  // Interior::IOR is a float in POV-Ray, so the ratio of two objects' iors is a float
  // division; with the atmosphere's (a double 1.0) it is a double one.
  static double iorRatio(double a, double b) { return double(float(a) / float(b)); }
  double fresnelIor(uint32_t object, const InteriorList& inside) const {
    if (inside.count == 0) return iorOf(object) / 1.0;
    const double back = iorOf(inside.ids[inside.count - 1]);
    if (inside.find(object) >= 0) return inside.count == 1 ? 1.0 / iorOf(object) : iorRatio(back, iorOf(object));
    return iorRatio(iorOf(object), back);
  }

  // n_from / n_to for a ray refracted at the surface of `object`, as POV-Ray's
  // ComputeRefraction forms it (nested objects count as outside their container; the
  // overlap of two objects belongs to the one entered last).
  double refractionEta(uint32_t object, const InteriorList& inside) const {
    if (inside.count == 0) return 1.0 / iorOf(object);
    const uint32_t back = inside.ids[inside.count - 1];
    if (back == object)
      return inside.count == 1 ? iorOf(object) / 1.0 : iorRatio(iorOf(object), iorOf(inside.ids[inside.count - 2]));
    if (inside.find(object) >= 0) return 1.0;
    return iorRatio(iorOf(back), iorOf(object));
  }

  // Light leaving an object through this surface has crossed its interior for `depth`;
  // POV-Ray fades only that transmitted share, not the surface's own shading.
  // In POV-Ray's float colours (ComputeLightedTexture): fade x transmitted x filter.
  povcolour::FloatColour transmit(const Ray& ray, double depth, uint32_t object, const Surface& s,
                                  const FilterColor& pig, const povcolour::FloatColour& rho, const SurfacePoint& sp,
                                  const Vec3& n, int level, double weight, const InteriorList& inside,
                                  bool& totalInternal, int lane) {
    povcolour::FloatColour filter = povcolour::transmittedFilter(pig);
    if (s.finish.conserveEnergy) filter = povcolour::conserved(filter, rho);
    const double tau = std::min(1.0, std::fabs(povcolour::greyscale(filter)));
    if (tau <= scene_.globals.adcBailout) return {};
    const Color wideFilter = povcolour::toColor(filter);
    const double w =
        rayWeight(weight * std::max({std::fabs(wideFilter.r), std::fabs(wideFilter.g), std::fabs(wideFilter.b)}));

    InteriorList next = inside;
    const int at = next.find(object);
    if (at >= 0) next.remove(at); else next.push(object);
    povcolour::FloatColour fade{1.0f, 1.0f, 1.0f};
    if (at >= 0) {
      const InteriorDesc& in = s.interior;
      if (std::fabs(in.fadeDistance) > kPovEpsilon) fade = povcolour::interiorFade(in, depth);
    }

    const double eta = refractionEta(object, inside);
    Ray passing;
    const Passage how = passage(ray, sp, n, eta, passing);
    // A ray at the last level or below the bailout goes no further, bent or not: POV-Ray's
    // TraceRay checks both on entry, a continued ray's level too (it only does not count one
    // more). Total internal reflection is found first (TraceRefractionRay), so a mirror ray
    // refused this way still takes the surface's own reflection's place.
    if (level >= scene_.globals.maxTraceLevel || w < scene_.globals.adcBailout) {
      totalInternal = how == Passage::Reflected;
      return {};
    }
    switch (how) {
      case Passage::Straight: {
        // POV-Ray does not spend a trace level on it.
        ++stats_.transmittedRays;
        const Color c = traceSpawned(passing, level - 1, w, next, lane, throughAhead_);
        return fade * povcolour::rounded(c) * filter;
      }
      case Passage::Reflected: {
        // Total internal reflection: the transmitted share comes back as a mirror ray,
        // not tinted by the filter, and replaces the ordinary reflection.
        totalInternal = true;
        ++stats_.reflectedRays;
        const Color c = traceSpawned(passing, level, w, inside, lane, mirrorAhead_);
        return fade * povcolour::rounded(c);
      }
      case Passage::Bent: break;
    }
    ++stats_.refractedRays;
    const Color c = traceSpawned(passing, level, w, next, lane, throughAhead_);
    return fade * povcolour::rounded(c) * filter;
  }

  // The shadow segments toward light j of the packet's hits, those that lightContribution
  // will ask for, answered before any is shaded; the results land in known_.
  void resolveShadows(int count, size_t j) {
    const Light& light = scene_.lights[j];
    if (light.shadowless) return;
    PacketLight& pl = known_[j];
    pl.noted = 0;
    if constexpr ((E & kAreaLights) != 0) {
      if (light.area) {  // sampled per hit, as before
        std::fill(pl.occlusion, pl.occlusion + count, kUnknown);
        return;
      }
    }
    const double tol = scene_.tol.shadow;
    // In a big scene each segment is answered from the light's buffer (as shadowFactor would
    // answer it); in a small one (Scene::packetShadowsFromBuffers) all of them together: from
    // the list of the buffer's cell when they all lie in one, else by one walk of the tree.
    // Only the lit rays have a segment: lightContribution stops before the shadow ray of the
    // others (misses, and the lanes past `count`, are never lit).
    uint64_t live = pl.lit;
    const LightBuffer* buffer = bufferOf(j);
    if (buffer && scene_.packetShadowsFromBuffers) {
      for (uint64_t b = live & served_; b != 0; b &= b - 1) {
        const int k = __builtin_ctzll(b);
        pl.occlusion[k] = uint8_t(scene_.bvh.occlusionToLight(
            *buffer, Ray{shadowOrigin(k), {pl.dirX[k], pl.dirY[k], pl.dirZ[k]}}, tol, pl.dist[k] - tol,
            bufferReach(pl.dist[k], shadowShift_[k]), stats_.intersectionTests, blocker_[k]));
      }
      live &= ~served_;
    }
    if (live == 0) return applyShadowCache(count, pl);
    // The segments segmentTransmittance() would trace, in the rays' own lanes: the others'
    // origins are NaN, which the packet's bounds leave out, and they end before they start.
    // Beside them, the range of their directions and the farthest reach from the light, for
    // a cell of the light's buffer that would hold them all.
    using namespace lanes;
    segments_.count = count;
    segments_.groups = (count + 3) / 4;
    const Double4 none = splat(NAN), tolerance = splat(tol), nowhere = splat(-INFINITY), widen = splat(1 + 1e-9);
    Double4 lo[3] = {splat(INFINITY), splat(INFINITY), splat(INFINITY)}, hi[3] = {nowhere, nowhere, nowhere};
    Double4 reach = nowhere;
    for (int k = 0; k < 4 * segments_.groups; k += 4) {
      const unsigned in = unsigned(live >> k) & 0xFu;
      const Double4 dist = load(pl.dist + k);
      const Double4 dir[3] = {load(pl.dirX + k), load(pl.dirY + k), load(pl.dirZ + k)};
      store(segments_.ox + k, select(in, load(shadowX_ + k), none));
      store(segments_.oy + k, select(in, load(shadowY_ + k), none));
      store(segments_.oz + k, select(in, load(shadowZ_ + k), none));
      store(segments_.dx + k, dir[0]);
      store(segments_.dy + k, dir[1]);
      store(segments_.dz + k, dir[2]);
      store(segmentEnd_ + k, select(in, dist - tolerance, nowhere));
      if (buffer) {  // lit lanes have finite directions (their dot with the normal passed a test)
        for (int a = 0; a < 3; ++a) {
          const Double4 d = select(in, dir[a], none);
          lo[a] = minOr(d, lo[a]);  // a NaN lane keeps what it had
          hi[a] = maxOr(d, hi[a]);
        }
        reach = maxOr(select(in, (dist + load(shadowShift_ + k)) * widen, nowhere), reach);
      }
    }
    // The cells list directions from the light: the negated range of the segments'.
    const int cell = buffer && (live & ~served_) == 0
                         ? buffer->commonCell({-highest(hi[0]), -highest(hi[1]), -highest(hi[2])},
                                              {-lowest(lo[0]), -lowest(lo[1]), -lowest(lo[2])})
                         : -1;
    if (cell >= 0)
      scene_.bvh.occlusionPacketInCell(*buffer, cell, highest(reach), segments_, segmentEnd_, tol, live,
                                       occlusion_, blocker_, stats_.intersectionTests, &pl.nearest);
    else
      scene_.bvh.occlusionPacket(light.location, segments_, segmentEnd_, tol, live, occlusion_, blocker_,
                                 stats_.intersectionTests, &pl.nearest);
    // Every segment tested here has its see-through walk's first step noted (and, with a
    // common cell, that cell is its direction's: commonCell holds every direction of the box).
    pl.noted = live;
    pl.cell = cell;
    for (uint64_t b = live; b != 0; b &= b - 1) {
      const int k = __builtin_ctzll(b);
      pl.occlusion[k] = uint8_t(occlusion_[k]);
    }
    applyShadowCache(count, pl);
  }

  // POV-Ray's shadow cache for the packet's (level-1) hits, in ray order, as
  // segmentTransmittance() does it: a ray tries the opaque object that last blocked this
  // light first, over [MIN_ISECT_DEPTH, dist); only where that misses does the full test's
  // answer count, and its opaque blocker becomes the cached object. The cache goes on from
  // the packet before unless ray 0 starts a pixel (pixelStarts_), and is left for the next.
  // (Across pixels POV-Ray's cache depends on the order its threads took the tiles; the
  // plain kernel starts every pixel empty, the adaptive one every block.)
  void applyShadowCache(int count, PacketLight& pl) {
    const size_t j = size_t(&pl - known_.data());
    uint32_t& levelOne = cacheEntry(j, true);
    uint32_t deeper = cacheEntry(j, false);  // no deeper ray of this packet has been traced yet
    for (int k = 0; k < count; ++k) {
      if ((pixelStarts_ >> k) & 1) levelOne = deeper = kNoCache;
      if (!((pl.lit >> k) & 1)) continue;
      const uint32_t cached = levelOne != kNoCache ? levelOne : deeper;
      const bool blocked = Occlusion(pl.occlusion[k]) == Occlusion::Blocked;
      if (cached != kNoCache && !(blocked && blocker_[k] == cached)) {
        if (scene_.bvh.objectHit(cached, Ray{shadowOrigin(k), {pl.dirX[k], pl.dirY[k], pl.dirZ[k]}},
                                 scene_.tol.minDepth, pl.dist[k], stats_.intersectionTests)) {
          pl.occlusion[k] = uint8_t(Occlusion::Blocked);
          continue;
        }
      }
      if (blocked) levelOne = blocker_[k];
    }
  }

  // How far each hit's shadow origin lies from its point (length(), lane by lane), and in
  // served_ the lanes whose segments the light buffers may answer (bufferServes).
  void measureShadowShifts(int padded, uint64_t hitBits) {
    using namespace lanes;
    const Double4 limit = splat(0.5 * LightBuffer::kMargin * scene_.tol.shadow);
    served_ = 0;
    for (int k = 0; k < padded; k += 4) {
      if (((hitBits >> k) & 0xFu) == 0) {  // misses' origins are zeros, as their points
        store(shadowShift_ + k, splat(0.0));
        served_ |= uint64_t(0xFu) << k;
        continue;
      }
      const Double4 x = load(shadowX_ + k) - load(px_ + k), y = load(shadowY_ + k) - load(py_ + k),
                    z = load(shadowZ_ + k) - load(pz_ + k);
      const Double4 shift = lanes::sqrt(x * x + y * y + z * z);
      store(shadowShift_ + k, shift);
      served_ |= uint64_t(lessEqual(shift, limit)) << k;
    }
  }

  // A Phong or specular term h of one light: intensity x h, the light colour tinted first
  // where metallic (ComputeSpecularColour: only Metallic > 0), rounded as POV-Ray's float
  // colour is.
  // `wide` is `light` rounded to floats and widened (povcolour::widened).
  static povcolour::FloatColour highlight(const FinishDesc& f, const povcolour::FloatColour& light,
                                          const povcolour::WideColour& wide, double h, double nl,
                                          const Color& pigment) {
    if (!(h > 0)) return {};
    if (!(f.metallic > 0)) return povcolour::highlight(wide, h);
    return povcolour::metallicHighlight(light, h, f.metallic, nl, povcolour::rounded(pigment));
  }
  // The same without a metallic tint (shadeFour's plain surfaces).
  static povcolour::FloatColour highlight(const povcolour::WideColour& wide, double h) {
    return h > 0 ? povcolour::highlight(wide, h) : povcolour::FloatColour{};
  }

  // `pigment` is pig.rgb rounded to floats and widened, once for all the point's lights.
  povcolour::FloatColour lightContribution(const Light& light, const Surface& s, const FilterColor& pig,
                                           const povcolour::WideColour& pigment, double alpha, const Ray& ray,
                                           const SurfacePoint& sp, const Vec3& n, const InteriorList& inside,
                                           const KnownLight* known) {
    const Vec3& p = sp.p;
    cacheSlot_ = size_t(&light - scene_.lights.data());
    Vec3 l;
    double dist;
    if (known) {
      // Not lit: the light is at the point or behind the surface; both give nothing below.
      if (!known->lit) return {};
      l = known->dir;
      dist = known->dist;
    } else {
      const Vec3 toLight = light.location - p;
      dist = length(toLight);
      if (!(dist > length(sp.error))) return {};  // a light at the point itself has no direction
      l = toLight * (1.0 / dist);  // POV-Ray's VInverseScaleEq: times the reciprocal
    }
    Color intensity = light.color;
    if (lightShaping_) {
      const double a = light.attenuation(l, dist);
      if (a == 0) return {};
      intensity *= a;
    }
    const double nl = dot(n, l);
    if (nl < kPovEpsilon) return {};  // lights behind the surface give nothing at all
    if constexpr ((E & kShadows) != 0) {
      if (!light.shadowless) {
        intensity = intensity * shadowFactor(light, sp, n, l, dist, inside, known);
        // POV-Ray's test is on the absolute values: a negative light (or a negative transmit
        // on the way) still shines, darkening what it lights.
        if (std::fabs(intensity.r) < kPovEpsilon && std::fabs(intensity.g) < kPovEpsilon &&
            std::fabs(intensity.b) < kPovEpsilon)
          return {};
      }
    }
    const FinishDesc& f = s.finish;
    // POV-Ray's float colour operations, term by term (render/pov_colour.h).
    const povcolour::FloatColour lightColour = povcolour::rounded(intensity);
    const povcolour::WideColour lightWide = povcolour::widened(lightColour);
    povcolour::FloatColour c;
    if (f.diffuse > 0) {
      const double k = f.brilliance == 1 ? nl : std::pow(nl, f.brilliance);
      c = povcolour::diffuse(pigment, k * (f.diffuse * alpha), lightColour);
    }
    if constexpr ((E & kHighlights) != 0) {
      if (s.highlights && !light.shadowless) {
        if (f.phong > 0) c = c + highlight(f, lightColour, lightWide, shading::phong(f, ray.dir, n, l), nl, pig.rgb);
        if (f.specular > 0)
          c = c + highlight(f, lightColour, lightWide, shading::specular(f, s.specularExponent, ray.dir, n, l), nl,
                            pig.rgb);
      }
    }
    return c;
  }

  // Fraction of the light (per channel) that reaches p: 0 behind an opaque object, the
  // product of the filter colours of every transparent surface crossed otherwise.
  // `inside` lists the interiors the shadow ray starts in (those of the ray being shaded).
  // `knownLight`, when given, is what tracePacket found of the segment (its occlusion, when
  // not kUnknown).
  // The segments start at sp's point, or at the error-bounded origin above it (shadowSegmentOrigin).
  Color shadowFactor(const Light& light, const SurfacePoint& sp, const Vec3& n, const Vec3& l, double dist,
                     const InteriorList& inside, const KnownLight* knownLight) {
    const uint8_t known = knownLight ? knownLight->occlusion : kUnknown;
    if (known != kUnknown) {
      ++stats_.shadowRays;
      switch (Occlusion(known)) {
        case Occlusion::Clear: return Color(1.0);
        case Occlusion::Blocked: return {};
        case Occlusion::Transparent: break;
      }
    }
    // Every segment of this point leaves on the side n points to (lightContribution asks
    // dot(n, l) >= kPovEpsilon first), so every light's starts at the same origin, found once.
    if (!pointShadowOrigin_) {
      const Vec3 origin = shadowSegmentOrigin(sp, n, shadowSlabLimit_);
      pointShadowOrigin_ = {origin, length(origin - sp.p)};
    }
    const Vec3 p = pointShadowOrigin_->p;
    if constexpr ((E & kAreaLights) != 0) {
      if (light.area) return areaShadow(light, p, l, inside);
    }
    const size_t j = size_t(&light - scene_.lights.data());
    if (known != kUnknown)
      return orderedTransmittance(p, l, dist, inside, bufferOf(j), knownLight->cell, knownLight->nearest);
    // The segment runs from p, a hair off the surface point, along the direction from the
    // surface point to the light: within kMargin of the light's ray when that hair is small
    // against the tolerance kept from the light (it always is but for absurd coordinates).
    // That ray's cell is the one shadeAt found for its prefetch, from the light toward the
    // surface point (the direction -l but for the rounding of l), when it found one.
    const double shift = pointShadowOrigin_->shift;
    if (const LightBuffer* buffer = bufferOf(j); buffer && bufferServes(shift))
      return segmentTransmittance(p, l, dist, inside, buffer, shift,
                                  pointCells_ && j < cells_.size() ? cells_[j] : -1);
    return segmentTransmittance(p, l, dist, inside);
  }

  // `buffer`, when given, is the light buffer of the light the segment ends at, and `shift`
  // how far the segment's origin is from the point at `dist` from the light; `cell`, when
  // not -1, the buffer's cell of the direction from the light to that point.
  Color segmentTransmittance(const Vec3& origin, const Vec3& dir, double dist, const InteriorList& inside,
                             const LightBuffer* buffer = nullptr, double shift = 0, int cell = -1) {
    ++stats_.shadowRays;
    // Else the cell of the segment's own direction, looked up once for both queries below
    // (a see-through walk's steps all share that direction); without one, the tree.
    if (buffer && cell < 0 && (cell = buffer->cellIndexOf(-dir)) < 0) buffer = nullptr;
    const Ray segment{origin, dir};
    if (blockedByCachedObject(segment, dist)) return {};
    // Most segments are either clear or blocked by something opaque: an unordered
    // query settles those; only see-through objects need the ordered walk below.
    // From the buffer, a see-through answer comes with the walk's first crossing.
    const double tol = scene_.tol.shadow;
    uint32_t blocker = 0;
    ClosestHit first;
    // From the buffer, it also lists the walk's candidates for its first step (orderedTransmittance).
    const Occlusion found =
        buffer ? scene_.bvh.occlusionToLight(*buffer, cell, segment, tol, dist - tol, bufferReach(dist, shift),
                                             stats_.intersectionTests, blocker, first, dist, LightBuffer::kMargin * tol,
                                             shadowCandidates_)
               : scene_.bvh.occlusion(segment, tol, dist - tol, stats_.intersectionTests, blocker);
    return transmittanceAfter(found, blocker, origin, dir, dist, inside, buffer, cell, buffer ? &first : nullptr,
                              buffer != nullptr);
  }

  // POV-Ray's shadow cache: the object that last blocked this light is tried first.
  bool blockedByCachedObject(const Ray& segment, double dist) {
    const uint32_t cached = cachedBlocker(cacheSlot_, levelOneShadows_);
    if (cached == kNoCache) return false;
    // TracePointLightShadowRay tries the cached object over [MIN_ISECT_DEPTH, depth),
    // not the full test's (SHADOW_TOLERANCE, depth - SHADOW_TOLERANCE): in a crease it
    // still finds the wall that the full test passes over; and a cached mesh is tried whole,
    // so a smooth mesh's shadow ray can be stopped by the neighbouring triangle there.
    return scene_.bvh.objectHit(cached, segment, scene_.tol.minDepth, dist, stats_.intersectionTests);
  }

  // What a segment that the cached object left open lets through, given the full test's
  // answer (`blocker`: the opaque object it found).
  Color transmittanceAfter(Occlusion found, uint32_t blocker, const Vec3& origin, const Vec3& dir, double dist,
                           const InteriorList& inside, const LightBuffer* buffer = nullptr, int cell = -1,
                           const ClosestHit* first = nullptr, bool listed = false) {
    switch (found) {
      case Occlusion::Clear: return Color(1.0);
      case Occlusion::Blocked: cacheEntry(cacheSlot_, levelOneShadows_) = blocker; return {};  // tried first next time
      case Occlusion::Transparent: break;
    }
    return orderedTransmittance(origin, dir, dist, inside, buffer, cell, first, listed);
  }

  // The product of the filters of every surface the segment crosses, nearest first, or
  // nothing as soon as one is opaque. Each crossing is found from the one before (POV-Ray
  // starts each step's ray there). `buffer`, when given, is the light's buffer: while the
  // steps stay close enough to the light's ray for its cell to list everything they can
  // meet (see bufferServes), they are answered from the few primitives of that list that
  // the line can reach (Bvh::shadowCandidates, listed at the first such step) instead of
  // by walks of the tree. `cell`, when not -1, is the buffer's cell of -dir (or of a
  // direction a few ulps off it). `first`, when given, is the first step's answer, found
  // by the segment's shadow query (Bvh::occlusionToLight, or a packet's PacketNearest).
  // `firstListed`: shadowCandidates_ holds the first step's candidates, listed by that query
  // from `cell` for this segment (over its query's reach, which holds the walk's).
  Color orderedTransmittance(Vec3 origin, const Vec3& dir, double dist, InteriorList inside,
                             const LightBuffer* buffer = nullptr, int cell = -1, const ClosestHit* first = nullptr,
                             bool firstListed = false) {
    const double tol = scene_.tol.shadow;
    // Every step that bufferServes lets through starts within this of the light's ray, so
    // within twice this of the first such step's line.
    const double drift = LightBuffer::kMargin * tol;
    bool listed = false;
    Color k(1.0);
    for (;; firstListed = false) {
      const Ray step{origin, dir};
      bool serves = false;
      if (buffer) {
        const Vec3 fromLight = origin - buffer->light();
        serves = bufferServesOffset(cross(fromLight, dir));
        if (serves && !listed && firstListed) {
          listed = true;
        } else if (serves && !listed) {
          const double reach = length(fromLight) * (1 + 1e-9);
          if (cell >= 0) {
            scene_.bvh.shadowCandidates(*buffer, cell, step, dist, reach, drift, shadowCandidates_);
            listed = true;
          } else {
            listed = scene_.bvh.shadowCandidates(*buffer, step, dist, reach, drift, shadowCandidates_);
          }
          if (!listed) buffer = nullptr, serves = false;  // no cell for this direction: the tree it is
        }
      }
      const std::optional<ClosestHit> found =
          first    ? *first
          : serves ? scene_.bvh.closestAmong(shadowCandidates_, step, tol, dist - tol, stats_.intersectionTests)
                   : scene_.bvh.closest(step, tol, dist - tol, stats_.intersectionTests, /*skipNoShadow=*/true);
      first = nullptr;
      if (!found) return k;
      if constexpr ((E & kTransmission) == 0) {
        return {};
      } else {
        const uint32_t object = scene_.bvh.object(found->primitive);
        const Material& m = scene_.materials[scene_.bvh.material(found->primitive)];
        if (m.opaque) return {};
        const double t = found->hit.t;
        origin = origin + dir * t;
        FilterColor pig = m.color;
        if (textures_) pig = scene_.materials.pigmentAt(m, origin);
        if (std::fabs(pig.filter) + std::fabs(pig.transmit) < scene_.globals.adcBailout) return {};
        k *= pig.rgb * pig.filter + Color(pig.transmit);
        // Leaving a fading interior: the light crossed it for t (POV-Ray fades shadow rays
        // only when fade_power > 0).
        const int at = inside.find(object);
        if (at >= 0) {
          const InteriorDesc& in = scene_.materials.surface(m).interior;
          if (in.fadePower > 0 && std::fabs(in.fadeDistance) > kPovEpsilon) k *= shading::interiorFade(in, t);
          inside.remove(at);
        } else {
          inside.push(object);
        }
        dist -= t;
      }
    }
  }

  // Sample (i, j)'s segment from p, as segmentTransmittance takes it, with the full test's
  // answer when traceSamples found it.
  Color sampleShadow(const Light& light, const Vec3& p, const Vec3& l, int i, int j, const InteriorList& inside) {
    const AreaSegment& s = areaSegment(light, p, l, i, j);
    if (s.found == kUnknown) return segmentTransmittance(p, s.dir, s.dist, inside);
    ++stats_.shadowRays;
    if (blockedByCachedObject(Ray{p, s.dir}, s.dist)) return {};
    const size_t k = size_t(j) * light.size1 + i;
    return transmittanceAfter(Occlusion(s.found), s.blocker, p, s.dir, s.dist, inside, nullptr, -1,
                              s.found == uint8_t(Occlusion::Transparent) ? &areaNearest_[k] : nullptr);
  }

  const AreaSegment& areaSegment(const Light& light, const Vec3& p, const Vec3& l, int i, int j) {
    AreaSegment& s = areaSegments_[size_t(j) * light.size1 + i];
    if (!s.made) {
      const Vec3 d = (light.grid.empty() ? light.areaSample(i, j, l) : light.grid[size_t(j) * light.size1 + i]) - p;
      s.dist = length(d);
      s.dir = d * (1.0 / s.dist);  // POV-Ray's VInverseScaleEq: times the reciprocal
      s.made = true;
    }
    return s;
  }

  // POV-Ray's recursive area-light sampling over the index rectangle [i0,i1] x [j0,j1]:
  // corners are shadow-tested (each sample once), rectangles larger than 2x2 are split at
  // the floor/ceil of their midpoint and averaged, which gives POV-Ray's non-uniform
  // sample weights (1/4, 1/2, 1/4 for three samples).
  Color areaShadow(const Light& light, const Vec3& p, const Vec3& l, const InteriorList& inside) {
    const size_t samples = size_t(light.size1) * light.size2;
    cache_.assign(samples, Color(-1.0));
    areaSegments_.assign(samples, AreaSegment{});
    areaInside_ = &inside;
    const int is[2] = {0, light.size1 - 1}, js[2] = {0, light.size2 - 1};
    traceSamples(light, p, l, is, 2, js, 2);
    return areaRect(light, p, l, 0, light.size1 - 1, 0, light.size2 - 1, 0);
  }

  // The full shadow tests of the samples (is[a], js[b]) not tested yet, together: their
  // segments share the origin p, so one walk of the tree serves them all and a leaf's
  // spheres are tested against four segments at a time. Each gets the answer its own query
  // would give; the shadow cache is applied afterwards, sample by sample in POV-Ray's order.
  void traceSamples(const Light& light, const Vec3& p, const Vec3& l, const int* is, int ni, const int* js,
                    int nj) {
    static_assert(kMaxPacket >= 16, "the corners of four quarters in one packet");
    int at[16];
    int n = 0;
    for (int b = 0; b < nj; ++b) {
      for (int a = 0; a < ni; ++a) {
        const int k = js[b] * light.size1 + is[a];
        if (areaSegments_[k].found != kUnknown || cache_[k].r >= 0 || std::find(at, at + n, k) != at + n)
          continue;
        at[n++] = k;
      }
    }
    if (n < 2) return;  // a lone segment goes its own way
    if (!light.grid.empty()) {
      // Four segments' square roots and reciprocals at once, each lane length()'s and
      // areaSegment()'s operations in their order (a segment made alone would wait on its own).
      using namespace lanes;
      for (int g = 0; g < n; g += 4) {
        alignas(32) double q[3][4];
        for (int c = 0; c < 4; ++c) {
          const Vec3& v = light.grid[size_t(at[std::min(g + c, n - 1)])];
          q[0][c] = v.x, q[1][c] = v.y, q[2][c] = v.z;
        }
        const Double4 dx = load(q[0]) - splat(p.x), dy = load(q[1]) - splat(p.y), dz = load(q[2]) - splat(p.z);
        const Double4 dist = lanes::sqrt(dx * dx + dy * dy + dz * dz);
        alignas(32) double ox[4], oy[4], oz[4], od[4];
        const Double4 inv = splat(1.0) / dist;
        store(ox, dx * inv), store(oy, dy * inv), store(oz, dz * inv), store(od, dist);
        for (int c = 0; c < 4 && g + c < n; ++c) {
          AreaSegment& s = areaSegments_[at[g + c]];
          s.dir = {ox[c], oy[c], oz[c]};
          s.dist = od[c];
          s.made = true;
        }
      }
    }
    for (int m = 0; m < n; ++m) {
      const AreaSegment& s = areaSegment(light, p, l, at[m] % light.size1, at[m] / light.size1);
      segments_.set(m, p, s.dir);
      segmentEnd_[m] = s.dist - scene_.tol.shadow;
    }
    segments_.finish(n);
    for (int k = n; k < segments_.groups * 4; ++k) segmentEnd_[k] = -INFINITY;
    scene_.bvh.occlusionPacketFromPoint(segments_, segmentEnd_, scene_.tol.shadow, (uint64_t(1) << n) - 1,
                                        occlusion_, blocker_, stats_.intersectionTests, &nearest_);
    if (areaNearest_.size() < areaSegments_.size()) areaNearest_.resize(areaSegments_.size());
    for (int m = 0; m < n; ++m) {
      areaSegments_[at[m]].found = uint8_t(occlusion_[m]);
      areaSegments_[at[m]].blocker = blocker_[m];
      if (occlusion_[m] == Occlusion::Transparent) areaNearest_[at[m]] = nearest_.hit[m];
    }
  }

  Color cachedSample(const Light& light, const Vec3& p, const Vec3& l, int i, int j) {
    Color& c = cache_[size_t(j) * light.size1 + i];
    if (c.r < 0) c = sampleShadow(light, p, l, i, j, *areaInside_);
    return c;
  }

  Color areaRect(const Light& light, const Vec3& p, const Vec3& l, int i0, int i1, int j0, int j1, int depth) {
    const Color c00 = cachedSample(light, p, l, i0, j0), c10 = cachedSample(light, p, l, i1, j0);
    const Color c01 = cachedSample(light, p, l, i0, j1), c11 = cachedSample(light, p, l, i1, j1);
    auto differ = [&](const Color& a, const Color& b) {
      const Color d = (a - b) * light.color;
      return std::fabs(d.r) + std::fabs(d.g) + std::fabs(d.b) > 0.1;
    };
    if ((i1 - i0 > 1 || j1 - j0 > 1) &&
        (depth < light.adaptive || differ(c00, c10) || differ(c10, c11) || differ(c11, c01) || differ(c01, c00))) {
      const int ia = (i0 + i1) / 2, ib = (i0 + i1 + 1) / 2;
      const int ja = (j0 + j1) / 2, jb = (j0 + j1 + 1) / 2;
      // Every corner of the four quarters is tested below: those not tested yet go together.
      const int is[4] = {i0, ia, ib, i1}, js[4] = {j0, ja, jb, j1};
      traceSamples(light, p, l, is, 4, js, 4);
      Color sum = areaRect(light, p, l, i0, ia, j0, ja, depth + 1);
      sum += areaRect(light, p, l, ib, i1, j0, ja, depth + 1);
      sum += areaRect(light, p, l, i0, ia, jb, j1, depth + 1);
      sum += areaRect(light, p, l, ib, i1, jb, j1, depth + 1);
      return sum * 0.25;
    }
    return (c00 + c10 + c01 + c11) * 0.25;
  }

  const Scene& scene_;
  RenderStats& stats_;
  double servesSquared_;  // the largest squared offset whose length bufferServes lets through
  double shadowSlabLimit_;  // shadow segments start at the hit point below this slab (render/spawn.h)
  bool pointCellsFirst_;    // whether shadeAt finds its point's light-buffer cells first (any buffer)
  // The effects the kernel is not compiled for (effects.h): branches that shading takes or
  // not for the whole render, as cheap as a template argument and a quarter of the kernels.
  bool textures_;           // patterned pigments: pigmentAt instead of the material's colour
  bool lightShaping_;       // spotlights or fading lights: each light's attenuation
  static constexpr uint32_t kNoCache = ~0u;
  // tracePacket's working arrays, kept here so that no pixel pays for initialising them.
  std::optional<ClosestHit> hits_[kMaxPacket];
  SurfacePoint points_[kMaxPacket];
  Vec3 normals_[kMaxPacket];
  // Where every shadow segment of a hit starts.
  alignas(32) double shadowX_[kMaxPacket], shadowY_[kMaxPacket], shadowZ_[kMaxPacket];
  Vec3 shadowOrigin(int k) const { return {shadowX_[k], shadowY_[k], shadowZ_[k]}; }
  void setShadowOrigin(int k, const Vec3& o) { shadowX_[k] = o.x, shadowY_[k] = o.y, shadowZ_[k] = o.z; }
  alignas(32) double px_[kMaxPacket], py_[kMaxPacket], pz_[kMaxPacket];
  alignas(32) double nx_[kMaxPacket], ny_[kMaxPacket], nz_[kMaxPacket];
  alignas(32) double pointError_[kMaxPacket];
  alignas(32) double shadowShift_[kMaxPacket];  // measureShadowShifts
  uint64_t served_ = 0;                         // measureShadowShifts: a bit per lane
  PacketRays segments_;
  alignas(32) double segmentEnd_[kMaxPacket];
  Occlusion occlusion_[kMaxPacket];
  uint32_t blocker_[kMaxPacket];
  uint64_t pixelStarts_ = 1;
  std::vector<PacketLight> known_;  // one per light
  std::vector<int> cells_;          // findShadowCells: each light's cell for the point
  bool pointCells_ = false;          // whether cells_ are those of the point shadeAt's light loop shades
  // The shadow segments' origin above the point shadeAt's light loop shades, and its
  // distance from the point, once shadowFactor has found them.
  struct ShadowOrigin {
    Vec3 p;
    double shift;
  };
  std::optional<ShadowOrigin> pointShadowOrigin_;
  std::vector<uint32_t> shadowCandidates_;  // orderedTransmittance: what its steps may meet
  int knownRay_ = -1;               // the packet ray whose hit is shaded next, if any
  // POV-Ray's two shadow caches per light (TracePointLightShadowRay): the first half for
  // the shadow tests of hits at trace level 1 (lightSourceLevel1ShadowCache), the second for
  // deeper ones (lightSourceOtherShadowCache); see cachedBlocker.
  std::vector<uint32_t> shadowCache_ = std::vector<uint32_t>(2 * (scene_.lights.size() + 1), kNoCache);
  size_t cacheSlot_ = 0;  // the light being tested (area-light samples share its slot)
  bool levelOneShadows_ = true;  // whether the shadow tests being made are of a level-1 hit
  std::vector<Color> cache_;
  const InteriorList* areaInside_ = nullptr;  // interiors the current area-light samples start in
  std::vector<AreaSegment> areaSegments_;  // the current point's, one per sample of the light
  // The see-through samples' nearest hits (their walks' first steps), as traceSamples found them.
  std::vector<ClosestHit> areaNearest_;
  PacketNearest nearest_;  // traceSamples' query's notes
  SpawnedAhead mirrorAhead_, throughAhead_;  // traceSpawnedAhead's
};

}  // namespace pvrt
