// Volumes against analytic values: a constant-density slab's transmittance exp(-sigma x thickness) seen by camera,
// shadow, mirror-reflected and refracted rays, a surface inside a volume attenuated by the part in front of it,
// trilinear interpolation of a linear field, early ray termination as a truncation, and bad input (NaN scalars, zero
// spacing, a single-point axis) skipped with a message and never a NaN pixel.
#include "shading/integrator.h"
#include "scenes/scenes.h"
#include "scenes/stiff_scenes.h"
#include "shading/integrator_test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace whitted;
using namespace whitted::integrator_test;

namespace {

constexpr float kOpacity = 0.3f;      // opacity per unit distance
constexpr double kUnit = 0.5;         // ScalarOpacityUnitDistance
const double kSigma = -std::log(1.0 - double(kOpacity)) / kUnit;  // extinction per world unit

/// A box lo..hi of constant scalar 1 (2 x 2 x 2 points), opacity kOpacity per kUnit, colour c.
Volume slab(const Vec3& lo, const Vec3& hi, Color c = Color(0.0f), double step = 0.3) {
  Volume v;
  const int dims[3] = {2, 2, 2};
  const float ones[8] = {1, 1, 1, 1, 1, 1, 1, 1};
  v.grid = VolumeGrid::fromScalars(dims, ones);
  v.grid.origin = lo;
  v.grid.spacing = hi - lo;
  v.transfer.opacityX = {0.0f, 2.0f};
  v.transfer.opacityY = {kOpacity, kOpacity};
  v.transfer.colorX = {0.0f};
  v.transfer.colorY = {c};
  v.transfer.unitDistance = kUnit;
  v.sampleDistance = step;  // does not divide the thicknesses below: the last step is a partial one
  return v;
}

Sample traceOne(const Scene& s, const Ray& r, RayStats& st, IntegratorSettings is = IntegratorSettings()) {
  Integrator integ(s, is, Vec3(0, 1, 0));
  return integ.trace(r, st, s.background);
}

void expectClean(const RayStats& st) {
  EXPECT_EQ(st.safetyNetCatches(), 0u);
  EXPECT_EQ(st.volumeInvalidSamples, 0u);
  EXPECT_EQ(st.volumeTerminated, 0u);
}

}  // namespace

TEST(Volume, TrilinearReproducesLinearField) {
  const int dims[3] = {5, 4, 3};
  std::vector<double> data;
  auto f = [](double i, double j, double k) { return 2.0 * i - 3.0 * j + 0.5 * k + 1.0; };
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i) data.push_back(f(i, j, k));
  Volume v;
  v.grid = VolumeGrid::fromScalars(dims, data.data());
  v.grid.spacing = Vec3(0.5, 2.0, 1.5);
  std::size_t invalid = 1;
  ASSERT_EQ(v.prepare(invalid), "");
  EXPECT_EQ(invalid, 0u);
  for (int n = 0; n < 200; ++n) {
    const Vec3 p(std::fmod(n * 0.6180339, 4.0), std::fmod(n * 0.4142135, 3.0), std::fmod(n * 0.7320508, 2.0));
    EXPECT_NEAR(v.sample(p), f(p.x, p.y, p.z), 1e-5) << p.x << " " << p.y << " " << p.z;
  }
  // Nearest: the closest point's value
  v.interpolation = VolumeInterpolation::Nearest;
  EXPECT_FLOAT_EQ(v.sample(Vec3(1.4, 2.6, 0.2)), float(f(1, 3, 0)));
}

TEST(Volume, BoundsFollowDirectionAndSpacing) {
  Volume v = slab(Vec3(0.0), Vec3(1.0));
  v.grid.spacing = Vec3(2.0, 3.0, 4.0);
  v.grid.direction = Mat3(Vec3(0, 1, 0), Vec3(-1, 0, 0), Vec3(0, 0, 1));  // columns: x axis -> +y, y axis -> -x
  v.grid.origin = Vec3(1.0, 1.0, 1.0);
  std::size_t invalid = 0;
  ASSERT_EQ(v.prepare(invalid), "");
  EXPECT_NEAR(v.bounds().lo.x, -2.0, 1e-12);
  EXPECT_NEAR(v.bounds().hi.y, 3.0, 1e-12);
  EXPECT_NEAR(v.bounds().hi.z, 5.0, 1e-12);
}

TEST(Volume, SlabTransmittanceIsExpSigmaThickness) {
  for (double thickness : {0.7, 2.05}) {
    for (double angle : {0.0, 0.6}) {
      Scene s;
      s.addVolume(slab(Vec3(-10, -10, 0), Vec3(10, 10, thickness)));
      s.background = Color(1.0f);
      const CommitStats cs = s.commit();
      EXPECT_EQ(cs.invalidVolumes + cs.invalidVoxels, 0u);
      ASSERT_TRUE(s.features().volumes);
      RayStats st;
      const Ray r = ray(Vec3(0, 0, -3), Vec3(std::sin(angle), 0, std::cos(angle)));
      const Sample smp = traceOne(s, r, st);
      const double expected = std::exp(-kSigma * thickness / std::cos(angle));
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(smp.color[c], expected, 1e-3) << thickness << " " << angle;
      EXPECT_GT(st.volumeSamples, 0u);
      expectClean(st);
      // With the screen's background left to what is drawn behind, the volume is the coverage
      s.backgroundAlpha = 0.0f;
      s.commit();
      RayStats st2;
      EXPECT_NEAR(traceOne(s, r, st2).alpha, 1.0 - expected, 1e-3);
    }
  }
}

TEST(Volume, EmissionAddsColourTimesOpacity) {
  const Color c(0.9f, 0.4f, 0.1f);
  Scene s;
  s.addVolume(slab(Vec3(-10, -10, 0), Vec3(10, 10, 1.3), c, 0.01));
  s.background = Color(0.2f, 0.5f, 1.0f);
  s.commit();
  RayStats st;
  const Sample smp = traceOne(s, ray(Vec3(0, 0, -3), Vec3(0, 0, 1)), st);
  const double T = std::exp(-kSigma * 1.3);
  // Constant colour: front-to-back compositing telescopes to c (1 - T) exactly, whatever the step
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(smp.color[k], c[k] * (1.0 - T) + T * s.background[k], 1e-3);
  expectClean(st);
}

TEST(Volume, SurfaceInsideIsAttenuatedByTheVolumeInFront) {
  const Color c(0.2f, 0.8f, 0.5f), wall(1.0f, 0.6f, 0.3f);
  Scene s;
  s.addVolume(slab(Vec3(-10, -10, 0), Vec3(10, 10, 3.0), c));
  // An unlit wall at z = 1.1 inside the volume: 1.1 of it in front, 1.9 behind (unseen)
  addObject(s, makeGrid(Vec3(-10, -10, 1.1), Vec3(20, 0, 0), Vec3(0, 20, 0), 1, 1), unlit(wall));
  s.background = Color(0.0f);
  s.commit();
  RayStats st;
  const Sample smp = traceOne(s, ray(Vec3(0, 0, -3), Vec3(0, 0, 1)), st);
  const double T = std::exp(-kSigma * 1.1);
  EXPECT_TRUE(smp.hit);
  EXPECT_NEAR(smp.firstHit.z, 1.1, 1e-9);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(smp.color[k], c[k] * (1.0 - T) + T * wall[k], 1e-3);
  EXPECT_NEAR(smp.alpha, 1.0f, 1e-6f);
  expectClean(st);
}

TEST(Volume, ShadowThroughSlabDarkensFloorByTransmittance) {
  const double thickness = 1.7;
  auto floorColour = [&](bool withVolume, double* shadowT) {
    Scene s;
    Material m;
    m.diffuseColor = Color(1.0f);
    addObject(s, makeGrid(Vec3(-10, 0, 10), Vec3(20, 0, 0), Vec3(0, 0, -20), 1, 1), m);
    // Slab above the floor; the camera ray stays below it
    if (withVolume) s.addVolume(slab(Vec3(-5, 1, -5), Vec3(5, 1 + thickness, 5), Color(1.0f)));
    Light l;
    l.position = Vec3(0, 1, 0);
    l.focalPoint = Vec3(0, 0, 0);  // straight down
    s.lights().push_back(l);
    s.commit();
    Ray up = ray(Vec3(0, 0, 0), Vec3(0, 1, 0));
    *shadowT = s.transmittance(up, 0.0f)[0];
    RayStats st;
    const Sample smp = traceOne(s, ray(Vec3(0, 0.5, -3), Vec3(0, -0.5, 3)), st);
    expectClean(st);
    return smp.color;
  };
  double tNone = 0.0, tVol = 0.0;
  const Color lit = floorColour(false, &tNone), shaded = floorColour(true, &tVol);
  const double expected = std::exp(-kSigma * thickness);
  EXPECT_NEAR(tNone, 1.0, 1e-12);
  EXPECT_NEAR(tVol, expected, 1e-3);
  ASSERT_GT(lit[0], 0.5f);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(shaded[k] / lit[k], expected, 1e-3);
}

TEST(Volume, MirrorShowsTheSameTransmittance) {
  const double thickness = 0.9;
  Scene s;
  Material mirror;
  mirror.opacity = 0.0f;  // no local colour: only the reflected ray
  mirror.reflectance = Color(1.0f);
  addObject(s, makeGrid(Vec3(-10, 0, 10), Vec3(20, 0, 0), Vec3(0, 0, -20), 1, 1), mirror);
  // Slab z in [3, 3 + thickness], above the mirror: the camera ray (z < 0) misses it, the reflected ray crosses it
  s.addVolume(slab(Vec3(-5, 0.5, 3), Vec3(5, 30, 3 + thickness)));
  s.background = Color(1.0f);
  s.commit();
  RayStats st;
  const Sample smp = traceOne(s, ray(Vec3(0, 5, -5), Vec3(0, -1, 1)), st);
  const double expected = std::exp(-kSigma * thickness * std::sqrt(2.0));
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(smp.color[k], expected, 1e-3);
  EXPECT_EQ(st.reflection, 1u);
  expectClean(st);
}

TEST(Volume, RefractedRaySeesTheSameTransmittance) {
  // A glass slab (IOR 1.5) in front of the volume: a ray leaves it parallel to itself (shifted), so it crosses the
  // volume slab over the same length as without the glass
  const double thickness = 1.2, angle = 0.5;
  Scene s;
  addObject(s, makeBoxMesh(Vec3(-50, -50, -2), Vec3(50, 50, -1)), glassMaterial(1.5f));
  s.addVolume(slab(Vec3(-50, -50, 1), Vec3(50, 50, 1 + thickness)));
  s.background = Color(1.0f);
  s.commit();
  RayStats st;
  const Sample smp = traceOne(s, ray(Vec3(0, 0, -5), Vec3(std::sin(angle), 0, std::cos(angle))), st);
  const double expected = std::exp(-kSigma * thickness / std::cos(angle));
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(smp.color[k], expected, 1e-3);
  EXPECT_GE(st.refraction, 2u);
  expectClean(st);
}

TEST(Volume, EarlyTerminationIsATruncation) {
  Scene s;
  Volume dense = slab(Vec3(-10, -10, 0), Vec3(10, 10, 50), Color(0.5f));
  s.addVolume(std::move(dense));
  s.background = Color(1.0f);
  s.commit();
  RayStats st;
  const Sample smp = traceOne(s, ray(Vec3(0, 0, -3), Vec3(0, 0, 1)), st);
  EXPECT_EQ(st.volumeTerminated, 1u);
  EXPECT_GT(smp.truncationBound, 0.0f);
  EXPECT_LE(smp.truncationBound, 1.0f / 255.0f + 1e-6f);
  // What was left out is within the bound: the exact value is 0.5 (1 - T) + T, T = exp(-50 sigma) ~ 0
  EXPECT_NEAR(smp.color[0], 0.5, smp.truncationBound + 1e-4);
  // Without the threshold the whole volume is marched
  IntegratorSettings exact;
  exact.contributionThreshold = 0.0f;
  RayStats st2;
  traceOne(s, ray(Vec3(0, 0, -3), Vec3(0, 0, 1)), st2, exact);
  EXPECT_EQ(st2.volumeTerminated, 0u);
  EXPECT_GT(st2.volumeSamples, st.volumeSamples);
}

TEST(Volume, NanScalarsAreTransparentAndCounted) {
  Scene s;
  Volume v = slab(Vec3(-10, -10, 0), Vec3(10, 10, 1.0), Color(1.0f));
  for (float& x : v.grid.scalars) x = std::numeric_limits<float>::quiet_NaN();
  v.grid.scalars[0] = std::numeric_limits<float>::infinity();
  s.addVolume(std::move(v));
  s.background = Color(0.25f);
  const CommitStats cs = s.commit();
  EXPECT_EQ(cs.invalidVoxels, 8u);
  EXPECT_EQ(cs.invalidVolumes, 0u);
  RayStats st;
  const Sample smp = traceOne(s, ray(Vec3(0, 0, -3), Vec3(0, 0, 1)), st);
  for (int k = 0; k < 3; ++k) EXPECT_FLOAT_EQ(smp.color[k], 0.25f);  // transparent
  EXPECT_GT(st.volumeInvalidSamples, 0u);
  EXPECT_EQ(st.volumeInvalidSamples, st.volumeSamples);
  EXPECT_EQ(st.nonFiniteSamples, 0u);
}

TEST(Volume, BadGridsAreSkippedWithAMessage) {
  struct Case {
    const char* what;
    void (*edit)(Volume&);
    const char* message;
  };
  const Case cases[] = {
      {"zero spacing", [](Volume& v) { v.grid.spacing.y = 0.0; }, "spacing along y"},
      {"NaN spacing", [](Volume& v) { v.grid.spacing.x = std::nan(""); }, "spacing along x"},
      {"one point along z",
       [](Volume& v) {
         v.grid.dims[2] = 1;
         v.grid.scalars.resize(4);
       },
       "single point along z"},
      {"too few scalars", [](Volume& v) { v.grid.scalars.resize(5); }, "5 scalars for 8 points"},
      {"2^24 + 1 points along x (single-precision sample points)",
       [](Volume& v) { v.grid.dims[0] = Volume::kMaxPointsPerAxis + 1; }, "more than 2^24 points along x"},
      {"singular direction", [](Volume& v) { v.grid.direction[2] = v.grid.direction[0]; }, "singular"},
      {"zero unit distance", [](Volume& v) { v.transfer.unitDistance = 0.0; }, "unit distance"},
  };
  for (const Case& c : cases) {
    Scene s;
    Volume v = slab(Vec3(-10, -10, 0), Vec3(10, 10, 1.0), Color(1.0f));
    c.edit(v);
    const uint32_t id = s.addVolume(std::move(v));
    addObject(s, makeGrid(Vec3(-10, -10, 5), Vec3(20, 0, 0), Vec3(0, 20, 0), 1, 1), unlit(Color(0.75f)));
    const CommitStats cs = s.commit();
    EXPECT_EQ(cs.invalidVolumes, 1u) << c.what;
    EXPECT_NE(s.volumeError(id).find(c.message), std::string::npos) << c.what << ": " << s.volumeError(id);
    EXPECT_FALSE(s.features().volumes) << c.what;
    EXPECT_EQ(s.stats().volumes, 0u) << c.what;
    RayStats st;
    const Sample smp = traceOne(s, ray(Vec3(0, 0, -3), Vec3(0, 0, 1)), st);
    for (int k = 0; k < 3; ++k) EXPECT_FLOAT_EQ(smp.color[k], 0.75f) << c.what << ": the rest of the scene renders";
    EXPECT_EQ(st.safetyNetCatches(), 0u) << c.what;
  }
}

TEST(Volume, SceneWithoutVolumesUsesNoVolumeKernel) {
  Scene s;
  addObject(s, makeGrid(Vec3(-10, -10, 5), Vec3(20, 0, 0), Vec3(0, 20, 0), 1, 1), unlit(Color(0.75f)));
  const uint32_t id = s.addVolume(slab(Vec3(-10, -10, 0), Vec3(10, 10, 1.0)));
  s.commit();
  EXPECT_TRUE(s.features().volumes);
  s.removeVolume(id);
  s.commit();
  EXPECT_FALSE(s.features().volumes);
  RayStats st;
  const Sample smp = traceOne(s, ray(Vec3(0, 0, -3), Vec3(0, 0, 1)), st);
  EXPECT_FLOAT_EQ(smp.color[0], 0.75f);
  EXPECT_EQ(st.volumeSamples, 0u);
  EXPECT_NEAR(s.bounds().lo.z, 5.0, 1e-12) << "a removed volume leaves the scene bounds";
}
