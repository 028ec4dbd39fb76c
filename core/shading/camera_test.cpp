// Camera tests: rays reproject to their pixels through the camera's own projection, perspective and parallel, far
// from the origin.
#include "shading/camera.h"

#include <gtest/gtest.h>

using namespace whitted;

TEST(Camera, RaysReprojectToTheirPixels) {
  for (bool parallel : {false, true}) {
    Vec3 eye(1e7 + 3.0, 2.0, -5.0), focal(1e7, 0.5, 0.0);
    Camera cam = parallel ? Camera::parallel(eye, focal, Vec3(0, 1, 0), 2.0, 1.25, 0.1, 50.0)
                          : Camera::perspective(eye, focal, Vec3(0, 1, 0), 35.0, 1.25, 0.1, 50.0);
    for (double px : {0.5, 17.25, 99.5})
      for (double py : {0.5, 40.0, 79.5}) {
        Ray r = cam.rayPixel(px, py, 100, 80);
        EXPECT_NEAR(glm::length(r.dir), 1.0, 1e-12);
        Vec3 p = r.origin + 3.0 * r.dir;
        Vec4 clip = cam.worldToClip() * Vec4(p, 1.0);
        // 1e-5 pixel: the camera sits 1e7 units from the origin, where a double has ~2e-9 absolute resolution and
        // the inverse projection amplifies it ~20x; a float pipeline would be off by whole pixels here
        EXPECT_NEAR((clip.x / clip.w * 0.5 + 0.5) * 100, px, 1e-5);
        EXPECT_NEAR((clip.y / clip.w * 0.5 + 0.5) * 80, py, 1e-5);
        EXPECT_NEAR(cam.glDepth(r.origin), 0.0, 1e-6);  // rays start on the near plane
      }
  }
}
