// Empty-space skipping (Volume::skipEmptySpace): the march with and without it gives the same colour, transmittance
// and termination, bit for bit, on rays in every direction through volumes with transparent regions, for both
// interpolations, a narrow opacity spike, NaN scalars and a changed transfer function; and it takes fewer samples.
#include "geometry/volume.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

using namespace whitted;

namespace {

// 61 x 47 x 53 points at 8-point macro cells, as many times more as the macro cell has more (not multiples of
// it; finer: times more again), over the same box: a radial field, the distance from a point off the centre in
// units of the 8-point grid
Volume ball(VolumeInterpolation interp, double finer = 1.0) {
  const double f = finer * Volume::kMacroCell / 8.0;
  const int dims[3] = {int(60 * f) + 1, int(46 * f) + 1, int(52 * f) + 1};
  std::vector<float> s(std::size_t(dims[0]) * dims[1] * dims[2]);
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i) {
        const double x = i / f - 25.3, y = j / f - 20.1, z = k / f - 30.7;
        s[(std::size_t(k) * dims[1] + j) * dims[0] + i] = float(std::sqrt(x * x + y * y + z * z));
      }
  Volume v;
  v.grid = VolumeGrid::fromScalars(dims, s.data());
  v.grid.origin = Vec3(-3.0, -2.0, -2.5);
  v.grid.spacing = Vec3(0.1, 0.09, 0.1) / f;
  v.interpolation = interp;
  // Opaque only in a shell 12-16 points from the centre, a spike at 5.0-5.02, transparent elsewhere
  v.transfer.opacityX = {0.0f, 5.0f, 5.01f, 5.02f, 12.0f, 14.0f, 16.0f};
  v.transfer.opacityY = {0.0f, 0.0f, 0.9f, 0.0f, 0.0f, 0.6f, 0.0f};
  v.transfer.colorX = {0.0f, 20.0f};
  v.transfer.colorY = {Color(1.0f, 0.2f, 0.1f), Color(0.1f, 0.4f, 1.0f)};
  v.transfer.unitDistance = 0.3;
  return v;
}

struct Result {
  int differ = 0;
  uint64_t samplesOn = 0, samplesOff = 0;
};

// Prepares v (again, when called again: a transfer function edit keeps the grid's cell ranges) and compares the
// marches of rays with and without skipping
Result compareMarches(Volume& v, int rays) {
  std::size_t invalid = 0;
  EXPECT_EQ(v.prepare(invalid), "");
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Result r;
  for (int n = 0; n < rays; ++n) {
    Ray ray;
    ray.origin = Vec3(4.0 * u(rng), 4.0 * u(rng), 4.0 * u(rng));
    const Vec3 target(1.5 * u(rng), 1.2 * u(rng), 1.5 * u(rng));
    ray.dir = n % 7 == 0 ? Vec3(0, 0, 1) : glm::normalize(target - ray.origin);  // some along an axis
    double t0 = 0.0, t1 = kInfinity;
    if (!v.clip(ray, t0, t1)) continue;
    VolumeMarch on, off;
    const float stop = n % 3 == 0 ? 0.05f : 0.0f;  // with and without early termination
    v.skipEmptySpace = true;
    v.march(ray, t0, t1, true, stop, on);
    v.skipEmptySpace = false;
    v.march(ray, t0, t1, true, stop, off);
    r.samplesOn += on.samples;
    r.samplesOff += off.samples;
    const bool same = std::memcmp(&on.color, &off.color, sizeof(Color)) == 0 &&
                      std::memcmp(&on.transmittance, &off.transmittance, sizeof(float)) == 0 &&
                      on.terminated == off.terminated && on.invalidSamples == off.invalidSamples;
    r.differ += !same;
  }
  return r;
}

}  // namespace

TEST(VolumeSkip, SameMarchBitForBitWithFewerSamples) {
  for (VolumeInterpolation interp : {VolumeInterpolation::Linear, VolumeInterpolation::Nearest}) {
    Volume v = ball(interp);
    const Result r = compareMarches(v, 3000);
    std::printf("%s: %llu samples with skipping, %llu without (%.2f)\n",
                interp == VolumeInterpolation::Linear ? "linear" : "nearest", (unsigned long long)r.samplesOn,
                (unsigned long long)r.samplesOff, double(r.samplesOn) / double(r.samplesOff));
    EXPECT_EQ(r.differ, 0);
    EXPECT_LT(r.samplesOn, r.samplesOff * 3 / 4);  // the transparent inside and corners are skipped
  }
}

// Slabs across x aligned with the macro cells (K = Volume::kMacroCell points): points 2Km+K+1 .. 2Km+2K-2 are 1, the
// rest 0, so every other macro cell is empty and opacity starts a point after its far face: a march that skipped a
// step too far would miss it
TEST(VolumeSkip, OpacityRightAfterAnEmptyCell) {
  Volume v = ball(VolumeInterpolation::Linear);
  const int* n = v.grid.dims;
  const int K = Volume::kMacroCell;
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i)
        v.grid.scalars[(std::size_t(k) * n[1] + j) * n[0] + i] =
            (i % (2 * K) >= K + 1 && i % (2 * K) <= 2 * K - 2) ? 1.0f : 0.0f;
  v.transfer.opacityX = {0.0f, 1.0f};
  v.transfer.opacityY = {0.0f, 0.5f};
  const Result r = compareMarches(v, 3000);
  std::printf("slabs: %llu samples with skipping, %llu without\n", (unsigned long long)r.samplesOn,
              (unsigned long long)r.samplesOff);
  EXPECT_EQ(r.differ, 0);
  EXPECT_LT(r.samplesOn, r.samplesOff * 3 / 4);
}

TEST(VolumeSkip, NanScalarsAndAChangedTransferFunction) {
  Volume v = ball(VolumeInterpolation::Linear);
  // One NaN in 8 macro cells' points and one: most macro cells hold none
  const std::size_t stride = 8 * std::size_t(Volume::kMacroCell * Volume::kMacroCell * Volume::kMacroCell) + 1;
  for (std::size_t i = 0; i < v.grid.scalars.size(); i += stride) v.grid.scalars[i] = std::numeric_limits<float>::quiet_NaN();
  Result r = compareMarches(v, 2000);
  EXPECT_EQ(r.differ, 0);
  // A transfer function change re-prepares with the same grid: the cells' ranges are kept, their emptiness is new
  v.transfer.opacityX = {0.0f, 30.0f};
  v.transfer.opacityY = {0.0f, 1.0f};  // opaque almost everywhere: little left to skip
  r = compareMarches(v, 2000);
  EXPECT_EQ(r.differ, 0);
  v.transfer.opacityY = {0.0f, 0.0f};  // fully transparent: everything skipped but the NaN cells
  r = compareMarches(v, 2000);
  std::printf("transparent with NaN: %llu samples with skipping, %llu without\n", (unsigned long long)r.samplesOn,
              (unsigned long long)r.samplesOff);
  EXPECT_EQ(r.differ, 0);
  EXPECT_LT(r.samplesOn, r.samplesOff / 2);
}

// A grid large enough for the passes over its scalars to run on all cores (4 x 2^20 points and more: the conversion
// and its count of non-finite values, prepare's pass that makes them NaN, the macro cells' ranges): the counts are
// exact and skipping still changes no march. Also run under ThreadSanitizer (whitted.sh).
TEST(VolumeSkip, LargeGridPreparedOnAllCores) {
  Volume v = ball(VolumeInterpolation::Linear, 1.6);
  const std::size_t n = v.grid.scalars.size();
  ASSERT_GE(n, std::size_t(4) << 20);
  // The same field as doubles, with NaN, infinite and beyond-float values (1e300 is infinite as a float)
  std::vector<double> d(v.grid.scalars.begin(), v.grid.scalars.end());
  std::size_t bad = 0;
  for (std::size_t i = 7; i < n; i += 9973, ++bad)
    d[i] = bad % 3 == 0 ? std::nan("") : bad % 3 == 1 ? 1e300 : -std::numeric_limits<double>::infinity();
  EXPECT_EQ(VolumeGrid::convertScalars(d.data(), n, v.grid.scalars), bad);
  std::size_t invalid = 0;
  ASSERT_EQ(v.prepare(invalid), "");
  EXPECT_EQ(invalid, bad);
  for (std::size_t i = 7; i < n; i += 9973) EXPECT_TRUE(std::isnan(v.grid.scalars[i])) << i;
  const Result r = compareMarches(v, 1500);
  std::printf("%zu points, %zu not finite: %llu samples with skipping, %llu without\n", n, bad,
              (unsigned long long)r.samplesOn, (unsigned long long)r.samplesOff);
  EXPECT_EQ(r.differ, 0);
  EXPECT_LT(r.samplesOn, r.samplesOff * 3 / 4);
}
