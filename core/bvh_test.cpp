// BVH: build invariants and traversal equal to brute force.
#include "bvh.h"
#include "scene.h"
#include "scenes.h"

#include <gtest/gtest.h>

#include <random>

using namespace whitted;

TEST(Bvh, NodesContainChildrenAndEveryPrimitiveOnce) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> U(-10, 10);
  std::vector<Bounds3> boxes;
  std::vector<Vec3> cents;
  for (int i = 0; i < 5000; ++i) {
    Vec3 c(U(rng), U(rng), U(rng));
    Bounds3 b{c - Vec3(0.1), c + Vec3(0.2)};
    boxes.push_back(b);
    cents.push_back(b.center());
  }
  Bvh bvh;
  bvh.build(boxes, cents);
  std::vector<int> seen(boxes.size(), 0);
  const auto& nodes = bvh.nodes();
  for (const BvhNode& n : nodes) {
    if (n.count > 0) {
      for (uint32_t i = n.first; i < n.first + n.count; ++i) {
        uint32_t p = bvh.primIndices()[i];
        ++seen[p];
        for (int a = 0; a < 3; ++a) {
          EXPECT_LE(n.lo[a], boxes[p].lo[a]);
          EXPECT_GE(n.hi[a], boxes[p].hi[a]);
        }
      }
    } else {
      for (uint32_t c = n.first; c < n.first + 2; ++c)
        for (int a = 0; a < 3; ++a) {
          EXPECT_LE(n.lo[a], nodes[c].lo[a]);
          EXPECT_GE(n.hi[a], nodes[c].hi[a]);
        }
    }
  }
  for (int s : seen) EXPECT_EQ(s, 1);
  EXPECT_LT(bvh.depth(), Bvh::kStackSize);
}

TEST(Bvh, CoincidentCentroidsStillSplit) {
  std::vector<Bounds3> boxes(1000, Bounds3{Vec3(0), Vec3(1)});
  std::vector<Vec3> cents(1000, Vec3(0.5));
  Bvh bvh;
  bvh.build(boxes, cents);
  for (const BvhNode& n : bvh.nodes()) EXPECT_LE(n.count, 8u);
  EXPECT_LT(bvh.depth(), Bvh::kStackSize);
}

TEST(Bvh, ClosestHitMatchesBruteForce) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> U(-1, 1);
  TriangleMesh m;
  for (int i = 0; i < 2000; ++i) {
    Vec3 c(U(rng) * 5, U(rng) * 5, U(rng) * 5);
    uint32_t b = uint32_t(m.positions.size());
    m.positions.push_back(c);
    m.positions.push_back(c + Vec3(U(rng), U(rng), U(rng)) * 0.5);
    m.positions.push_back(c + Vec3(U(rng), U(rng), U(rng)) * 0.5);
    m.triangles.push_back({b, b + 1, b + 2});
  }
  Scene scene;
  TriangleMesh copy = m;
  scene.addInstance(scene.addMesh(std::move(copy)), Mat4(1.0), scene.addMaterial(Material{}));
  scene.commit();
  int hits = 0;
  for (int k = 0; k < 2000; ++k) {
    Ray r;
    r.origin = Vec3(U(rng), U(rng), U(rng)) * 8.0;
    r.dir = glm::normalize(Vec3(U(rng), U(rng), U(rng)));
    double best = kInfinity;
    uint32_t bestPrim = 0;
    for (uint32_t i = 0; i < m.triangles.size(); ++i) {
      auto& t = m.triangles[i];
      auto h = intersectTriangle(r, m.positions[t.x], m.positions[t.y], m.positions[t.z]);
      if (h && h->t < best) {
        best = h->t;
        bestPrim = i;
      }
    }
    Hit h;
    bool found = scene.intersect(r, h);
    ASSERT_EQ(found, std::isfinite(best));
    if (found) {
      ++hits;
      EXPECT_EQ(h.t, best);
      EXPECT_EQ(h.prim, bestPrim);
    }
  }
  EXPECT_GT(hits, 200);
}
