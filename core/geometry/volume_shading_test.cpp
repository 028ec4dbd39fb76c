// Shaded volumes (vtkVolumeProperty Shade, gradient opacity) against values computed here from the formulas: a field
// linear along the grid's x axis (trilinear interpolation reproduces it, so its central differences are exact) on a
// grid with unequal spacings and a rotated direction matrix, whose world gradient direction is worked out
// independently of the code's toIndex transpose (the normal of the planes of equal scalar).
#include "geometry/volume.h"
#include "geometry/volume_shading.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using namespace whitted;

namespace {

constexpr int kN = 24;

// s = slope (i + ySlope j) at point (i, j, k) of a kN^3 grid, spacing (1, 3, 0.5), axes turned 30 degrees about z
Volume linearField(float slope, const Color& color, float opacity, float ySlope = 1.0f) {
  const int dims[3] = {kN, kN, kN};
  std::vector<float> s;
  for (int k = 0; k < kN; ++k)
    for (int j = 0; j < kN; ++j)
      for (int i = 0; i < kN; ++i) s.push_back(slope * (float(i) + ySlope * float(j)));
  Volume v;
  v.grid = VolumeGrid::fromScalars(dims, s.data());
  v.grid.spacing = Vec3(1.0, 3.0, 0.5);
  const double c = std::cos(kPi / 6.0), sn = std::sin(kPi / 6.0);
  v.grid.direction = Mat3(Vec3(c, sn, 0.0), Vec3(-sn, c, 0.0), Vec3(0.0, 0.0, 1.0));  // columns: the grid's axes
  v.transfer.colorX = {0.0f};
  v.transfer.colorY = {color};
  v.transfer.opacityX = {0.0f};
  v.transfer.opacityY = {opacity};
  v.transfer.shade = true;
  v.transfer.ambient = 0.1f;
  v.transfer.diffuse = 0.7f;
  v.transfer.specular = 0.4f;
  v.transfer.specularPower = 12.0f;
  return v;
}

void prepare(Volume& v) {
  std::size_t invalid = 0;
  ASSERT_EQ(v.prepare(invalid), "");
}

// The expected lit colour. With the grid's axes a0, a1 (unit) and spacings h0, h1, the scalar grows by slope / h0
// per unit length along a0 and slope ySlope / h1 along a1, and not along a2: its gradient is the sum of those
// (chain rule), here with ySlope 1
// (along: the lone-headlight case, whose ambient term is ambient x C; otherwise ambient x the ambient light, 1)
Color expectedLit(const Volume& v, const Color& c, const Vec3& toLight, const Vec3& toEye, double att = 1.0,
                  bool along = false) {
  const Vec3 n = glm::normalize(v.grid.direction[0] / v.grid.spacing.x + v.grid.direction[1] / v.grid.spacing.y);
  const double nl = std::abs(glm::dot(n, toLight));
  const double nh = std::abs(glm::dot(n, glm::normalize(toLight + toEye)));
  const Color ambient = along ? v.transfer.ambient * c : Color(v.transfer.ambient);
  const Color lit = ambient + float(att * v.transfer.diffuse * nl) * c +
                    float(att * v.transfer.specular * std::pow(nh, double(v.transfer.specularPower))) * Color(1.0f);
  return glm::clamp(lit, Color(0.0f), Color(1.0f));
}

}  // namespace

TEST(VolumeShade, DirectionalLightLitsTheMarchByTheGradientDirection) {
  const Color c(0.8f, 0.5f, 0.2f);
  Volume v = linearField(0.25f, c, 0.3f);
  prepare(v);
  VolumeLight light;
  light.toLight = glm::normalize(Vec3(0.3, -0.5, 0.8));
  VolumeLighting lighting;
  lighting.lights = &light;
  lighting.count = 1;
  // A ray through the middle of the grid: every sample has the same gradient, so the accumulated colour is the lit
  // colour times the opacity accumulated, 1 - T
  const Vec3 centre = v.grid.origin + v.grid.direction * (v.grid.spacing * Vec3(0.5 * (kN - 1)));
  Ray ray;
  ray.dir = glm::normalize(Vec3(0.2, 0.3, -1.0));
  ray.origin = centre - 40.0 * ray.dir;
  double t0 = 0.0, t1 = 1e30;
  ASSERT_TRUE(v.clip(ray, t0, t1));
  VolumeMarch acc;
  v.march(ray, t0, t1, true, 0.0f, acc, lighting);
  ASSERT_GT(acc.samples, 10u);
  ASSERT_LT(acc.transmittance, 0.9f);
  const Color expect = expectedLit(v, c, light.toLight, -ray.dir) * (1.0f - acc.transmittance);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(acc.color[k], expect[k], 2e-5) << "channel " << k;
  // (The index-space gradient (1, 1, 0) merely turned by the direction matrix would light it differently: spacing
  // matters)
  const Vec3 turned = glm::normalize(v.grid.direction * Vec3(1.0, 1.0, 0.0));
  const Color wrong =
      Color(v.transfer.ambient) + float(v.transfer.diffuse * std::abs(glm::dot(turned, light.toLight))) * c;
  EXPECT_GT(std::abs(wrong.r - expectedLit(v, c, light.toLight, -ray.dir).r), 0.02f);
  // Without Shade the march adds the transfer colour
  v.transfer.shade = false;
  prepare(v);
  VolumeMarch plain;
  v.march(ray, t0, t1, true, 0.0f, plain, lighting);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(plain.color[k], c[k] * (1.0f - plain.transmittance), 2e-5);
  EXPECT_EQ(plain.transmittance, acc.transmittance);  // shading changes colour, not opacity
}

TEST(VolumeShade, HeadlightAlongRaysPositionalAndSpotLights) {
  const Color c(0.6f, 0.6f, 0.9f);
  Volume v = linearField(0.5f, c, 0.2f);
  prepare(v);
  Ray ray;
  ray.dir = Vec3(0.1, -0.2, -1.0);
  ray.origin = Vec3(0.0);
  VolumeLight light;
  light.toLight = Vec3(1.0, 0.0, 0.0);  // ignored along rays
  VolumeLighting lighting;
  lighting.lights = &light;
  lighting.count = 1;
  lighting.alongRays = true;
  const VolumeShader along(v, ray, lighting, true);
  const Vec3f g(1.0f, 1.0f, 0.0f);  // the field's differences: the same along x and y
  const Vec3 toEye = -glm::normalize(ray.dir), x(0.0, 0.0, -5.0);
  Color got = along.shade(g, x, c), expect = expectedLit(v, c, toEye, toEye, 1.0, true);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(got[k], expect[k], 1e-6);
  // Positional with VTK's attenuation and a spot cone: a point inside the cone and one outside
  lighting.alongRays = false;
  light.positional = true;
  light.position = Vec3(3.0, 1.0, -2.0);
  light.attenuation = Vec3(0.5, 0.2, 0.1);
  light.axis = glm::normalize(x - light.position);
  light.cosCone = std::cos(20.0 * kPi / 180.0);
  light.exponent = 2.0;
  const VolumeShader spot(v, ray, lighting, true);
  const double d = glm::length(light.position - x);
  const double att = 1.0 / (0.5 + 0.2 * d + 0.1 * d * d);  // on the spot's axis: cos = 1
  got = spot.shade(g, x, c);
  expect = expectedLit(v, c, (light.position - x) / d, toEye, att);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(got[k], expect[k], 1e-6);
  const Vec3 outside = x + Vec3(0.0, 4.0, 0.0);
  got = spot.shade(g, outside, c);
  expect = Color(v.transfer.ambient);  // out of the cone: ambient only (the ambient light, not times C)
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(got[k], expect[k], 1e-6);
  // The ambient light colour scales the ambient term
  lighting.ambient = Color(0.0f);
  const VolumeShader dark(v, ray, lighting, true);
  got = dark.shade(g, outside, c);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(got[k], 0.0f);
}

TEST(VolumeShade, NoGradientMeansAmbientAndBadInputStaysFinite) {
  const Color c(0.5f, 0.7f, 0.9f);
  Volume v = linearField(0.0f, c, 0.2f);  // constant field: zero gradient
  v.transfer.specularPower = std::numeric_limits<float>::quiet_NaN();
  v.transfer.diffuse = std::numeric_limits<float>::infinity();
  prepare(v);
  EXPECT_EQ(v.transfer.specularPower, 0.0f);
  EXPECT_EQ(v.transfer.diffuse, 0.0f);
  Ray ray;
  ray.dir = Vec3(0.0, 0.0, -1.0);
  VolumeLight light;
  VolumeLighting lighting;
  lighting.lights = &light;
  lighting.count = 1;
  const VolumeShader shader(v, ray, lighting, true);
  Color got = shader.shade(Vec3f(0.0f), Vec3(0.0), c);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(got[k], v.transfer.ambient, 1e-7);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  got = shader.shade(Vec3f(nan, 1.0f, 0.0f), Vec3(0.0), c);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(got[k], v.transfer.ambient, 1e-7);
}

TEST(VolumeShade, EveryLightCountsBeyondThoseSetUpPerSegment) {
  // Twelve equal directional lights (more than the eight set up once per ray segment) light a sample twelve times
  // as much as one (diffuse only, no ambient, no highlight)
  const Color c(0.5f);
  Volume v = linearField(0.5f, c, 0.2f);
  v.transfer.ambient = 0.0f;
  v.transfer.specular = 0.0f;
  prepare(v);
  Ray ray;
  ray.dir = Vec3(0.0, 0.0, -1.0);
  std::vector<VolumeLight> lights(12);
  for (VolumeLight& l : lights) {
    l.toLight = glm::normalize(Vec3(0.2, 0.5, 1.0));
    l.radiance = Color(0.05f);
  }
  const Vec3f g(1.0f, 1.0f, 0.0f);
  auto diffuse = [&](std::size_t n, bool positional) {
    for (VolumeLight& l : lights) {
      l.positional = positional;
      l.position = Vec3(0.0) + 1e3 * l.toLight;  // far away: the same direction at x = 0
    }
    VolumeLighting lighting;
    lighting.lights = lights.data();
    lighting.count = n;
    return VolumeShader(v, ray, lighting, true).shade(g, Vec3(0.0), c).r;
  };
  const float one = diffuse(1, false);
  ASSERT_GT(one, 0.0f);
  EXPECT_NEAR(diffuse(8, false), 8.0f * one, 1e-5f);
  EXPECT_NEAR(diffuse(9, false), 9.0f * one, 1e-5f);
  EXPECT_NEAR(diffuse(12, false), 12.0f * one, 1e-5f);
  EXPECT_NEAR(diffuse(12, true), 12.0f * one, 1e-4f);  // positional, per sample (attenuation 1)
}

TEST(VolumeShade, GradientOpacityScalesAlphaByTheMagnitudePerMeanVoxel) {
  // slope 0.25 per point along x, spacing 1: 0.25 per unit; the mean spacing is 1.5, so the magnitude is 0.375
  Volume v = linearField(0.25f, Color(1.0f), 0.3f, 0.0f);
  v.transfer.shade = false;
  v.transfer.gradientOpacityMax = 1.5;  // a linear ramp 0 .. 1 over magnitudes 0 .. 1.5: factor 0.25
  v.transfer.gradientOpacity.resize(1024);
  for (std::size_t i = 0; i < 1024; ++i) v.transfer.gradientOpacity[i] = float(i) / 1023.0f;
  prepare(v);
  Ray ray;
  ray.dir = Vec3(0.0, 0.0, -1.0);
  const VolumeShader shader(v, ray, VolumeLighting(), true);
  EXPECT_NEAR(shader.opacityFactor(Vec3f(0.5f, 0.0f, 0.0f)), 0.25f, 1e-6f);  // differences over two points: 2 x 0.25
  EXPECT_NEAR(shader.opacityFactor(Vec3f(0.0f, 0.0f, 0.0f)), 0.0f, 1e-7f);
  EXPECT_NEAR(shader.opacityFactor(Vec3f(100.0f, 0.0f, 0.0f)), 1.0f, 1e-7f);  // clamped at the last value
  // In the march: a ray along the grid's z axis through its middle sees the same gradient everywhere. Factor 0:
  // nothing absorbed; a constant factor 1: the same march as without gradient opacity; the ramp: in between
  const Vec3 centre = v.grid.origin + v.grid.direction * (v.grid.spacing * Vec3(0.5 * (kN - 1)));
  ray.origin = centre + Vec3(0.0, 0.0, 30.0);
  double t0 = 0.0, t1 = 1e30;
  ASSERT_TRUE(v.clip(ray, t0, t1));
  auto transmittance = [&](const Volume& vol) {
    VolumeMarch acc;
    vol.march(ray, t0, t1, false, 0.0f, acc);
    return acc.transmittance;
  };
  const float ramp = transmittance(v);
  Volume off = v, zero = v, one = v;
  off.transfer.gradientOpacity.clear();
  std::fill(zero.transfer.gradientOpacity.begin(), zero.transfer.gradientOpacity.end(), 0.0f);
  std::fill(one.transfer.gradientOpacity.begin(), one.transfer.gradientOpacity.end(), 1.0f);
  for (Volume* w : {&off, &zero, &one}) prepare(*w);
  const float plain = transmittance(off);
  EXPECT_LT(plain, 0.5f);
  EXPECT_EQ(transmittance(zero), 1.0f);
  EXPECT_EQ(transmittance(one), plain);
  EXPECT_GT(ramp, plain);
  EXPECT_LT(ramp, 1.0f);
}
