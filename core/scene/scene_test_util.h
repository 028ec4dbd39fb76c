// Shared by the scene's tests (scene_test.cpp, upgrade_test.cpp): rays from above onto a mesh around the origin.
#pragma once

#include "util/math.h"

#include <random>

namespace whitted::scene_test {

/// A ray from z = 4 down toward the xy plane, starting within +-width of the z axis.
inline Ray rayFromAbove(std::mt19937& rng, double width) {
  std::uniform_real_distribution<double> U(-1, 1);
  Ray r;
  r.origin = Vec3(width * U(rng), width * U(rng), 4.0);
  r.dir = glm::normalize(Vec3(0.2 * U(rng), 0.2 * U(rng), -1.0));
  return r;
}

}  // namespace whitted::scene_test
