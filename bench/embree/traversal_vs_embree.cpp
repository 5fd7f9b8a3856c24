// The traversal decision, measured: the same ray workload answered by pvrt's BVH and by
// Intel Embree 3, on one thread, in one process, the two alternating.
//
// Workload: a camera ray through the centre of every pixel; from every sphere it hits, a
// shadow segment toward each light in front of the surface (the plane and shading are left
// out: only the spheres go to Embree). pvrt answers with Bvh::closest and Bvh::occlusion in
// double precision, as the renderer does. Embree gets its best case: its built-in float
// spheres (RTC_GEOMETRY_TYPE_SPHERE_POINT), a high-quality build, rtcIntersect1 and
// rtcOccluded1. Its float hits are not pvrt's exact ones, so its counts differ somewhat
// (docs/design.md says by how much, and why).
//
// Usage: bench_embree SCENE.xml [WIDTH HEIGHT RUNS]
#include <embree3/rtcore.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "render/scene.h"
#include "scene/xml_loader.h"

namespace {

using namespace pvrt;
using Clock = std::chrono::steady_clock;

double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

struct Counts {
  uint64_t sphereHits = 0, segments = 0, blocked = 0;
};

struct Hit {
  Vec3 point, normal;  // normal facing the ray
};

// The workload, for either tracer: camera rays, then the shadow segments of every sphere
// hit that `closest` reports; `occluded` answers a segment.
template <class Closest, class Occluded>
Counts traceWorkload(const Scene& scene, int width, int height, Closest&& closest, Occluded&& occluded) {
  Counts c;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const Ray ray = scene.camera.ray(x, y, 0, 0, width, height);
      Hit hit;
      if (!closest(ray, hit)) continue;
      ++c.sphereHits;
      const Vec3 origin = hit.point + hit.normal * 1e-6;
      for (const Light& light : scene.lights) {
        const Vec3 toLight = light.location - origin;
        const double dist = length(toLight);
        const Vec3 dir = toLight / dist;
        if (dot(dir, hit.normal) <= 0) continue;
        ++c.segments;
        if (occluded(Ray{origin, dir}, dist)) ++c.blocked;
      }
    }
  }
  return c;
}

class EmbreeScene {
 public:
  explicit EmbreeScene(const std::vector<Primitive>& prims) {
    device_ = rtcNewDevice(nullptr);
    scene_ = rtcNewScene(device_);
    std::vector<const SphereShape*> spheres;
    for (const Primitive& p : prims)
      if (const auto* s = std::get_if<SphereShape>(&p.shape); s && !p.transform) spheres.push_back(s);
    RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_SPHERE_POINT);
    auto* v = static_cast<float*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), spheres.size()));
    for (size_t i = 0; i < spheres.size(); ++i) {
      v[4 * i + 0] = float(spheres[i]->center.x);
      v[4 * i + 1] = float(spheres[i]->center.y);
      v[4 * i + 2] = float(spheres[i]->center.z);
      v[4 * i + 3] = float(spheres[i]->radius);
    }
    rtcCommitGeometry(g);
    rtcAttachGeometry(scene_, g);
    rtcReleaseGeometry(g);
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
    rtcCommitScene(scene_);
  }
  ~EmbreeScene() {
    rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
  }
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  bool closest(const Ray& r, Hit& hit) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh{};
    setRay(rh.ray, r, 1e7f);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene_, &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    hit.point = r.origin + r.dir * double(rh.ray.tfar);
    hit.normal = normalize(Vec3{rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z});
    if (dot(hit.normal, r.dir) > 0) hit.normal = -hit.normal;
    return true;
  }
  bool occluded(const Ray& r, double dist) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay ray{};
    setRay(ray, r, float(dist));
    rtcOccluded1(scene_, &context, &ray);
    return ray.tfar < 0;  // Embree's mark of an occluded ray
  }

 private:
  static void setRay(RTCRay& out, const Ray& r, float tfar) {
    out.org_x = float(r.origin.x), out.org_y = float(r.origin.y), out.org_z = float(r.origin.z);
    out.dir_x = float(r.dir.x), out.dir_y = float(r.dir.y), out.dir_z = float(r.dir.z);
    out.tnear = 1e-6f;
    out.tfar = tfar;
    out.mask = ~0u;
  }
  RTCDevice device_;
  RTCScene scene_;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2 && argc != 5) {
    std::fprintf(stderr, "usage: %s SCENE.xml [WIDTH HEIGHT RUNS]\n", argv[0]);
    return 2;
  }
  const int width = argc == 5 ? std::atoi(argv[2]) : 640, height = argc == 5 ? std::atoi(argv[3]) : 400;
  const int runs = argc == 5 ? std::atoi(argv[4]) : 5;
  if (width < 1 || height < 1 || runs < 1) {
    std::fprintf(stderr, "%s: WIDTH, HEIGHT and RUNS must be positive integers\n", argv[0]);
    return 2;
  }
  try {
    const Scene scene = buildScene(loadSceneFile(argv[1]));
    const double pvrtBuild = scene.bvh.stats().buildSeconds;
    auto t0 = Clock::now();
    const EmbreeScene embree(scene.bvh.primitives());
    const double embreeBuild = since(t0);

    const std::vector<Primitive>& prims = scene.bvh.primitives();
    auto pvrtClosest = [&](const Ray& r, Hit& hit) {
      uint64_t tests = 0;
      const auto found = scene.bvh.closest(r, 1e-6, 1e7, tests);
      if (!found) return false;
      const auto* sphere = std::get_if<SphereShape>(&prims[found->primitive].shape);
      if (!sphere) return false;  // the plane: left out, as it is for Embree
      hit.point = r.origin + r.dir * found->hit.t;
      hit.normal = normalize(hit.point - sphere->center);
      if (dot(hit.normal, r.dir) > 0) hit.normal = -hit.normal;
      return true;
    };
    auto pvrtOccluded = [&](const Ray& r, double dist) {
      uint64_t tests = 0;
      uint32_t blocker = 0;
      return scene.bvh.occlusion(r, 1e-6, dist, tests, blocker) == Occlusion::Blocked;
    };
    auto embreeClosest = [&](const Ray& r, Hit& hit) { return embree.closest(r, hit); };
    auto embreeOccluded = [&](const Ray& r, double dist) { return embree.occluded(r, dist); };

    std::vector<double> pvrtTimes, embreeTimes;
    Counts pc, ec;
    for (int i = 0; i < runs; ++i) {
      t0 = Clock::now();
      pc = traceWorkload(scene, width, height, pvrtClosest, pvrtOccluded);
      pvrtTimes.push_back(since(t0));
      t0 = Clock::now();
      ec = traceWorkload(scene, width, height, embreeClosest, embreeOccluded);
      embreeTimes.push_back(since(t0));
    }
    std::printf("%-8s %10s %10s %12s %12s %12s %10s\n", "tracer", "build s", "trace s", "sphere hits", "segments",
                "blocked", "Mrays/s");
    auto row = [&](const char* name, double build, const std::vector<double>& t, const Counts& c) {
      const double m = median(t);
      std::printf("%-8s %10.4f %10.4f %12lu %12lu %12lu %10.2f\n", name, build, m, (unsigned long)c.sphereHits,
                  (unsigned long)c.segments, (unsigned long)c.blocked,
                  (double(width) * height + double(c.segments)) / m / 1e6);
    };
    row("pvrt", pvrtBuild, pvrtTimes, pc);
    row("embree", embreeBuild, embreeTimes, ec);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  return 0;
}
