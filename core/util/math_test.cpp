// Vector math (util/math.h): rounding to float that survives the compiler's vectorizer.
#include "util/math.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using namespace whitted;

// roundToFloat rounds in the loops the benchmark and the leaf code run over glm vectors (GCC 12's vectorizer
// turns the plain double(float(x)) there into x); a volatile float is the independent reference.
TEST(Math, RoundToFloatRoundsInsideVectorizedLoops) {
  std::vector<Vec3> v;
  for (int i = 0; i < 64; ++i) v.push_back(Vec3(0.1 * i, std::sin(0.3 * i), 1e7 + 0.7 * i));
  std::vector<Vec3> expected = v;
  for (Vec3& p : expected)
    for (int k = 0; k < 3; ++k) {
      volatile float f = float(p[k]);
      p[k] = f;
    }
  for (Vec3& p : v) p = Vec3(roundToFloat(p.x), roundToFloat(p.y), roundToFloat(p.z));
  int rounded = 0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    EXPECT_EQ(v[i], expected[i]) << i;
    rounded += v[i] != Vec3(0.1 * i, std::sin(0.3 * i), 1e7 + 0.7 * i);
  }
  EXPECT_GT(rounded, 60);  // the input is not already single precision
}
