// Shared by the BVH's tests (bvh_test.cpp, box_ray_test.cpp): random boxes, a tree of one primitive per leaf, and
// the exact (long double) slab test that conservative box tests are checked against.
#pragma once

#include "accel/bvh.h"

#include <algorithm>
#include <random>
#include <utility>
#include <vector>

namespace whitted::bvh_test {

inline std::vector<Bounds3> randomBoxes(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-10, 10);
  std::vector<Bounds3> boxes;
  for (int i = 0; i < n; ++i) {
    Vec3 c(U(rng), U(rng), U(rng));
    boxes.push_back(Bounds3{c - Vec3(0.1), c + Vec3(0.2)});
  }
  return boxes;
}

/// A tree split down to one primitive per leaf (many partly empty wide nodes).
inline Bvh singlePrimitiveLeaves(const std::vector<Bounds3>& boxes) {
  std::vector<Vec3> cents;
  for (auto& b : boxes) cents.push_back(b.center());
  Bvh bvh;
  BvhBuildOptions opt;
  opt.maxLeafSize = 1;
  opt.traversalCost = 0.01;
  bvh.build(boxes, cents, opt);
  return bvh;
}

/// Reference slab test of a double box in long double (no float rounding anywhere): a conservative traversal
/// must enter every box this enters.
inline bool exactSlab(const long double lo[3], const long double hi[3], const Ray& r) {
  long double t0 = r.tMin, t1 = r.tMax;
  for (int a = 0; a < 3; ++a) {
    if (r.dir[a] == 0.0) {
      if (r.origin[a] < lo[a] || r.origin[a] > hi[a]) return false;
      continue;
    }
    long double ta = (lo[a] - r.origin[a]) / r.dir[a];
    long double tb = (hi[a] - r.origin[a]) / r.dir[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return t0 <= t1;
}
inline bool exactSlab(const Bounds3& b, const Ray& r) {
  const long double lo[3] = {b.lo.x, b.lo.y, b.lo.z}, hi[3] = {b.hi.x, b.hi.y, b.hi.z};
  return exactSlab(lo, hi, r);
}

}  // namespace whitted::bvh_test
