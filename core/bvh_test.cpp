// BVH: build invariants and traversal equal to brute force.
#include "bvh.h"
#include "scene.h"
#include "scenes.h"

#include <gtest/gtest.h>

#include <random>

using namespace whitted;

namespace {

std::vector<Bounds3> randomBoxes(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-10, 10);
  std::vector<Bounds3> boxes;
  for (int i = 0; i < n; ++i) {
    Vec3 c(U(rng), U(rng), U(rng));
    boxes.push_back(Bounds3{c - Vec3(0.1), c + Vec3(0.2)});
  }
  return boxes;
}

/// Every node contains its children / primitives, every primitive is in exactly one leaf, children are in range.
void checkInvariants(const Bvh& bvh, const std::vector<Bounds3>& boxes) {
  std::vector<int> seen(boxes.size(), 0);
  const auto& nodes = bvh.nodes();
  for (const BvhNode& n : nodes) {
    if (n.count > 0) {
      for (uint32_t i = n.first; i < n.first + n.count; ++i) {
        uint32_t p = bvh.primIndices()[i];
        ++seen[p];
        for (int a = 0; a < 3; ++a) {
          ASSERT_LE(n.lo[a], boxes[p].lo[a]);
          ASSERT_GE(n.hi[a], boxes[p].hi[a]);
        }
      }
    } else {
      ASSERT_LT(n.first + 1, nodes.size());
      for (uint32_t c = n.first; c < n.first + 2; ++c)
        for (int a = 0; a < 3; ++a) {
          ASSERT_LE(n.lo[a], nodes[c].lo[a]);
          ASSERT_GE(n.hi[a], nodes[c].hi[a]);
        }
    }
  }
  for (int s : seen) ASSERT_EQ(s, 1);
  EXPECT_LT(bvh.depth(), Bvh::kStackSize);
  EXPECT_EQ(nodes.size() % 2, 1u);  // binary tree: 2 * leaves - 1 nodes
}

}  // namespace

TEST(Bvh, NodesContainChildrenAndEveryPrimitiveOnce) {
  auto boxes = randomBoxes(5000, 1);
  std::vector<Vec3> cents;
  for (auto& b : boxes) cents.push_back(b.center());
  Bvh bvh;
  bvh.build(boxes, cents);
  checkInvariants(bvh, boxes);
}

// Above 65536 primitives the top levels are built by parallel threads and spliced together.
TEST(Bvh, ParallelBuildKeepsInvariants) {
  auto boxes = randomBoxes(300000, 2);
  std::vector<Vec3> cents;
  for (auto& b : boxes) cents.push_back(b.center());
  Bvh bvh;
  bvh.build(boxes, cents);
  checkInvariants(bvh, boxes);
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
