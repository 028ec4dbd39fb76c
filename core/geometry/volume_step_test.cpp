// The march converges to the emission-absorption integral as the step shrinks (issue 29's step study): against a
// closed form, not against a finer march. A field linear along the grid's x axis (trilinear interpolation reproduces
// it), an opacity linear in the scalar (the table's lerp reproduces it), so the exact transmittance along a ray is
// exp(|d| / u x integral of ln(1 - opacity(s)) ds), in closed form; the march's product of (1 - opacity)^(h / u)
// over step middles is the midpoint rule for that integral: second order in the step.
#include "geometry/volume.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

using namespace whitted;

namespace {

constexpr int kNx = 33;           // points along x: scalar = x index, 0 .. 32
constexpr double kTop = 0.9;      // opacity at the largest scalar (0 at 0), per unit distance
constexpr double kUnit = 8.0;     // ScalarOpacityUnitDistance

Volume ramp(double step) {
  const int dims[3] = {kNx, 5, 5};
  std::vector<float> s;
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i) s.push_back(float(i));
  Volume v;
  v.grid = VolumeGrid::fromScalars(dims, s.data());
  v.transfer.opacityX = {0.0f, float(kNx - 1)};
  v.transfer.opacityY = {0.0f, float(kTop)};
  v.transfer.colorX = {0.0f};
  v.transfer.colorY = {Color(1.0f)};
  v.transfer.unitDistance = kUnit;
  v.sampleDistance = step;
  std::size_t invalid = 0;
  EXPECT_EQ(v.prepare(invalid), "");
  return v;
}

}  // namespace

TEST(VolumeStep, TransmittanceConvergesToTheIntegralAsTheStepShrinks) {
  // A ray across the whole ramp, oblique in y and z (inside the grid from x = 0 to x = 32)
  const Vec3 d(1.0, 0.1, 0.05);
  Ray ray;
  ray.origin = Vec3(-1.0, 0.4, 1.2);
  ray.dir = d;
  // Closed form: with a = kTop / 32 and w = 1 - a s, the integral of ln(1 - a s) over s in [0, 32] is
  // -(1 / a) [w ln w - w] from w = 1 to w = 1 - kTop; s = x = t - 1 along the ray, and a step dt has length |d| dt
  const double a = kTop / (kNx - 1), w1 = 1.0 - kTop;
  const double integral = -(1.0 / a) * ((w1 * std::log(w1) - w1) - (0.0 - 1.0));
  const double exact = std::exp(glm::length(d) / kUnit * integral);
  std::vector<double> steps = {4.0, 2.0, 1.0, 0.5, 0.25}, error;
  for (double h : steps) {
    const Volume v = ramp(h);
    double t0 = 0.0, t1 = 1e30;
    ASSERT_TRUE(v.clip(ray, t0, t1));
    VolumeMarch acc;
    v.march(ray, t0, t1, true, 0.0f, acc);
    error.push_back(std::abs(double(acc.transmittance) - exact));
    std::printf("step %.3f: transmittance %.7f, exact %.7f, error %.3g, %llu samples\n", h, double(acc.transmittance),
                exact, error.back(), (unsigned long long)acc.samples);
    // Emission with a constant colour 1 telescopes: colour + transmittance = 1 at any step
    EXPECT_NEAR(double(acc.color.r) + double(acc.transmittance), 1.0, 1e-5);
  }
  // Second order: halving the step divides the error by about 4 (at least 3), down to float rounding
  for (std::size_t i = 1; i < steps.size(); ++i) {
    if (error[i - 1] < 1e-5) break;
    EXPECT_GT(error[i - 1] / error[i], 3.0) << "step " << steps[i];
  }
  EXPECT_LT(error.back(), 2e-5);
}

// A march at stepScale s (progressive refinement's finer levels, the step estimate's coarser one) is the march of the
// same volume whose step is 2^s times as long: each full step's alpha from the table's by squaring or square roots
// agrees with the table built for that step to float rounding; the sample count follows the step. A step already
// at the finest the march takes (the diagonal / kMaxSteps) is not made finer than twice that.
TEST(VolumeStep, ScaledStepIsTheMarchAtThatStep) {
  const Vec3 d(1.0, 0.1, 0.05);
  Ray ray;
  ray.origin = Vec3(-1.0, 0.4, 1.2);
  ray.dir = d;
  const Volume v = ramp(1.0);
  for (int scale : {2, 1, -1, -2, -3}) {
    const Volume at = ramp(std::ldexp(1.0, scale));
    double t0 = 0.0, t1 = 1e30;
    ASSERT_TRUE(v.clip(ray, t0, t1));
    VolumeMarch a, b;
    v.march(ray, t0, t1, true, 0.0f, a, VolumeLighting(), scale);
    at.march(ray, t0, t1, true, 0.0f, b);
    EXPECT_EQ(a.samples, b.samples) << scale;
    EXPECT_NEAR(a.transmittance, b.transmittance, 2e-6) << scale;
    EXPECT_NEAR(a.color.r, b.color.r, 2e-6) << scale;
  }
  EXPECT_EQ(v.finestStepScale(), -10);  // 2^-10 >= 32.5 / 40000 > 2^-11 (the diagonal of 32 x 4 x 4 voxels)
  // The finest step: a sample distance below the diagonal / kMaxSteps is raised to it, and halved once at most
  const Volume finest = ramp(1e-9);
  EXPECT_EQ(finest.finestStepScale(), -1);
  double t0 = 0.0, t1 = 1e30;
  ASSERT_TRUE(finest.clip(ray, t0, t1));
  VolumeMarch a, b;
  finest.march(ray, t0, t1, false, 0.0f, a, VolumeLighting(), -3);
  finest.march(ray, t0, t1, false, 0.0f, b, VolumeLighting(), -1);
  EXPECT_EQ(a.samples, b.samples);
  EXPECT_EQ(a.transmittance, b.transmittance);
}
