// BVH: build invariants and traversal equal to brute force.
#include "accel/bvh.h"
#include "accel/bvh_test_util.h"
#include "scene/scene.h"
#include "scenes/scenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <optional>
#include <random>
#include <stdexcept>

using namespace whitted;
using namespace whitted::bvh_test;

namespace {

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
          const Bounds3 nb = bvh.childBounds(n, c);
          for (int a = 0; a < 3; ++a) {
            ASSERT_LE(nb.lo[a], boxes[p].lo[a]);
            ASSERT_GE(nb.hi[a], boxes[p].hi[a]);
          }
        }
      } else {
        ASSERT_LT(n.first[c], nodes.size());
        ASSERT_GT(n.first[c], std::size_t(&n - nodes.data()));  // children after parents (refit relies on it)
        ++parents[n.first[c]];
        const BvhWideNode& child = nodes[n.first[c]];
        // Both in the tree's anchored float coordinates: nesting is exact there
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

std::vector<Vec3> centers(const std::vector<Bounds3>& boxes) {
  std::vector<Vec3> cents;
  for (auto& b : boxes) cents.push_back(b.center());
  return cents;
}

BvhBuildOptions withQuality(BvhBuildQuality q, int threads = 0) {
  BvhBuildOptions opt;
  opt.quality = q;
  opt.threads = threads;
  return opt;
}

bool sameTree(const Bvh& a, const Bvh& b) {
  return a.nodes().size() == b.nodes().size() && a.primIndices() == b.primIndices() &&
         std::memcmp(a.nodes().data(), b.nodes().data(), a.nodes().size() * sizeof(BvhWideNode)) == 0;
}

class BvhQuality : public testing::TestWithParam<BvhBuildQuality> {};

/// Random triangles (in a cube of edge 10) and their boxes.
struct Triangles {
  TriangleMesh mesh;  // triangle i: vertices 3i, 3i+1, 3i+2
  std::vector<Bounds3> boxes;
  Triangles(int n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> U(-1, 1);
    for (int i = 0; i < n; ++i) {
      Vec3 c(U(rng) * 5, U(rng) * 5, U(rng) * 5);
      for (int k = 0; k < 3; ++k) mesh.positions.push_back(k == 0 ? c : c + Vec3(U(rng), U(rng), U(rng)) * 0.5);
      mesh.triangles.push_back({3 * i, 3 * i + 1, 3 * i + 2});
    }
    updateBoxes();
  }
  void updateBoxes() {
    boxes.assign(mesh.triangles.size(), Bounds3());
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) boxes[i / 3].extend(mesh.positions[i]);
  }
  std::optional<PrimHit> intersect(const Ray& r, uint32_t i) const {
    return intersectTriangle(r, mesh.positions[3 * i], mesh.positions[3 * i + 1], mesh.positions[3 * i + 2]);
  }
  /// Closest hit distance over all triangles (infinity for none); prim: the lowest index at that distance.
  double bruteForce(const Ray& r, uint32_t& prim) const {
    double best = kInfinity;
    for (uint32_t i = 0; i < boxes.size(); ++i) {
      auto h = intersect(r, i);
      if (h && h->t < best) {
        best = h->t;
        prim = i;
      }
    }
    return best;
  }
};

Ray randomRay(std::mt19937& rng) {
  std::uniform_real_distribution<double> U(-1, 1);
  Ray r;
  r.origin = Vec3(U(rng), U(rng), U(rng)) * 8.0;
  r.dir = glm::normalize(Vec3(U(rng), U(rng), U(rng)));
  return r;
}

/// Closest hits through the tree equal brute force over every triangle (same t, same triangle) for random rays.
void expectClosestHitsMatch(const Bvh& bvh, const Triangles& tris, unsigned seed) {
  std::mt19937 rng(seed);
  int hits = 0;
  for (int k = 0; k < 1000; ++k) {
    const Ray r = randomRay(rng);
    uint32_t bestPrim = 0;
    const double best = tris.bruteForce(r, bestPrim);
    double tMax = r.tMax;
    uint32_t prim = 0;
    bool found = bvh.traverse<false>(r, tMax, [&](uint32_t first, uint32_t count, double& t) {
      bool any = false;
      for (uint32_t i = first; i < first + count; ++i) {
        const uint32_t p = bvh.primIndices()[i];
        auto h = tris.intersect(r, p);
        if (h && (h->t < t || (h->t == t && p < prim))) {  // ties: the lower index, as the brute force
          t = h->t;
          prim = p;
          any = true;
        }
      }
      return any;
    });
    ASSERT_EQ(found, std::isfinite(best)) << "ray " << k;
    if (found) {
      ++hits;
      EXPECT_EQ(tMax, best);
      EXPECT_EQ(prim, bestPrim);
    }
  }
  EXPECT_GT(hits, 100);
}

}  // namespace

TEST_P(BvhQuality, NodesContainChildrenAndEveryPrimitiveOnce) {
  auto boxes = randomBoxes(5000, 1);
  Bvh bvh;
  bvh.build(boxes, centers(boxes), withQuality(GetParam()));
  checkInvariants(bvh, boxes);
}

TEST_P(BvhQuality, CoincidentCentroidsStillSplit) {
  for (int n : {1000, 70000}) {  // sequential and chunked passes
    std::vector<Bounds3> boxes(n, Bounds3{Vec3(0), Vec3(1)});
    std::vector<Vec3> cents(n, Vec3(0.5));
    Bvh bvh;
    bvh.build(boxes, cents, withQuality(GetParam()));
    checkInvariants(bvh, boxes);
  }
}

TEST_P(BvhQuality, ClosestHitsMatchBruteForce) {
  Triangles tris(3000, 4);
  Bvh bvh;
  bvh.build(tris.boxes, centers(tris.boxes), withQuality(GetParam()));
  expectClosestHitsMatch(bvh, tris, 5);
}

// Points move, topology stays: after refit the boxes contain the moved primitives and hits are still exact.
TEST_P(BvhQuality, RefitFollowsMovedPrimitives) {
  Triangles tris(3000, 6);
  Bvh bvh;
  bvh.build(tris.boxes, centers(tris.boxes), withQuality(GetParam()));
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1, 1);
  for (Vec3& p : tris.mesh.positions) p += Vec3(U(rng), U(rng), U(rng)) * 0.8;  // larger than the triangles themselves
  tris.updateBoxes();
  const std::vector<uint32_t> order = bvh.primIndices();
  bvh.refit(tris.boxes);
  EXPECT_EQ(bvh.primIndices(), order);
  checkInvariants(bvh, tris.boxes);
  Bounds3 all;
  for (const Bounds3& b : tris.boxes) all.extend(b);
  for (int a = 0; a < 3; ++a) {
    EXPECT_LE(bvh.bounds().lo[a], all.lo[a]);
    EXPECT_GE(bvh.bounds().hi[a], all.hi[a]);
  }
  expectClosestHitsMatch(bvh, tris, 8);
}

// Refit on the build's own boxes, given by primitive or in leaf order, reproduces the built boxes bit for bit (same
// outward rounding).
TEST_P(BvhQuality, RefitOnSameBoxesChangesNothing) {
  auto boxes = randomBoxes(50000, 9);
  Bvh built, refitted;
  built.build(boxes, centers(boxes), withQuality(GetParam()));
  refitted = built;
  refitted.refit(boxes);
  EXPECT_TRUE(sameTree(built, refitted));
  EXPECT_THROW(refitted.refit(std::vector<Bounds3>(boxes.begin(), boxes.end() - 1)), std::invalid_argument);
  // The same boxes given in leaf order
  std::vector<Bounds3> leafOrder;
  for (uint32_t p : built.primIndices()) leafOrder.push_back(boxes[p]);
  Bvh fromLeafOrder = built;
  fromLeafOrder.refitLeafOrder(leafOrder);
  EXPECT_TRUE(sameTree(built, fromLeafOrder));
  // The same boxes made piece by piece by a callback (never all stored in double): the same tree, every slot asked
  // for once; a piece that fails leaves the tree as it was
  Bvh fromPieces = built;
  std::vector<int> asked(leafOrder.size(), 0);
  EXPECT_TRUE(fromPieces.refitLeafOrder(leafOrder.size(), [&](std::size_t b, std::size_t e, Bounds3* out) {
    for (std::size_t k = b; k < e; ++k) out[k - b] = leafOrder[k], ++asked[k];
    return true;
  }));
  EXPECT_TRUE(sameTree(built, fromPieces));
  EXPECT_EQ(std::count(asked.begin(), asked.end(), 1), std::ptrdiff_t(asked.size()));
  Bvh failed = built;
  std::vector<Bounds3> moved = leafOrder;
  for (Bounds3& b : moved) b.hi += Vec3(1.0);
  EXPECT_FALSE(failed.refitLeafOrder(moved.size(), [&](std::size_t b, std::size_t e, Bounds3* out) {
    for (std::size_t k = b; k < e; ++k) out[k - b] = moved[k];
    return e < moved.size();  // the last piece fails
  }));
  EXPECT_TRUE(sameTree(built, failed));
  EXPECT_THROW(failed.refitLeafOrder(moved.size() - 1, [](std::size_t, std::size_t, Bounds3*) { return true; }),
               std::invalid_argument);
}

INSTANTIATE_TEST_SUITE_P(Bvh, BvhQuality, testing::Values(BvhBuildQuality::Sah, BvhBuildQuality::Fast),
                         [](const testing::TestParamInfo<BvhBuildQuality>& i) {
                           return i.param == BvhBuildQuality::Sah ? "Sah" : "Fast";
                         });

// The SAH cost tracks trace work: a refit on the same boxes keeps the cost, and a refit after the primitives trade
// places (same topology, scattered boxes) scores several times higher and visits correspondingly more nodes and
// primitives along random rays. Empty trees cost 0.
TEST(Bvh, SahCostTracksTraceWork) {
  EXPECT_EQ(Bvh().sahCost(), 0.0);
  auto boxes = randomBoxes(20000, 5);
  Bvh sah;
  sah.build(boxes, centers(boxes), withQuality(BvhBuildQuality::Sah));
  const double cost = sah.sahCost();
  EXPECT_GT(cost, 1.0);
  Bvh same = sah;
  same.refit(boxes);
  EXPECT_EQ(same.sahCost(), cost);

  // Work along random rays: wide nodes visited plus primitives tested
  auto work = [](const Bvh& bvh) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> U(-12, 12);
    uint64_t total = 0;
    for (int k = 0; k < 2000; ++k) {
      Ray r;
      r.origin = Vec3(U(rng), U(rng), U(rng));
      r.dir = glm::normalize(Vec3(U(rng), U(rng), U(rng)));
      double tMax = kInfinity;
      bvh.traverse<false>(
          r, tMax,
          [&](uint32_t, uint32_t count, double&) {
            total += count;
            return false;
          },
          &total);
    }
    return double(total);
  };
  std::vector<Bounds3> scattered = boxes;
  std::shuffle(scattered.begin(), scattered.end(), std::mt19937(11));
  Bvh moved = sah;
  moved.refit(scattered);
  EXPECT_GT(moved.sahCost(), 3.0 * cost);
  EXPECT_GT(work(moved), 3.0 * work(sah));
}

// Above 32768 primitives large nodes bin and partition in parallel chunks and subtrees are built as tasks on a
// thread pool (the ThreadSanitizer suite runs this test). The tree is a function of the input only: the same nodes
// and primitive order on 1, 2 and 3 threads.
TEST(Bvh, ParallelBuildKeepsInvariantsAndIsDeterministic) {
  auto boxes = randomBoxes(200000, 2);
  const auto cents = centers(boxes);
  for (BvhBuildQuality q : {BvhBuildQuality::Sah, BvhBuildQuality::Fast}) {
    Bvh one, two, three;
    one.build(boxes, cents, withQuality(q, 1));
    two.build(boxes, cents, withQuality(q, 2));
    three.build(boxes, cents, withQuality(q, 3));
    checkInvariants(two, boxes);
    EXPECT_TRUE(sameTree(one, two));
    EXPECT_TRUE(sameTree(one, three));
    // Refit on more threads than one, too
    for (Bounds3& b : boxes) b.hi += Vec3(0.05);
    two.refit(boxes);
    checkInvariants(two, boxes);
  }
}

// Object rebuilds pass no centroids (Bvh::build over caller-owned arrays, centroids null): the tree must be the one
// the boxes' centres give, since a background upgrade builds from validBoxes() with explicit centres and its tree
// is compared with (and swapped for) the rebuild's. Small (one thread) and parallel inputs, both builders.
TEST(Bvh, NullCentroidsBuildTheTreeOfTheBoxCentres) {
  for (int n : {1000, 100000}) {
    auto boxes = randomBoxes(n, 3);
    std::mt19937 rng(5);  // boxes of different sizes: their centres differ from any fixed corner offset
    std::uniform_real_distribution<double> grow(0.0, 2.0);
    for (Bounds3& b : boxes) b.hi += Vec3(grow(rng), grow(rng), grow(rng));
    const auto cents = centers(boxes);
    for (BvhBuildQuality q : {BvhBuildQuality::Sah, BvhBuildQuality::Fast}) {
      Bvh given, implied;
      given.build(boxes, cents, withQuality(q, 2));
      implied.build(boxes.data(), nullptr, boxes.size(), withQuality(q, 2));
      checkInvariants(implied, boxes);
      EXPECT_TRUE(sameTree(given, implied)) << n << " primitives";
      EXPECT_EQ(given.bounds().lo, implied.bounds().lo);
      EXPECT_EQ(given.bounds().hi, implied.bounds().hi);
    }
  }
}

// Single-primitive leaves need more wide nodes per primitive than a subtree reserves up front (its nodes then move
// to storage of their own): the tree stays whole and the same on 1 and 2 threads.
TEST(Bvh, ParallelBuildOfSinglePrimitiveLeaves) {
  auto boxes = randomBoxes(100000, 11);
  const auto cents = centers(boxes);
  for (BvhBuildQuality q : {BvhBuildQuality::Sah, BvhBuildQuality::Fast}) {
    BvhBuildOptions opt = withQuality(q, 1);
    opt.maxLeafSize = 1;
    opt.traversalCost = 0.01;
    Bvh one, two;
    one.build(boxes, cents, opt);
    opt.threads = 2;
    two.build(boxes, cents, opt);
    EXPECT_GT(two.nodes().size(), boxes.size() / 3);
    checkInvariants(two, boxes);
    EXPECT_TRUE(sameTree(one, two));
  }
}

// The SAH build is the better tree: lower expected cost than the Morton build of the same boxes.
TEST(Bvh, SahBuildBeatsFastBuildOnSahCost) {
  auto boxes = randomBoxes(100000, 10);
  const auto cents = centers(boxes);
  Bvh sah, fast;
  sah.build(boxes, cents, withQuality(BvhBuildQuality::Sah));
  fast.build(boxes, cents, withQuality(BvhBuildQuality::Fast));
  EXPECT_LT(sah.sahCost(), 0.95 * fast.sahCost());
}

// Through the scene (two levels, leaf-ordered triangle copies) as well as through the bare tree.
TEST(Bvh, ClosestHitMatchesBruteForce) {
  Triangles tris(2000, 3);
  Scene scene;
  scene.addInstance(scene.addMesh(TriangleMesh(tris.mesh)), Mat4(1.0), scene.addMaterial(Material{}));
  scene.commit();
  std::mt19937 rng(4);
  int hits = 0;
  for (int k = 0; k < 2000; ++k) {
    const Ray r = randomRay(rng);
    uint32_t bestPrim = 0;
    const double best = tris.bruteForce(r, bestPrim);
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
        expected[p] = exactSlab(boxes[p], r) ? 1 : 0;
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
