// Scene editing without rebuilds: attribute-only updates keep object BVHs, textures are replaced and freed in
// place (ids reused, memory not growing).
#include "util/parallel.h"  // hardwareThreads()
#include "scene/scene.h"
#include "scenes/scenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <future>
#include <limits>
#include <memory>
#include <optional>
#include <random>
#include <thread>
#ifdef __linux__
#include <sched.h>
#endif

using namespace whitted;

namespace {

Texture solid(int w, uint8_t r, uint8_t g, uint8_t b) {
  Texture t;
  t.width = w;
  t.height = 1;
  for (int i = 0; i < w; ++i) t.rgba.insert(t.rgba.end(), {r, g, b, 255});
  return t;
}

/// A ray from z = 4 down toward the xy plane, starting within +-width of the z axis.
Ray rayFromAbove(std::mt19937& rng, double width) {
  std::uniform_real_distribution<double> U(-1, 1);
  Ray r;
  r.origin = Vec3(width * U(rng), width * U(rng), 4.0);
  r.dir = glm::normalize(Vec3(0.2 * U(rng), 0.2 * U(rng), -1.0));
  return r;
}

/// Closest hits of 2000 rays from above through the scene's one mesh equal a brute-force test over mesh.
void expectHitsMatchBruteForce(const Scene& s, const TriangleMesh& mesh) {
  std::mt19937 rng(9);
  int hits = 0;
  for (int k = 0; k < 2000; ++k) {
    const Ray r = rayFromAbove(rng, 1.5);
    double best = kInfinity;
    uint32_t bestPrim = 0;
    for (uint32_t i = 0; i < mesh.triangles.size(); ++i) {
      const glm::uvec3& t = mesh.triangles[i];
      if (!isFinite(mesh.positions[t.x]) || !isFinite(mesh.positions[t.y]) || !isFinite(mesh.positions[t.z])) continue;
      auto h = intersectTriangle(r, mesh.positions[t.x], mesh.positions[t.y], mesh.positions[t.z]);
      if (h && h->t < best) {
        best = h->t;
        bestPrim = i;
      }
    }
    Hit h;
    EXPECT_EQ(s.intersect(r, h), std::isfinite(best));
    if (std::isfinite(best)) {
      ++hits;
      EXPECT_EQ(h.t, best);
      EXPECT_EQ(h.prim, bestPrim);
      if (!mesh.triangleColors.empty()) EXPECT_EQ(s.surface(r, h).color, mesh.triangleColors[bestPrim]);
    }
  }
  EXPECT_GT(hits, 500);
}

/// Closest hits (distance, primitive, shading normal, colour) of 3000 rays through scenes a and b are the same.
void expectSameHits(const Scene& a, const Scene& b) {
  std::mt19937 rng(5);
  int hits = 0;
  for (int k = 0; k < 3000; ++k) {
    const Ray r = rayFromAbove(rng, 1.2);
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

/// A mesh large enough for the background upgrade, with colours per triangle and a few invalid triangles (a
/// non-finite vertex), so the leaf order maps valid and invalid ones.
TriangleMesh upgradeMesh(const Vec3& center) {
  TriangleMesh m = makeSphereMesh(center, 1.0, 320, 160);
  m.triangleColors.resize(m.triangles.size());
  for (std::size_t i = 0; i < m.triangleColors.size(); ++i)
    m.triangleColors[i] = Color4(float(i % 7) / 7.0f, float(i % 11) / 11.0f, float(i % 13) / 13.0f, 1.0f);
  m.positions[m.triangles[777].y] = Vec3(std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0);
  return m;
}

/// A scene of one instance of mesh, committed; with the background upgrade or with the SAH build only.
uint32_t addCommitted(Scene& s, const TriangleMesh& mesh) {
  const uint32_t o = s.addMesh(mesh);
  s.addInstance(o, Mat4(1.0), s.addMaterial(Material{}));
  s.commit();
  return o;
}

}  // namespace

// New colours on the same positions and triangles: no object BVH and no top level rebuilt, the new colours are
// used; moved positions: rebuilt.
TEST(Scene, UpdateMeshKeepsBvhWhenOnlyAttributesChange) {
  Scene s;
  TriangleMesh m = makeSphereMesh(Vec3(0.0), 1.0, 16, 8);
  m.vertexColors.assign(m.positions.size(), Color4(1, 0, 0, 1));
  uint32_t o = s.addMesh(m);
  Material mat;
  mat.lighting = false;
  mat.colorSource = ColorSource::ScalarsAmbientAndDiffuse;
  s.addInstance(o, Mat4(1.0), s.addMaterial(mat));
  EXPECT_EQ(s.commit().objectsRebuilt, 1);

  m.vertexColors.assign(m.positions.size(), Color4(0, 2, 0, 1));  // out of range: clamped to 1
  EXPECT_FALSE(s.updateMesh(o, m));
  CommitStats st = s.commit();
  EXPECT_EQ(st.objectsRebuilt, 0);
  EXPECT_FALSE(st.topLevelRebuilt);
  Ray r;
  r.origin = Vec3(0.1, 0.2, 5.0);
  r.dir = Vec3(0, 0, -1);
  Hit h;
  ASSERT_TRUE(s.intersect(r, h));
  SurfacePoint sp = s.surface(r, h);
  EXPECT_EQ(sp.color, Color4(0, 1, 0, 1));

  m.positions[5].x += 1e-12;  // any change of geometry updates the BVH (same triangles: refit)
  EXPECT_TRUE(s.updateMesh(o, m));
  EXPECT_EQ(s.commit().objectsRefit, 1);

  // Spheres and tubes alike
  SphereSet sp1;
  sp1.centers = {Vec3(3, 0, 0)};
  sp1.radii = {0.5};
  uint32_t so = s.addSpheres(sp1);
  TubeSet cs;
  cs.p0 = {Vec3(-3, 0, 0)};
  cs.p1 = {Vec3(-3, 1, 0)};
  cs.radii = {0.2};
  uint32_t co = s.addTubes(cs);
  s.addInstance(so, Mat4(1.0), 0);
  s.addInstance(co, Mat4(1.0), 0);
  s.commit();
  sp1.colors = {Color4(0, 0, 1, 1)};
  cs.colors0 = {Color4(0, 0, 1, 1)};
  EXPECT_FALSE(s.updateSpheres(so, sp1));
  EXPECT_FALSE(s.updateTubes(co, cs));
  EXPECT_EQ(s.commit().objectsRebuilt, 0);
  cs.radii = {0.25};
  EXPECT_TRUE(s.updateTubes(co, cs));
  EXPECT_EQ(s.commit().objectsRefit, 1);
  cs.p0.push_back(Vec3(-3, 1, 0));  // one tube more: rebuilt
  cs.p1.push_back(Vec3(-2, 1, 0));
  EXPECT_TRUE(s.updateTubes(co, cs));
  EXPECT_EQ(s.commit().objectsRebuilt, 1);
}

// A committed mesh keeps its triangles in BVH leaf order internally: mesh() still returns them as given, hits
// report the index as given (triangle colours follow it), an unchanged update keeps the BVH, a reordered triangle
// list is a geometry change, and invalid triangles (left out of the BVH) keep their place too.
TEST(Scene, LeafOrderIsInvisibleOutsideTheObject) {
  TriangleMesh m = makeSphereMesh(Vec3(0.0), 1.0, 16, 8);
  m.triangles.insert(m.triangles.begin() + 7, glm::uvec3(0, 0, 0));  // degenerate: invalid
  m.triangles.push_back(glm::uvec3(0, 1, 99999));                    // index out of range: invalid
  for (std::size_t i = 0; i < m.triangles.size(); ++i) m.triangleColors.push_back(Color4(float(i) / 1024.0f, 0, 0, 1));
  Scene s;
  uint32_t o = s.addMesh(m);
  Material mat;
  mat.lighting = false;
  s.addInstance(o, Mat4(1.0), s.addMaterial(mat));
  CommitStats st = s.commit();
  EXPECT_EQ(st.invalidPrimitives, 2u);
  EXPECT_EQ(s.mesh(o).triangles, m.triangles);
  EXPECT_EQ(s.stats().triangles, m.triangles.size() - 2);

  // Every hit's primitive, checked by brute force over the mesh as given
  int hits = 0;
  for (int i = 0; i < 200; ++i) {
    Ray r;
    r.origin = Vec3(0.01 * (i % 20) - 0.1, 0.01 * (i / 20) - 0.05, 5.0);
    r.dir = Vec3(0.02 * (i % 7), -0.03 * (i % 5), -1.0);
    Hit h;
    if (!s.intersect(r, h)) continue;
    ++hits;
    const glm::uvec3& t = m.triangles[h.prim];
    auto ph = intersectTriangle(r, m.positions[t.x], m.positions[t.y], m.positions[t.z]);
    ASSERT_TRUE(ph);
    EXPECT_EQ(ph->t, h.t);
    EXPECT_EQ(s.surface(r, h).color, m.triangleColors[h.prim]);
  }
  EXPECT_GT(hits, 100);

  EXPECT_FALSE(s.updateMesh(o, m));
  EXPECT_EQ(s.mesh(o).triangles, m.triangles);
  std::swap(m.triangles[0], m.triangles[1]);
  EXPECT_TRUE(s.updateMesh(o, m));
  EXPECT_EQ(s.commit().objectsRebuilt, 1);
  EXPECT_EQ(s.mesh(o).triangles, m.triangles);
}

// setTexture replaces in place; removeTexture frees the texels and addTexture reuses the id: 1000 replace or
// remove/add cycles leave the slot count and the texture memory where they were.
TEST(Scene, TexturesAreReplacedAndFreedInPlace) {
  Scene s;
  uint32_t a = s.addTexture(solid(256, 255, 0, 0));
  uint32_t b = s.addTexture(solid(64, 0, 255, 0));
  EXPECT_EQ(s.stats().textures, 2u);
  const std::size_t bytes = s.stats().textureBytes;
  for (int i = 0; i < 1000; ++i) {
    s.setTexture(a, solid(256, uint8_t(i), 0, 0));
    s.removeTexture(b);
    EXPECT_EQ(s.addTexture(solid(64, 0, uint8_t(i), 0)), b);
  }
  EXPECT_EQ(s.textureCount(), 2u);
  EXPECT_EQ(s.stats().textureBytes, bytes);
  EXPECT_NEAR(s.texture(a).sample(0.5f, 0.5f).r, 999 % 256 / 255.0f, 1e-6f);
  s.removeTexture(a);
  EXPECT_EQ(s.stats().textures, 1u);
  EXPECT_EQ(s.stats().textureBytes, 64u * 4u);
  EXPECT_EQ(s.texture(a).sample(0.5f, 0.5f), Color4(1.0f));  // a removed texture samples white
}

// A geometry change on an object that had been built (a time step, a new contour value) is rebuilt with the fast
// builder; its first build, and a new object, use the SAH builder. Closest hits through the fast tree equal a
// brute-force test of every triangle.
TEST(Scene, ReplacedGeometryIsRebuiltFastAndStillExact) {
  Scene s;
  uint32_t o = s.addMesh(makeSphereMesh(Vec3(0.0), 1.0, 24, 12));
  s.addInstance(o, Mat4(1.0), s.addMaterial(Material{}));
  CommitStats st = s.commit();
  EXPECT_EQ(st.objectsRebuilt, 1);
  EXPECT_EQ(st.objectsFastBuilt, 0);

  const TriangleMesh moved = makeSphereMesh(Vec3(0.2, -0.1, 0.05), 0.9, 32, 16);
  EXPECT_TRUE(s.updateMesh(o, moved));
  st = s.commit();
  EXPECT_EQ(st.objectsRebuilt, 1);
  EXPECT_EQ(st.objectsFastBuilt, 1);

  uint32_t fresh = s.addMesh(makeSphereMesh(Vec3(5.0, 0.0, 0.0), 1.0, 8, 4));
  s.addInstance(fresh, Mat4(1.0), 0);
  st = s.commit();
  EXPECT_EQ(st.objectsRebuilt, 1);
  EXPECT_EQ(st.objectsFastBuilt, 0);

  expectHitsMatchBruteForce(s, moved);  // the fresh sphere at x = 5 is out of these rays' way
}

// Moved points on the same triangles (a deforming mesh's time step) refit the BVH instead of rebuilding it, and
// closest hits through the refit tree equal a brute-force test; a point moved to infinity (an invalid triangle)
// falls back to a rebuild, and hits stay exact.
TEST(Scene, MovedPointsOnSameTrianglesAreRefit) {
  Scene s;
  TriangleMesh m = makeSphereMesh(Vec3(0.0), 1.0, 24, 12);
  m.triangleColors.assign(m.triangles.size(), Color4(1.0f));
  uint32_t o = s.addMesh(m);
  s.addInstance(o, Mat4(1.0), s.addMaterial(Material{}));
  s.commit();

  // A wave over the sphere and a shift: every box moves
  for (Vec3& p : m.positions) p = p * (1.0 + 0.2 * std::sin(3.0 * p.y)) + Vec3(0.3, -0.2, 0.1);
  for (std::size_t i = 0; i < m.triangleColors.size(); ++i) m.triangleColors[i] = Color4(float(i % 7) / 7.0f, 0, 0, 1);
  EXPECT_TRUE(s.updateMesh(o, m));
  CommitStats st = s.commit();
  EXPECT_EQ(st.objectsRefit, 1);
  EXPECT_EQ(st.objectsRebuilt, 0);
  EXPECT_TRUE(st.topLevelRebuilt);
  expectHitsMatchBruteForce(s, m);
  EXPECT_EQ(s.mesh(o).triangles, m.triangles);  // the order given, as before

  m.positions[3].x = kInfinity;  // its triangles become invalid: rebuilt instead
  EXPECT_TRUE(s.updateMesh(o, m));
  st = s.commit();
  EXPECT_EQ(st.objectsRefit, 0);
  EXPECT_EQ(st.objectsRebuilt, 1);
  EXPECT_GT(st.invalidPrimitives, 0u);
  expectHitsMatchBruteForce(s, m);
}

// A refit whose tree would trace much slower (points that trade places: every triangle now spans the sphere, the
// kept topology groups far-apart triangles) is rebuilt instead; a gentle deformation keeps its refit. Hits stay
// exact either way.
TEST(Scene, RefitThatTracesTooSlowlyIsRebuilt) {
  Scene s;
  TriangleMesh m = makeSphereMesh(Vec3(0.0), 1.0, 48, 24);
  uint32_t o = s.addMesh(m);
  s.addInstance(o, Mat4(1.0), s.addMaterial(Material{}));
  s.commit();

  for (Vec3& p : m.positions) p *= 1.0 + 0.05 * std::sin(4.0 * p.x);
  EXPECT_TRUE(s.updateMesh(o, m));
  CommitStats st = s.commit();
  EXPECT_EQ(st.objectsRefit, 1);
  EXPECT_EQ(st.objectsRefitRejected, 0);
  EXPECT_GT(st.refitCostRatio, 0.5);
  EXPECT_LE(st.refitCostRatio, Object::kRefitRebuildRatio);
  expectHitsMatchBruteForce(s, m);

  std::shuffle(m.positions.begin(), m.positions.end(), std::mt19937(4));
  EXPECT_TRUE(s.updateMesh(o, m));
  st = s.commit();
  EXPECT_EQ(st.objectsRefit, 0);
  EXPECT_EQ(st.objectsRefitRejected, 1);
  EXPECT_GT(st.refitCostRatio, Object::kRefitRebuildRatio);
  EXPECT_EQ(st.objectsRebuilt, 1);
  EXPECT_EQ(st.objectsFastBuilt, 1);
  expectHitsMatchBruteForce(s, m);
  EXPECT_NEAR(s.object(o).refitCostRatio(), 1.0, 1e-12);  // a fresh tree
}

// An object taken out of the scene (a time cache keeping an earlier step) leaves its id free for other geometry,
// and restored later it needs no rebuild: the same hits as before, only the top level is rebuilt.
TEST(Scene, TakenObjectIsRestoredWithoutRebuild) {
  Scene s;
  TriangleMesh first = makeSphereMesh(Vec3(0.0), 1.0, 24, 12);
  uint32_t o = s.addMesh(first);
  s.addInstance(o, Mat4(1.0), s.addMaterial(Material{}));
  s.commit();
  Object kept = s.takeObject(o);
  EXPECT_EQ(s.stats().triangles, 0u);

  TriangleMesh second = makeSphereMesh(Vec3(0.3, 0, 0), 1.1, 10, 5);  // another step: other topology
  s.setMesh(o, second);
  CommitStats st = s.commit();
  EXPECT_EQ(st.objectsRebuilt, 1);
  EXPECT_EQ(st.objectsFastBuilt, 1);  // the id had geometry before: a replacement
  expectHitsMatchBruteForce(s, second);

  Object copy = s.object(o);  // keep this step too (a copy), then bring the first back
  s.restoreObject(o, std::move(kept));
  st = s.commit();
  EXPECT_EQ(st.objectsRebuilt, 0);
  EXPECT_EQ(st.objectsRefit, 0);
  EXPECT_TRUE(st.topLevelRebuilt);
  expectHitsMatchBruteForce(s, first);
  EXPECT_EQ(s.mesh(o).triangles, first.triangles);
  s.restoreObject(o, std::move(copy));
  EXPECT_EQ(s.commit().objectsRebuilt, 0);
  expectHitsMatchBruteForce(s, second);
}

// Instance colours: many instances of one object with one material, each seen with its own colour (over the
// object's own colours), sanitised; clearing one restores the object's colour.
TEST(Scene, InstanceColorsReplaceObjectColors) {
  Scene s;
  SphereSet balls;
  balls.centers = {Vec3(0.0)};
  balls.radii = {0.4};
  balls.colors = {Color4(0.5f, 0.5f, 0.5f, 1.0f)};
  const uint32_t o = s.addSpheres(balls);
  Material mat;
  mat.colorSource = ColorSource::ScalarsAmbientAndDiffuse;
  const uint32_t m = s.addMaterial(mat);
  std::vector<uint32_t> ids;
  for (int i = 0; i < 3; ++i) {
    Mat4 place(1.0);
    place[3] = Vec4(2.0 * i, 0.0, 0.0, 1.0);
    ids.push_back(s.addInstance(o, place, m));
  }
  s.setInstanceColor(ids[0], Color4(1, 0, 0, 1));
  s.setInstanceColor(ids[1], Color4(0, std::nanf(""), 2, -1));  // sanitised like geometry colours
  s.commit();
  auto colorAt = [&](double x) {
    Ray r;
    r.origin = Vec3(x, 0.0, 5.0);
    r.dir = Vec3(0, 0, -1);
    Hit h;
    EXPECT_TRUE(s.intersect(r, h));
    return s.surface(r, h).color;
  };
  EXPECT_EQ(colorAt(0.0), Color4(1, 0, 0, 1));
  EXPECT_EQ(colorAt(2.0), Color4(0, 0, 1, 0));
  EXPECT_EQ(colorAt(4.0), Color4(0.5f, 0.5f, 0.5f, 1.0f));
  s.clearInstanceColor(ids[0]);
  EXPECT_EQ(colorAt(0.0), Color4(0.5f, 0.5f, 0.5f, 1.0f));
  EXPECT_EQ(s.stats().spheres, 1u);  // one object for every instance
}

// Background upgrade: a new large mesh is built with the fast builder, its SAH tree is built on a background thread
// after the frame and swapped in by the first commit after it finished, never before: commits while the build runs
// (here held after building, before reporting) trace the complete fast tree. Hits equal the SAH-only scene's
// throughout, and the swapped-in tree and leaf order are exactly the SAH build's.
TEST(Scene, BackgroundUpgradeSwapsInTheSahTreeOnceBuilt) {
  const TriangleMesh mesh = upgradeMesh(Vec3(0.0));
  ASSERT_GE(mesh.triangles.size(), Scene::kUpgradeMin);
  Scene ref;
  const uint32_t ro = addCommitted(ref, mesh);

  Scene s;
  s.setBackgroundUpgrade(true);
  const uint32_t o = s.addMesh(mesh);
  s.addInstance(o, Mat4(1.0), s.addMaterial(Material{}));
  CommitStats st = s.commit();
  EXPECT_EQ(st.objectsFastBuilt, 1);
  EXPECT_EQ(s.stats().fastTrees, 1u);
  EXPECT_GT(st.invalidPrimitives, 0u);  // the triangles around the NaN vertex
  EXPECT_NE(s.object(o).bvh.sahCost(), ref.object(ro).bvh.sahCost());
  expectSameHits(s, ref);

  std::promise<void> release;
  std::shared_future<void> gate = release.get_future().share();
  std::atomic<bool> built{false};
  s.setUpgradeHookForTesting([&] {
    built = true;
    gate.wait();
  });
  s.startUpgrades();
  EXPECT_TRUE(s.upgradePending());
  while (!built) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  for (int frame = 0; frame < 3; ++frame) {
    st = s.commit();
    EXPECT_EQ(st.objectsUpgraded, 0);
    EXPECT_EQ(s.stats().fastTrees, 1u);
    expectSameHits(s, ref);
  }
  release.set_value();
  s.waitForUpgrades();
  st = s.commit();
  EXPECT_EQ(st.objectsUpgraded, 1);
  EXPECT_EQ(st.objectsRebuilt, 0);
  EXPECT_EQ(s.stats().fastTrees, 0u);
  EXPECT_FALSE(s.upgradePending());
  EXPECT_EQ(s.object(o).bvh.sahCost(), ref.object(ro).bvh.sahCost());
  EXPECT_EQ(s.object(o).bvh.primIndices(), ref.object(ro).bvh.primIndices());
  EXPECT_EQ(s.object(o).primOrder, ref.object(ro).primOrder);
  EXPECT_EQ(s.mesh(o).triangles, mesh.triangles);
  expectSameHits(s, ref);
  s.startUpgrades();  // nothing left to upgrade
  EXPECT_FALSE(s.upgradePending());
}

/// A spinning thread on every core while it lives: frames back to back, as a background build sees them.
struct BusyCores {
  std::atomic<bool> stop{false};
  std::vector<std::thread> threads;
  BusyCores() {
    for (int i = 0; i < hardwareThreads(); ++i)
      threads.emplace_back([this] {
        while (!stop.load(std::memory_order_relaxed)) {
        }
      });
  }
  ~BusyCores() {
    stop = true;
    for (std::thread& t : threads) t.join();
  }
};

// Frames back to back leave the idle-priority build no idle core (here: a spinning thread per core): it is raised
// to normal priority after kUpgradeIdleCommits commits, and swapped in at the latest by the kUpgradeWaitCommits-th
// commit, never left pending for ever.
TEST(Scene, BackgroundUpgradeLandsWhileFramesKeepComing) {
  const TriangleMesh mesh = upgradeMesh(Vec3(0.0));
  Scene ref;
  const uint32_t ro = addCommitted(ref, mesh);
  Scene s;
  s.setBackgroundUpgrade(true);
  const uint32_t o = addCommitted(s, mesh);
  ASSERT_EQ(s.stats().fastTrees, 1u);

  std::optional<BusyCores> busy(std::in_place);
  s.startUpgrades();
  // A scene change waits until the build has read its inputs, by when it has lowered its priority
  s.addSpheres(SphereSet{{Vec3(5.0, 0.0, 0.0)}, {0.5}, {}});
  int upgraded = 0, at = 0;
  for (int commit = 1; commit <= Scene::kUpgradeWaitCommits && upgraded == 0; ++commit) {
    upgraded += s.commit().objectsUpgraded;
    at = commit;
  }
  busy.reset();
  EXPECT_EQ(upgraded, 1) << "still pending after " << at << " commits";
  EXPECT_FALSE(s.upgradePending());
  EXPECT_EQ(s.stats().fastTrees, 0u);
  EXPECT_EQ(s.object(o).bvh.primIndices(), ref.object(ro).bvh.primIndices());
  expectSameHits(s, ref);
}

// Where the process may not raise the idle build's priority (an ordinary user: no CAP_SYS_NICE), frames back to back
// must not wait for it at the (kUpgradeIdleCommits + 1)-th commit: the build starts again at normal priority and
// lands while commits keep coming, before the kUpgradeWaitCommits-th would wait for it.
TEST(Scene, BackgroundUpgradeRestartsWhereItsPriorityCannotBeRaised) {
  const TriangleMesh mesh = upgradeMesh(Vec3(0.0));
  Scene ref;
  const uint32_t ro = addCommitted(ref, mesh);
  Scene s;
  s.setBackgroundUpgrade(true);
  s.setUpgradeRaiseDeniedForTesting(true);
  const uint32_t o = addCommitted(s, mesh);
  ASSERT_EQ(s.stats().fastTrees, 1u);

  std::optional<BusyCores> busy(std::in_place);  // frames: the idle build makes (almost) no progress
  s.startUpgrades();
  s.addSpheres(SphereSet{{Vec3(5.0, 0.0, 0.0)}, {0.5}, {}});  // waits until the build read its inputs and lowered
  int upgraded = 0, restartedAt = 0, waitedAt = 0, at = 0;
  for (int commit = 1; commit <= Scene::kUpgradeWaitCommits && upgraded == 0; ++commit) {
    const CommitStats st = s.commit();
    upgraded += st.objectsUpgraded;
    if (st.upgradeRestarted) restartedAt = commit;
    if (st.waitedForUpgrade) waitedAt = commit;
    at = commit;
    if (restartedAt) {  // the restarted build shares the cores with the busy threads: it finishes (up to a minute)
      for (int ms = 0; ms < 60000 && s.upgradePending() && !s.upgradeFinished(); ms += 10)
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }
  busy.reset();
  EXPECT_EQ(restartedAt, Scene::kUpgradeIdleCommits + 1);
  EXPECT_EQ(waitedAt, 0) << "a commit waited for the build";
  EXPECT_EQ(upgraded, 1) << "still pending after " << at << " commits";
  EXPECT_EQ(at, restartedAt + 1);  // finished at normal priority while the busy threads ran
  EXPECT_FALSE(s.upgradePending());
  EXPECT_EQ(s.stats().fastTrees, 0u);
  EXPECT_EQ(s.object(o).bvh.primIndices(), ref.object(ro).bvh.primIndices());
  expectSameHits(s, ref);
}

// A cancelled build leaves an empty tree (here cancelled before it starts), with either builder; the same options
// without the flag build the whole tree.
TEST(Bvh, CancelledBuildLeavesAnEmptyTree) {
  const TriangleMesh mesh = upgradeMesh(Vec3(0.0));
  std::vector<Bounds3> boxes;
  std::vector<Vec3> centroids;
  for (const auto& t : mesh.triangles) {
    Bounds3 b;
    for (int k = 0; k < 3; ++k) b.extend(mesh.positions[t[k]]);
    if (!isFinite(b.lo) || !isFinite(b.hi)) continue;
    boxes.push_back(b);
    centroids.push_back(b.center());
  }
  for (BvhBuildQuality q : {BvhBuildQuality::Sah, BvhBuildQuality::Fast}) {
    std::atomic<bool> cancel{true};
    BvhBuildOptions opt;
    opt.quality = q;
    opt.cancel = &cancel;
    Bvh bvh;
    bvh.build(boxes, centroids, opt);
    EXPECT_TRUE(bvh.empty());
    EXPECT_TRUE(bvh.primIndices().empty());
    cancel = false;
    bvh.build(boxes, centroids, opt);
    EXPECT_FALSE(bvh.empty());
    EXPECT_EQ(bvh.primIndices().size(), boxes.size());
  }
}

#ifdef __linux__
// Object rebuilds split their box and reordering passes over all cores: the tree, the leaf order and the stored
// triangles must not depend on how many (here: all cores against one, with the fast and the SAH builder, on a mesh
// with invalid triangles, so the pieces are compacted).
TEST(Scene, ObjectRebuildDoesNotDependOnTheCoreCount) {
  const TriangleMesh mesh = upgradeMesh(Vec3(0.0));
  for (bool fast : {false, true}) {
    auto build = [&] {
      auto s = std::make_unique<Scene>();
      s->setBackgroundUpgrade(fast);  // large new geometry: the fast builder
      addCommitted(*s, mesh);
      return s;
    };
    const std::unique_ptr<Scene> all = build();
    cpu_set_t saved, one;
    ASSERT_EQ(sched_getaffinity(0, sizeof saved, &saved), 0);
    CPU_ZERO(&one);
    for (int c = 0; c < CPU_SETSIZE; ++c)
      if (CPU_ISSET(c, &saved)) {
        CPU_SET(c, &one);
        break;
      }
    ASSERT_EQ(sched_setaffinity(0, sizeof one, &one), 0);
    ASSERT_EQ(hardwareThreads(), 1);
    const std::unique_ptr<Scene> single = build();
    ASSERT_EQ(sched_setaffinity(0, sizeof saved, &saved), 0);
    const Object &a = all->object(0), &b = single->object(0);
    EXPECT_EQ(a.builtQuality, fast ? BvhBuildQuality::Fast : BvhBuildQuality::Sah);
    EXPECT_EQ(a.bvh.primIndices(), b.bvh.primIndices());
    EXPECT_EQ(a.primOrder, b.primOrder);
    EXPECT_FALSE(a.primOrder.empty());  // some triangles were left out
    ASSERT_EQ(a.bvh.nodes().size(), b.bvh.nodes().size());
    EXPECT_EQ(std::memcmp(a.bvh.nodes().data(), b.bvh.nodes().data(), a.bvh.nodes().size() * sizeof(BvhWideNode)), 0);
    EXPECT_EQ(a.bounds.lo, b.bounds.lo);
    EXPECT_EQ(a.bounds.hi, b.bounds.hi);
    EXPECT_EQ(std::get<TriangleMesh>(a.geometry).triangles, std::get<TriangleMesh>(b.geometry).triangles);
    // The rebuild (boxes only: centroids implied) builds the tree that a background build from validBoxes()
    // (explicit centres) gives: the upgrade's swap relies on it
    std::vector<Bounds3> boxes;
    std::vector<Vec3> centroids;
    std::vector<uint32_t> valid;
    a.validBoxes(boxes, centroids, valid);
    BvhBuildOptions opt;
    opt.quality = a.builtQuality;
    Bvh fromValid;
    fromValid.build(boxes, centroids, opt);
    EXPECT_EQ(fromValid.primIndices(), a.bvh.primIndices());
    ASSERT_EQ(fromValid.nodes().size(), a.bvh.nodes().size());
    EXPECT_EQ(std::memcmp(fromValid.nodes().data(), a.bvh.nodes().data(), a.bvh.nodes().size() * sizeof(BvhWideNode)),
              0);
    all->waitForUpgrades();
  }
}
#endif

// A background build of geometry replaced while it ran is dropped; the new geometry gets its own upgrade.
TEST(Scene, BackgroundUpgradeOfReplacedGeometryIsDropped) {
  Scene s;
  s.setBackgroundUpgrade(true);
  const uint32_t o = addCommitted(s, upgradeMesh(Vec3(0.0)));
  std::promise<void> release;
  std::shared_future<void> gate = release.get_future().share();
  s.setUpgradeHookForTesting([gate] { gate.wait(); });
  s.startUpgrades();
  const TriangleMesh moved = upgradeMesh(Vec3(0.1, -0.05, 0.0));
  EXPECT_TRUE(s.updateMesh(o, moved));
  release.set_value();
  s.waitForUpgrades();
  CommitStats st = s.commit();
  EXPECT_EQ(st.objectsUpgraded, 0);
  EXPECT_EQ(st.objectsFastBuilt, 1);
  Scene ref;
  addCommitted(ref, moved);
  expectSameHits(s, ref);

  s.setUpgradeHookForTesting({});
  s.startUpgrades();
  s.waitForUpgrades();
  st = s.commit();
  EXPECT_EQ(st.objectsUpgraded, 1);
  EXPECT_EQ(s.stats().fastTrees, 0u);
  expectSameHits(s, ref);
}
