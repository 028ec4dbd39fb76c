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

/// Every wide node's child box contains its child node's boxes / its primitives, every primitive is in exactly
/// one leaf, children are in range, empty slots are inverted boxes, leaves hold at most 8 primitives.
void checkInvariants(const Bvh& bvh, const std::vector<Bounds3>& boxes) {
  std::vector<int> seen(boxes.size(), 0);
  const auto& nodes = bvh.nodes();
  std::vector<int> parents(nodes.size(), 0);
  for (const BvhWideNode& n : nodes) {
    int used = 0;
    for (int c = 0; c < 4; ++c) {
      if (n.count[c] == BvhWideNode::kEmpty) {
        ASSERT_GT(n.b[0][c], n.b[3][c]);  // inverted
        continue;
      }
      ++used;
      if (n.count[c] > 0) {
        EXPECT_LE(n.count[c], 8u);
        for (uint32_t i = n.first[c]; i < n.first[c] + n.count[c]; ++i) {
          uint32_t p = bvh.primIndices()[i];
          ++seen[p];
          for (int a = 0; a < 3; ++a) {
            ASSERT_LE(n.b[a][c], boxes[p].lo[a]);
            ASSERT_GE(n.b[3 + a][c], boxes[p].hi[a]);
          }
        }
      } else {
        ASSERT_LT(n.first[c], nodes.size());
        ASSERT_GT(n.first[c], 0u);
        ++parents[n.first[c]];
        const BvhWideNode& child = nodes[n.first[c]];
        for (int cc = 0; cc < 4; ++cc) {
          if (child.count[cc] == BvhWideNode::kEmpty) continue;
          for (int a = 0; a < 3; ++a) {
            ASSERT_LE(n.b[a][c], child.b[a][cc]);
            ASSERT_GE(n.b[3 + a][c], child.b[3 + a][cc]);
          }
        }
      }
    }
    EXPECT_GE(used, nodes.size() == 1 ? 1 : 2);
  }
  for (int s : seen) ASSERT_EQ(s, 1);
  for (std::size_t i = 1; i < parents.size(); ++i) ASSERT_EQ(parents[i], 1) << "wide node " << i;
  EXPECT_LT(bvh.depth(), Bvh::kStackSize);
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
  checkInvariants(bvh, boxes);
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

// Tiny trees (a root leaf, roots with 2 or 3 children, partly empty wide nodes) find exactly the boxes a brute-force
// slab test finds, with closest-first order: the leaf callback sees each entered leaf once.
TEST(Bvh, TinyTreesVisitWhatBruteForceHits) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(-1, 1);
  for (int n = 1; n <= 40; ++n) {
    auto boxes = randomBoxes(n, unsigned(100 + n));
    std::vector<Vec3> cents;
    for (auto& b : boxes) cents.push_back(b.center());
    Bvh bvh;
    BvhBuildOptions opt;
    opt.maxLeafSize = 1 + n % 3;
    opt.traversalCost = 0.01;  // split down to small leaves
    bvh.build(boxes, cents, opt);
    checkInvariants(bvh, boxes);
    for (int k = 0; k < 200; ++k) {
      Ray r;
      r.origin = Vec3(U(rng), U(rng), U(rng)) * 15.0;
      r.dir = glm::normalize(Vec3(U(rng), U(rng), U(rng)));
      std::vector<int> expected(boxes.size(), 0), got(boxes.size(), 0);
      for (std::size_t p = 0; p < boxes.size(); ++p) {
        BvhNode leaf{};
        for (int a = 0; a < 3; ++a) {
          leaf.lo[a] = float(boxes[p].lo[a]);
          leaf.hi[a] = float(boxes[p].hi[a]);
        }
        double t;
        expected[p] = Bvh::slab(leaf, RayTraversal(r), r.tMin, r.tMax, t) ? 1 : 0;
      }
      double tMax = r.tMax;
      bvh.traverse<false>(r, tMax, [&](uint32_t first, uint32_t count, double&) {
        for (uint32_t i = first; i < first + count; ++i) ++got[bvh.primIndices()[i]];
        return false;
      });
      // Every primitive whose own box the ray enters is in a visited leaf, and no leaf is visited twice
      for (std::size_t p = 0; p < boxes.size(); ++p) {
        ASSERT_LE(got[p], 1);
        if (expected[p]) ASSERT_EQ(got[p], 1) << "n " << n << " ray " << k << " prim " << p;
      }
    }
  }
}
