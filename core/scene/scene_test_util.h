// Shared by the scene's tests (scene_test.cpp, upgrade_test.cpp): rays from above onto a mesh around the origin,
// and the check that two scenes give those rays the same closest hits.
#pragma once

#include "scene/scene.h"
#include "util/math.h"

#include <gtest/gtest.h>

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

/// Closest hits (distance, primitive, shading normal, colour) of `rays` rays from above (rayFromAbove, spread width)
/// through scenes a and b are the same, and more than 1000 of them hit.
inline void expectSameHits(const Scene& a, const Scene& b, double width, int rays = 3000) {
  std::mt19937 rng(5);
  int hits = 0;
  for (int k = 0; k < rays; ++k) {
    const Ray r = rayFromAbove(rng, width);
    Hit ha, hb;
    const bool hitA = a.intersect(r, ha);
    ASSERT_EQ(hitA, b.intersect(r, hb));
    if (!hitA) continue;
    ++hits;
    ASSERT_EQ(ha.t, hb.t);
    ASSERT_EQ(ha.prim, hb.prim);
    const SurfacePoint sa = a.surface(r, ha), sb = b.surface(r, hb);
    ASSERT_EQ(sa.ns, sb.ns);
    ASSERT_EQ(sa.color, sb.color);
  }
  EXPECT_GT(hits, 1000);
}

}  // namespace whitted::scene_test
