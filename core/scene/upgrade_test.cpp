// The background upgrade (upgrade.cpp): a large new mesh is traced through its fast tree until its SAH tree, built
// on a background thread, is swapped in; frames back to back cannot hold it off for ever; replaced geometry's build
// is dropped. And the builds it relies on: a cancelled build, object rebuilds independent of the core count.
#include "scene/scene.h"
#include "scene/scene_test_util.h"
#include "scenes/scenes.h"
#include "util/parallel.h"  // hardwareThreads()

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <future>
#include <limits>
#include <memory>
#include <optional>
#include <random>
#include <thread>
#include <vector>
#ifdef __linux__
#include <sched.h>
#endif

using namespace whitted;
using namespace whitted::scene_test;

namespace {

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
  expectSameHits(s, ref, 1.2);

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
    expectSameHits(s, ref, 1.2);
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
  expectSameHits(s, ref, 1.2);
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
  expectSameHits(s, ref, 1.2);
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
  expectSameHits(s, ref, 1.2);
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
  expectSameHits(s, ref, 1.2);

  s.setUpgradeHookForTesting({});
  s.startUpgrades();
  s.waitForUpgrades();
  st = s.commit();
  EXPECT_EQ(st.objectsUpgraded, 1);
  EXPECT_EQ(s.stats().fastTrees, 0u);
  expectSameHits(s, ref, 1.2);
}
