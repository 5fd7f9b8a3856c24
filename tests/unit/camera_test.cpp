#include "render/camera.h"

#include <gtest/gtest.h>

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
