// BoxRay, the conservative single-precision box test: it never loses a box the exact slab test enters (grazing
// rays at every scale and offset, rays touching a stored float box), and never enters an empty slot.
#include "accel/bvh.h"
#include "accel/bvh_test_util.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <vector>

using namespace whitted;
using namespace whitted::bvh_test;

namespace {

// The single-precision box test never loses a box the exact (long double) slab test enters: boxes of size 1e-6
// to 1e3 at offsets 0 to 1e7, rays with direction magnitudes 1e-200 to 1e200, near-parallel slopes (down to 1e-40
// and exact zeros), and origins placed exactly on box faces. Every ray is aimed at one box's interior or at one of
// its face planes, so most of these rays graze.
TEST(Bvh, FloatBoxTestIsConservativeForDoubleRays) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(-1, 1), U01(0, 1);
  const double scales[] = {1e-6, 1e-2, 1e3}, offsets[] = {0.0, 1e3, 1e7};
  const double dirMags[] = {1e-200, 1.0, 1e200};
  long entered = 0, rays = 0;
  for (double scale : scales)
    for (double offset : offsets) {
      std::vector<Bounds3> boxes;
      for (int i = 0; i < 300; ++i) {
        Vec3 c = Vec3(offset) + scale * 20.0 * Vec3(U(rng), U(rng), U(rng));
        Vec3 h = scale * Vec3(U01(rng), U01(rng), U01(rng)) + Vec3(scale * 1e-3);
        boxes.push_back(Bounds3{c - h, c + h});
      }
      const Bvh bvh = singlePrimitiveLeaves(boxes);
      for (int k = 0; k < 3000; ++k) {
        const Bounds3& target = boxes[std::size_t(k) % boxes.size()];
        Vec3 aim = target.lo + (target.hi - target.lo) * Vec3(U01(rng), U01(rng), U01(rng));
        if (k % 3 == 1) aim[k % 3] = (k & 8) ? target.lo[k % 3] : target.hi[k % 3];  // on a face plane
        Vec3 d = glm::normalize(Vec3(U(rng), U(rng), U(rng)));
        if (k % 5 == 0) d[(k / 5) % 3] = (k & 16) ? 0.0 : 1e-40 * U(rng);  // (nearly) parallel to an axis plane
        d *= dirMags[std::size_t(k) % 3];
        Ray r;
        const double back = scale * (k % 7 == 0 ? 1e4 : 30.0);  // also from far away
        r.origin = aim - (back / glm::length(d / dirMags[std::size_t(k) % 3])) * d / dirMags[std::size_t(k) % 3];
        if (k % 11 == 0) r.origin = aim;  // origin on the face plane / inside the box
        r.dir = d;
        if (!isFinite(r.origin) || !isFinite(r.dir)) continue;
        std::vector<int> got(boxes.size(), 0);
        double tMax = r.tMax;
        bvh.traverse<false>(r, tMax, [&](uint32_t first, uint32_t count, double&) {
          for (uint32_t i = first; i < first + count; ++i) ++got[bvh.primIndices()[i]];
          return false;
        });
        ++rays;
        for (std::size_t p = 0; p < boxes.size(); ++p)
          if (exactSlab(boxes[p], r)) {
            ++entered;
            ASSERT_EQ(got[p], 1) << "scale " << scale << " offset " << offset << " ray " << k << " box " << p;
          }
      }
    }
  std::printf("[bvh] float box test: %ld rays, %ld exact box entries, none lost\n", rays, entered);
  EXPECT_GT(entered, rays);  // the aimed-at box at least, for most rays
}

// The stored float boxes themselves (leaf children), touched exactly: rays aimed at a corner or an edge of a leaf's
// single-precision box (its exact value b + anchor, in long double), from near and far, at every scale and offset.
// Half of these rays only touch the box, so any rounding toward the inside (origin, reciprocal, subtraction,
// product) loses some. Trees of 64 boxes and of 3 (every leaf's box shares faces with the root's), walked by the
// single-ray and the packet closest-hit traversals.
TEST(Bvh, FloatBoxTestKeepsRaysTouchingTheStoredBox) {
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> U(-1, 1), U01(0, 1);
  long touching = 0;
  for (int count : {64, 3})
  for (double scale : {1e-6, 1.0, 1e4})
    for (double offset : {0.0, 3e2, 1e7}) {
      std::vector<Bounds3> boxes;
      for (int i = 0; i < count; ++i) {
        Vec3 c = Vec3(offset) + scale * 10.0 * Vec3(U(rng), U(rng), U(rng));
        boxes.push_back(Bounds3{c - Vec3(scale * 0.3), c + Vec3(scale * 0.3)});
      }
      const Bvh bvh = singlePrimitiveLeaves(boxes);
      for (const BvhWideNode& n : bvh.nodes())
        for (int c = 0; c < 4; ++c) {
          if (n.count[c] == 0 || n.count[c] == BvhWideNode::kEmpty) continue;
          const uint32_t prim = bvh.primIndices()[n.first[c]];
          long double lo[3], hi[3];
          for (int a = 0; a < 3; ++a) {
            lo[a] = (long double)n.b[a][c] + bvh.anchor()[a];
            hi[a] = (long double)n.b[3 + a][c] + bvh.anchor()[a];
          }
          for (int k = 0; k < 60; ++k) {
            // A corner (k even) or a point on an edge, approached from a random direction
            long double aim[3];
            for (int a = 0; a < 3; ++a) aim[a] = (rng() & 1) ? lo[a] : hi[a];
            if (k & 1) aim[k % 3] = lo[k % 3] + (hi[k % 3] - lo[k % 3]) * U01(rng);
            Vec3 d = glm::normalize(Vec3(U(rng), U(rng), U(rng))) * (k % 3 == 0 ? 1e-100 : 1.0);
            const long double back = scale * ((k % 4 == 0) ? 1e5 : 2.0) / glm::length(d);
            Ray r;
            for (int a = 0; a < 3; ++a) r.origin[a] = double(aim[a] - back * d[a]);
            r.dir = d;
            if (k % 5 == 4) {
              // From the anchor itself (the origin rounds exactly): only the reciprocal's and the products'
              // rounding can lose these
              r.origin = bvh.anchor();
              for (int a = 0; a < 3; ++a) r.dir[a] = double(aim[a] - r.origin[a]);
            }
            if (!exactSlab(lo, hi, r)) continue;
            ++touching;
            bool seen = false;
            double tMax = r.tMax;
            bvh.traverse<false>(r, tMax, [&](uint32_t first, uint32_t cnt, double&) {
              for (uint32_t i = first; i < first + cnt; ++i) seen |= bvh.primIndices()[i] == prim;
              return false;
            });
            ASSERT_TRUE(seen) << "scale " << scale << " offset " << offset << " ray " << k;
            seen = false;
            bvh.traverse4(&r, 1u, &tMax, [&](uint32_t first, uint32_t cnt, unsigned, double*) {
              for (uint32_t i = first; i < first + cnt; ++i) seen |= bvh.primIndices()[i] == prim;
              return 0u;
            });
            ASSERT_TRUE(seen) << "packet: scale " << scale << " offset " << offset << " ray " << k;
          }
        }
    }
  std::printf("[bvh] %ld rays touching stored float boxes, all entered\n", touching);
  EXPECT_GT(touching, 5000);
}

}  // namespace

namespace {

// Rays whose origin lies beyond float range from the tree's anchor on one, two or three axes (the origin rounds to
// +-inf there), with infinite exit bounds: the leaf callback never sees an empty slot. Found by the scene fuzzer
// (an empty slot entered through NaN exits and an +inf entry compared with an infinite exit bound).
TEST(Bvh, OriginsBeyondFloatRangeNeverEnterEmptySlots) {
  for (int n : {2, 3, 5, 6, 7}) {
    auto boxes = randomBoxes(n, unsigned(300 + n));
    const Bvh bvh = singlePrimitiveLeaves(boxes);
    for (double far : {-1e39, 1e39, -1e300, 1e300})
      for (int axes = 1; axes < 8; ++axes) {  // far on one, two or all three axes, aimed back at the boxes
        Ray r;
        r.origin = Vec3(0.1, -0.2, 0.3);
        r.dir = Vec3(0.0);
        for (int axis = 0; axis < 3; ++axis)
          if (axes & (1 << axis)) {
            r.origin[axis] = far;
            r.dir[axis] = far < 0 ? 1.0 : -1.0;
          }
        double tMax = r.tMax;
        bvh.traverse<false>(r, tMax, [&](uint32_t first, uint32_t count, double&) {
          EXPECT_NE(count, BvhWideNode::kEmpty);
          EXPECT_LE(std::size_t(first) + count, boxes.size());
          return false;
        });
      }
  }
}

}  // namespace
