// sanitizeMaterial: out-of-range values and the energy rule kr + kt <= 1.
#include "scene/material.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

using namespace whitted;

// kr 0.8 + kt 0.6 = 1.4: both scaled by 1 / 1.4, so the sum is 1 and the ratio kept; the energy bit is set.
TEST(Material, KrPlusKtAboveOneIsScaledToOne) {
  Material m;
  m.reflectance = Color(0.8f);
  m.transmittance = Color(0.6f);
  uint32_t bits = sanitizeMaterial(m);
  EXPECT_EQ(bits, kMaterialEnergyScaled);
  for (int c = 0; c < 3; ++c) {
    float sum = m.reflectance[c] + m.transmittance[c];
    EXPECT_NEAR(sum, 1.0f, 1e-6f) << c;
    EXPECT_LE(sum, 1.0f) << c;
    EXPECT_NEAR(m.reflectance[c] / m.transmittance[c], 0.8f / 0.6f, 1e-6f) << c;
  }
}

// Per channel: only the largest channel sum reaches 1; every channel is scaled by the same factor.
TEST(Material, EnergyScaleIsOneFactorForAllChannels) {
  Material m;
  m.reflectance = Color(1.0f, 0.5f, 0.0f);
  m.transmittance = Color(1.0f, 0.2f, 0.4f);  // sums 2, 0.7, 0.4
  EXPECT_EQ(sanitizeMaterial(m), kMaterialEnergyScaled);
  const float expectKr[3] = {0.5f, 0.25f, 0.0f}, expectKt[3] = {0.5f, 0.1f, 0.2f};
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(m.reflectance[c], expectKr[c], 1e-6f) << c;
    EXPECT_NEAR(m.transmittance[c], expectKt[c], 1e-6f) << c;
  }
  // kr = kt = 1 (a mirror that is also clear glass): half each
  Material g;
  g.reflectance = Color(1.0f);
  g.transmittance = Color(1.0f);
  EXPECT_EQ(sanitizeMaterial(g), kMaterialEnergyScaled);
  EXPECT_EQ(g.reflectance, Color(0.5f));
  EXPECT_EQ(g.transmittance, Color(0.5f));
}

// Out-of-range values are clamped first (their own bits), then the energy rule applies to what is left.
TEST(Material, ClampThenEnergy) {
  Material m;
  m.reflectance = Color(3.0f, 0.5f, 0.5f);  // clamped to 1 in red
  m.transmittance = Color(0.5f);
  uint32_t bits = sanitizeMaterial(m);
  EXPECT_EQ(bits, (1u << 4) | kMaterialEnergyScaled);
  EXPECT_NEAR(m.reflectance.x + m.transmittance.x, 1.0f, 1e-6f);
  EXPECT_NEAR(m.reflectance.y / m.transmittance.y, 1.0f, 1e-6f);
}

// kr + kt <= 1 everywhere: untouched, bit for bit, and no bit set (including sums exactly 1).
TEST(Material, KrPlusKtAtMostOneIsUntouched) {
  const Color pairs[][2] = {{Color(0.8f), Color(0.2f)},
                            {Color(0.3f, 0.0f, 1.0f), Color(0.7f, 1.0f, 0.0f)},
                            {Color(0.1f, 0.2f, 0.3f), Color(0.4f, 0.5f, 0.6f)},
                            {Color(0.0f), Color(1.0f)},
                            {Color(1.0f), Color(0.0f)}};
  for (const auto& p : pairs) {
    Material m;
    m.reflectance = p[0];
    m.transmittance = p[1];
    EXPECT_EQ(sanitizeMaterial(m), 0u);
    EXPECT_EQ(std::memcmp(&m.reflectance, &p[0], sizeof(Color)), 0);
    EXPECT_EQ(std::memcmp(&m.transmittance, &p[1], sizeof(Color)), 0);
  }
}

// The sum a warning quotes: after clamping kr and kt to [0,1] (2 -> 1, NaN -> 0), before the scaling.
TEST(Material, EnergySumIsTheClampedSumBeforeScaling) {
  Material m;
  m.reflectance = Color(2.0f, 0.3f, std::nanf(""));
  m.transmittance = Color(0.5f, 0.3f, 0.9f);
  float energy = -1.0f;
  EXPECT_EQ(sanitizeMaterial(m, &energy), kMaterialEnergyScaled | (1u << 4));
  EXPECT_EQ(energy, 1.5f);
}

// Beer-Lambert from a colour kept after a distance: -ln(kept) / distance, kept 0 capped at kMaxAbsorption, kept 1
// no absorption at any distance; what is out of range comes out as a value sanitizeMaterial clamps and reports.
TEST(Material, AbsorptionFromAttenuation) {
  EXPECT_EQ(absorptionFromAttenuation(0.5, 2.0), float(-std::log(0.5) / 2.0));
  EXPECT_EQ(absorptionFromAttenuation(0.0, 1.0), kMaxAbsorption);
  EXPECT_EQ(absorptionFromAttenuation(0.5, 0.0), kMaxAbsorption);
  EXPECT_EQ(absorptionFromAttenuation(1.0, 0.0), 0.0f);
  Material m;
  m.absorption = Color(absorptionFromAttenuation(2.0, 1.0), absorptionFromAttenuation(0.5, -1.0),
                       absorptionFromAttenuation(std::nan(""), 1.0));
  EXPECT_EQ(sanitizeMaterial(m), 1u << 7);
  EXPECT_EQ(m.absorption, Color(0.0f));
}

// The opacity rule sanitizeMaterial applies, for adapters that derive defaults from the opacity first.
TEST(Material, SanitizeOpacity) {
  float o = 0.25f;
  EXPECT_FALSE(sanitizeOpacity(o));
  EXPECT_EQ(o, 0.25f);
  o = 1.5f;
  EXPECT_TRUE(sanitizeOpacity(o));
  EXPECT_EQ(o, 1.0f);
  o = -std::numeric_limits<float>::infinity();
  EXPECT_TRUE(sanitizeOpacity(o));
  EXPECT_EQ(o, 1.0f);
}

// The metallic rule at its analytic corners: a smooth metal mirrors its base colour, a smooth dielectric of index
// 1.5 reflects F0 = (0.5 / 2.5)^2 = 0.04, a fully rough surface nothing; inputs outside [0, 1] are clamped and an
// index that is no positive number falls back to 0.04.
TEST(Material, MetallicReflectance) {
  const double base[3] = {1.0, 0.71, 0.29};
  double r[3];
  metallicReflectance(base, 1.0, 0.0, 1.5, r);
  EXPECT_EQ(r[0], 1.0); EXPECT_EQ(r[1], 0.71); EXPECT_EQ(r[2], 0.29);
  metallicReflectance(base, 0.0, 0.0, 1.5, r);
  for (double c : r) EXPECT_NEAR(c, 0.04, 1e-15);
  metallicReflectance(base, 0.0, 0.0, 2.0, r);
  for (double c : r) EXPECT_NEAR(c, 1.0 / 9.0, 1e-15);
  metallicReflectance(base, 0.5, 0.25, 1.5, r);
  EXPECT_NEAR(r[1], 0.75 * (0.5 * 0.71 + 0.5 * 0.04), 1e-15);
  metallicReflectance(base, 0.7, 1.0, 1.5, r);
  for (double c : r) EXPECT_EQ(c, 0.0);
  metallicReflectance(base, 3.0, -1.0, std::nan(""), r);
  EXPECT_EQ(r[2], 0.29);
  metallicReflectance(base, 0.0, 0.0, -1.0, r);
  for (double c : r) EXPECT_NEAR(c, 0.04, 1e-15);
}
