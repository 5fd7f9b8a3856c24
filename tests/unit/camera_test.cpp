#include "render/camera.h"
#include "render/camera_grid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace pvrt {
namespace {

void expectNear(const Vec3& a, const Vec3& b, double eps = 1e-12) {
  EXPECT_NEAR(a.x, b.x, eps);
  EXPECT_NEAR(a.y, b.y, eps);
  EXPECT_NEAR(a.z, b.z, eps);
}

TEST(Camera, DefaultCameraCentreRayLooksAlongZ) {
  const Camera cam{CameraDesc{}};
  // 2x2 image: pixel centres at u,v = +-1/4; the centre of the image is a pixel corner.
  const Ray r = cam.ray(1, 1, -0.5, -0.5, 2, 2);
  expectNear(r.dir, {0, 0, 1});
}

TEST(Camera, PixelCentresAndRowsFromTheTop) {
  const Camera cam{CameraDesc{}};
  const Ray r = cam.ray(0, 0, 0, 0, 4, 2);  // u = (0.5)/4 - 0.5, v = 0.5 - 0.5/2
  expectNear(r.dir, normalize(Vec3{1.33 * (0.125 - 0.5), 0.25, 1}));
}

// CreateCameraRay's operations, in its order: x + 0.5 over the width, the row counted from
// the bottom as ((height - 1) - (y - 0.5)) / height, and the direction times 1/length.
TEST(Camera, SampleArithmeticIsPovRaysBitForBit) {
  CameraDesc desc;
  desc.location = {0, 10, 0};
  desc.right = {0.05, 0, 0};
  const Camera cam{desc};
  const double dy = 0.33333333333333326;
  const Ray r = cam.ray(7, 50, 0, dy, 160, 100);
  const double x0 = (7.0 + 0.5) / 160 - 0.5;
  const double y0 = (99.0 - ((50.0 + dy) - 0.5)) / 100 - 0.5;
  const Vec3 d{0.05 * x0, y0, 1.0};
  const double inv = 1.0 / std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
  EXPECT_EQ(r.dir.x, d.x * inv);
  EXPECT_EQ(r.dir.y, d.y * inv);
  EXPECT_EQ(r.dir.z, d.z * inv);
}

// A camera looking down and along at a slant, and `n` sub-sample offsets spread over the
// pixel: the rays of the packet and grid paths are checked against ray() with these.
Camera tiltedCamera() {
  CameraDesc desc;
  desc.location = {0.3, 6.1, -14.7};
  desc.lookAt = Vec3{0.2, 1.1, 2.9};
  desc.right = {1.6, 0, 0};
  return Camera{desc};
}
std::vector<SubSample> spreadOffsets(int n) {
  std::vector<SubSample> offsets;
  for (int i = 0; i < n; ++i) offsets.push_back({-0.5 + 0.37 * i / 7.0, 0.49 - 0.051 * i});
  return offsets;
}

// The packet path computes four rays at a time; every one must be bit for bit the ray
// the one-at-a-time path gives (the determinism of every backend rests on it).
TEST(Camera, RaysOfAPixelAreExactlyItsRays) {
  const Camera cam = tiltedCamera();
  const std::vector<SubSample> offsets = spreadOffsets(19);
  std::vector<Ray> rays(offsets.size());
  for (int count : {1, 3, 4, 17, 19}) {
    cam.rays(1279, 3, offsets.data(), count, 1280, 800, rays.data());
    for (int k = 0; k < count; ++k) {
      const Ray one = cam.ray(1279, 3, offsets[size_t(k)].dx, offsets[size_t(k)].dy, 1280, 800);
      EXPECT_EQ(rays[size_t(k)].origin, one.origin);
      EXPECT_EQ(rays[size_t(k)].dir, one.dir) << "ray " << k << " of " << count;
    }
  }
}

// The kernel's rays from per-column and per-row quotients (CameraGrid) must be the bits of
// ray() too, for every count of rays a call may make, the last one to three padded.
TEST(Camera, GridRaysAreExactlyItsRays) {
  const Camera cam = tiltedCamera();
  const std::vector<SubSample> offsets = spreadOffsets(17);
  const int width = 1279, height = 801, x0 = 1200, x1 = 1279;
  CameraGrid grid(cam, offsets, x0, x1, width, height);
  std::vector<Ray> rays(4 * offsets.size());
  // Ray k of pixel x as the one-at-a-time path gives it, against `got`.
  auto check = [&](int x, int y, int k, const Ray& got) {
    const Ray one = cam.ray(x, y, offsets[size_t(k)].dx, offsets[size_t(k)].dy, width, height);
    EXPECT_EQ(got.origin, one.origin);
    EXPECT_EQ(got.dir, one.dir) << "pixel " << x << " row " << y << " ray " << k;
    EXPECT_EQ(grid.ray(x, k).dir, one.dir);
  };
  const int n = int(offsets.size());
  for (int y : {0, 3, 800}) {
    grid.setRow(y);
    for (int pixels : {1, 2, 4}) {  // whole pixels: 17, 34 and 68 rays
      const int x = x1 - pixels;
      grid.rays(x, pixels, rays.data());
      for (int i = 0; i < pixels; ++i)
        for (int k = 0; k < n; ++k) check(x + i, y, k, rays[size_t(i * n + k)]);
    }
    for (int from : {0, 5})  // part of one pixel's rays
      for (int count : {1, 2, 3, 4, 7, 12}) {
        grid.rays(x0, from, count, rays.data());
        for (int k = 0; k < count; ++k) check(x0, y, from + k, rays[size_t(k)]);
      }
  }
}

TEST(Camera, DefaultRightIsExactly133) {
  const Camera cam{CameraDesc{}};
  EXPECT_EQ(cam.right().x, 1.33);
}

TEST(Camera, AngleRescalesDirectionToTheHorizontalFieldOfView) {
  CameraDesc d;
  d.right = {2, 0, 0};
  d.angle = 90;
  const Camera cam{d};
  EXPECT_NEAR(length(cam.direction()), 1.0, 1e-12);  // |R|/(2 tan 45) = 1
  // The right edge of the image is then at 45 degrees.
  const Ray edge = cam.ray(0, 0, -0.5, 0.5, 1, 1);
  EXPECT_NEAR(edge.dir.x, -edge.dir.z, 1e-12);
}

TEST(Camera, LookAtKeepsLengthsAndUsesSky) {
  CameraDesc d;
  d.location = {0, 0, -5};
  d.lookAt = Vec3{5, 0, -5};  // look along +x
  const Camera cam{d};
  expectNear(cam.direction(), {1, 0, 0});
  expectNear(cam.right(), {0, 0, -1.33});  // sky x direction, left-handed
  expectNear(cam.up(), {0, 1, 0});
}

TEST(Camera, NegativeRightMirrorsTheImage) {
  CameraDesc d;
  d.right = {-1.33, 0, 0};
  d.lookAt = Vec3{0, 0, 1};
  const Camera cam{d};
  EXPECT_LT(cam.right().x, 0);
}

TEST(Camera, SkyRollsTheCamera) {
  CameraDesc d;
  d.sky = {1, 0, 0};
  d.lookAt = Vec3{0, 0, 1};
  const Camera cam{d};
  expectNear(cam.up(), {1, 0, 0});
}

}  // namespace
}  // namespace pvrt
