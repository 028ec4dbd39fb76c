// Safety-net tests: each net counts what it catches in the frame statistics and the report, catches nothing on a
// valid frame, and keeps what it guards in range when fed input that trips it. The renderer's other behaviour is
// tested in renderer_test.cpp.
#include "image/renderer.h"
#include "image/report.h"
#include "scenes/scenes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

using namespace whitted;

// The safety nets count what they catch: a valid frame catches nothing; a non-finite material value smuggled in
// after commit (bypassing the sanitiser) is zeroed in every sample it reaches, never reaches a pixel, and is
// counted in the statistics and the report.
TEST(Renderer, SafetyNetsCountWhatTheyCatch) {
  Scene scene;
  CameraSpec cs;
  buildClassicScene(scene, cs);
  scene.commit();
  Camera cam = cs.make(1.0, scene.bounds());
  RenderSettings rs;
  rs.threads = 2;
  FrameBuffer fb;
  FrameStats clean = render(scene, cam, rs, 32, 32, fb);
  EXPECT_EQ(clean.rays.safetyNetCatches(), 0u);
  for (std::size_t m = 0; m < scene.materialCount(); ++m)
    scene.material(uint32_t(m)).diffuseColor = Color(std::numeric_limits<float>::quiet_NaN());
  FrameStats bad = render(scene, cam, rs, 32, 32, fb);
  EXPECT_GT(bad.rays.nonFiniteSamples, 0u);
  EXPECT_EQ(bad.rays.safetyNetCatches(), bad.rays.nonFiniteSamples);  // samples zeroed: pixels stay finite
  for (const Color4& px : fb.color)
    for (int k = 0; k < 4; ++k) EXPECT_TRUE(std::isfinite(px[k]));
  const std::string report = frameReport(bad, scene.stats(), CommitStats{}, 32, 32, 0.0, nullptr);
  EXPECT_NE(report.find(std::to_string(bad.rays.nonFiniteSamples) + " non-finite samples"), std::string::npos)
      << report;
}

// Negative controls of the other three safety nets: each is fed input that trips it (input the scene's sanitiser
// or the camera's contract would not let through) and must count it, while what it guards stays in range.
namespace {
// A quad filling the view of camera(): z = -1, seen from the origin
Scene quadScene(const Material& m, float backgroundAlpha) {
  Scene s;
  s.addInstance(s.addMesh(makeGrid(Vec3(-50, -50, -1), Vec3(100, 0, 0), Vec3(0, 100, 0), 1, 1)), Mat4(1.0),
                s.addMaterial(m));
  s.backgroundAlpha = backgroundAlpha;
  s.commit();
  return s;
}
Camera quadCamera() { return Camera::perspective(Vec3(0), Vec3(0, 0, -1), Vec3(0, 1, 0), 40.0, 1.0, 0.1, 10.0); }
void expectInRange(const FrameBuffer& fb) {
  for (std::size_t i = 0; i < fb.color.size(); ++i) {
    for (int k = 0; k < 4; ++k) ASSERT_TRUE(std::isfinite(fb.color[i][k])) << i;
    ASSERT_GE(fb.color[i].a, 0.0f) << i;
    ASSERT_LE(fb.color[i].a, 1.0f) << i;
    ASSERT_GE(fb.depth[i], 0.0f) << i;
    ASSERT_LE(fb.depth[i], 1.0f) << i;
  }
}
}  // namespace

// clampedAlpha: a transmittance of 2 (the sanitiser caps kr + kt at 1) smuggled in after commit lets a straight
// path escape with weight 2, so coverage 1 - 2 < 0 must be clamped and counted.
TEST(Renderer, SafetyNetClampedAlphaTripsOnTransmittanceAboveOne) {
  Material m;
  m.opacity = 0.5f;
  m.transmittance = Color(0.5f);  // transmissive at commit, so the refraction kernel is compiled in
  Scene s = quadScene(m, 0.0f);
  RenderSettings rs;
  rs.threads = 1;
  FrameBuffer fb;
  const FrameStats clean = render(s, quadCamera(), rs, 8, 8, fb);
  EXPECT_EQ(clean.rays.safetyNetCatches(), 0u);
  s.material(0).transmittance = Color(2.0f);
  const FrameStats bad = render(s, quadCamera(), rs, 8, 8, fb);
  EXPECT_EQ(bad.rays.clampedAlpha, 64u);
  EXPECT_EQ(bad.rays.safetyNetCatches(), bad.rays.clampedAlpha);
  expectInRange(fb);
}

// clampedDepth: a "camera" whose near plane lies behind the eye (near < 0; vtkCamera requires near > 0) maps
// every point between near and far but off the planes outside [-1, 1] in NDC: the hit's depth must be clamped
// and counted, per sample.
TEST(Renderer, SafetyNetClampedDepthTripsOnNearPlaneBehindTheEye) {
  Scene s = quadScene(Material{}, 1.0f);
  RenderSettings rs;
  rs.threads = 1;
  FrameBuffer fb;
  EXPECT_EQ(render(s, quadCamera(), rs, 8, 8, fb).rays.safetyNetCatches(), 0u);
  const Camera bad = Camera::perspective(Vec3(0), Vec3(0, 0, -1), Vec3(0, 1, 0), 40.0, 1.0, -0.5, 10.0);
  for (int spp : {1, 4}) {
    rs.samplesPerPixel = spp;
    const FrameStats fs = render(s, bad, rs, 8, 8, fb);
    EXPECT_EQ(fs.rays.clampedDepth, 64u * spp);
    EXPECT_EQ(fs.rays.safetyNetCatches(), fs.rays.clampedDepth);
    expectInRange(fb);
  }
}

// nonFinitePixels: a background of 3e38 (the sanitiser caps colours far below) smuggled in after commit gives
// finite samples whose sum over two samples overflows to infinity: the pixel must be zeroed and counted, the
// samples not.
TEST(Renderer, SafetyNetNonFinitePixelsTripsOnOverflowingSum) {
  Scene s;
  s.commit();
  RenderSettings rs;
  rs.threads = 1;
  rs.samplesPerPixel = 2;
  FrameBuffer fb;
  EXPECT_EQ(render(s, quadCamera(), rs, 8, 8, fb).rays.safetyNetCatches(), 0u);
  s.background = Color(3e38f);
  const FrameStats fs = render(s, quadCamera(), rs, 8, 8, fb);
  EXPECT_EQ(fs.rays.nonFinitePixels, 64u);
  EXPECT_EQ(fs.rays.nonFiniteSamples, 0u);
  EXPECT_EQ(fs.rays.safetyNetCatches(), fs.rays.nonFinitePixels);
  expectInRange(fb);
  const std::string report = frameReport(fs, s.stats(), CommitStats{}, 8, 8, 0.0, nullptr);
  EXPECT_NE(report.find("64 non-finite pixels"), std::string::npos) << report;
}
