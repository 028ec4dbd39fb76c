// The background SAH upgrade of a Scene (see Scene::setBackgroundUpgrade): one build thread at idle scheduling
// priority builds the SAH trees of the objects that got a fast tree, commit() presses it when frames leave it no
// idle core (raise, restart at normal priority, or wait) and swaps in the trees still current. The rest of the
// scene (registry, commit steps) is in scene.cpp.
#include "scene/scene.h"

#include <atomic>
#include <condition_variable>
#include <mutex>
#include <thread>
#ifdef __linux__
#include <pthread.h>
#include <sched.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>
#endif

namespace whitted {


/// One background build: the SAH trees of the objects that had a fast tree when it started. The thread reads those
/// objects first (inputsRead: until then nothing may change objects_), then builds from its own copies.
struct Scene::Upgrade {
  struct Item {
    uint32_t object = 0;
    uint64_t version = 0;  ///< Object::treeVersion it was started from: swapped in only if still current.
    std::vector<uint32_t> valid;
    Bvh tree;
  };
  std::vector<Item> items;
  std::mutex mutex;
  std::condition_variable read;
  bool inputsRead = false;  // guarded by mutex
  bool lowered = false;     // runs at idle priority (guarded by mutex)
  bool raised = false;      // taken back to normal priority: never lowered again (guarded by mutex)
  long tid = 0;             // its thread's id (Linux), for the nice fallback
  bool raiseDenied = false;  // for tests: raise() fails (as without CAP_SYS_NICE)
  std::atomic<bool> finished{false};
  std::atomic<bool> cancel{false};  // stop building: the trees are not wanted (finished then stays false)
  bool hasHook = false;             // a test's hook: the build is always waited for, never left to itself
  int commits = 0;  ///< Commits since it (or the build it restarts) started (the scene's thread only).
  // A thread of its own, not the shared pool's (util/parallel.h): it runs at idle priority and may be raised back,
  // restarted or waited for, and a pool worker lowered to SCHED_IDLE would carry that into the next frame's tiles.
  // It builds with one thread, so it never uses the pool either.
  std::thread thread;

  void run(const std::vector<Object>& objects, const std::function<void()>& hook) {
    std::vector<std::vector<Bounds3>> boxes(items.size());
    std::vector<std::vector<Vec3>> centroids(items.size());
    for (std::size_t i = 0; i < items.size(); ++i)
      objects[items[i].object].validBoxes(boxes[i], centroids[i], items[i].valid);
    {
      std::lock_guard<std::mutex> lock(mutex);
      inputsRead = true;
      // The build itself runs only on cores nothing else wants (the time between frames, not a frame's cores);
      // the read above ran at normal priority, as a scene change may be waiting for it
      if (!hook && !raised) lowered = setIdlePriority();
    }
    read.notify_all();
    BvhBuildOptions opt;
    opt.quality = BvhBuildQuality::Sah;
    opt.threads = 1;
    opt.cancel = &cancel;
    for (std::size_t i = 0; i < items.size(); ++i) {
      items[i].tree.build(boxes[i], centroids[i], opt);
      boxes[i] = {};
      centroids[i] = {};
      if (cancel) return;
    }
    if (hook) hook();
    finished = true;
  }

  /// This thread to idle scheduling priority (or nice 19 where SCHED_IDLE is refused); false if neither worked.
  bool setIdlePriority() {
#ifdef __linux__
    tid = long(syscall(SYS_gettid));
    sched_param idle{};
    return pthread_setschedparam(pthread_self(), SCHED_IDLE, &idle) == 0 ||
           setpriority(PRIO_PROCESS, id_t(tid), 19) == 0;
#else
    return false;
#endif
  }

  /// Back to normal priority (for good: a build not lowered yet never will be). False if the process may not
  /// raise it (Linux: leaving SCHED_IDLE or lowering nice needs CAP_SYS_NICE or a high enough RLIMIT_NICE).
  bool raise() {
    std::lock_guard<std::mutex> lock(mutex);
    raised = true;
    if (!lowered || finished) return true;
    if (raiseDenied) return false;
#ifdef __linux__
    sched_param normal{};
    if (pthread_setschedparam(thread.native_handle(), SCHED_OTHER, &normal) != 0) return false;
    if (getpriority(PRIO_PROCESS, id_t(tid)) > 0 && setpriority(PRIO_PROCESS, id_t(tid), 0) != 0) return false;
#endif
    lowered = false;
    return true;
  }
};

Scene::UpgradeSlot::UpgradeSlot() = default;
Scene::UpgradeSlot::UpgradeSlot(UpgradeSlot&& o) noexcept {
  o.wait();
  job = std::move(o.job);
}
Scene::UpgradeSlot& Scene::UpgradeSlot::operator=(UpgradeSlot&& o) noexcept {
  wait();
  o.wait();
  job = std::move(o.job);
  return *this;
}
Scene::UpgradeSlot::~UpgradeSlot() {
  drop();
}

void Scene::UpgradeSlot::drop() {
  // Its trees are not wanted any more: once it has read the scene, it is cancelled and left to stop at its next
  // node on its own (an idle build may get no core for a long time on a busy machine; nothing waits for it). A
  // test's hook may refer to the test's state: such a build is waited for
  if (!job || !job->thread.joinable()) return;
  if (job->finished || job->hasHook) return wait();
  settle();
  retire();
}

void Scene::UpgradeSlot::settle() {
  Upgrade* u = job.get();
  if (!u) return;
  std::unique_lock<std::mutex> lock(u->mutex);
  u->read.wait(lock, [u] { return u->inputsRead; });
}

void Scene::UpgradeSlot::retire() {
  // Lowered or cancelled after its read, the thread touches only its own data: it keeps the job alive itself
  job->cancel = true;
  job->thread.detach();
  job.reset();
}

void Scene::UpgradeSlot::wait() {
  if (!job || !job->thread.joinable()) return;
  // Someone waits for it now: back to normal priority, or a busy machine could starve it indefinitely (where the
  // process may not raise it, the build gets the core the waiting thread leaves)
  job->raise();
  job->thread.join();
}

void Scene::settleUpgrade() {
  upgrade_.settle();
}

void Scene::startUpgrades() {
  if (!backgroundUpgrade_ || upgrade_.job) return;
  auto job = std::make_shared<Upgrade>();
  for (uint32_t i = 0; i < objects_.size(); ++i) {
    const Object& o = objects_[i];
    if (o.alive && !o.dirty && !o.refitPending && o.builtQuality == BvhBuildQuality::Fast)
      job->items.push_back({i, o.treeVersion, {}, {}});
  }
  if (job->items.empty()) return;
  launchUpgrade(std::move(job));
}

void Scene::launchUpgrade(std::shared_ptr<Upgrade> job) {
  job->raiseDenied = upgradeRaiseDenied_;
  job->hasHook = bool(upgradeHook_);
  // The thread holds the job too, so a build left to itself (UpgradeSlot::retire) keeps its data until it stops
  job->thread = std::thread([job, objects = &objects_, hook = upgradeHook_] { job->run(*objects, hook); });
  upgrade_.job = std::move(job);
}

bool Scene::upgradeFinished() const {
  return upgrade_.job && upgrade_.job->finished;
}

void Scene::waitForUpgrades() {
  upgrade_.wait();
}

void Scene::pressUpgrade(CommitStats& st) {
  Upgrade* u = upgrade_.job.get();
  if (!u || u->finished || ++u->commits <= kUpgradeIdleCommits) return;
  // Frames keep coming and leave it no idle core: it continues at normal priority, sharing the cores with the
  // frames, and a commit waits for it at the latest kUpgradeWaitCommits after it started
  if (u->commits >= kUpgradeWaitCommits) {
    upgrade_.wait();
    st.waitedForUpgrade = true;
    return;
  }
  if (u->raise()) return;
  // The process may not raise it (Linux: leaving SCHED_IDLE or lowering nice needs CAP_SYS_NICE, which an
  // ordinary user lacks): stop it and build the objects still current again at normal priority. It stops at its
  // next node, on the core this thread leaves while it waits
  auto job = std::make_shared<Upgrade>();
  job->commits = u->commits;
  job->raised = true;  // never lowered
  for (const Upgrade::Item& item : u->items) {
    const Object& o = objects_[item.object];
    if (o.alive && !o.dirty && !o.refitPending && o.treeVersion == item.version)
      job->items.push_back({item.object, item.version, {}, {}});
  }
  // Not joined: it stops at its next node whenever it gets a core (it was lowered, so it has read the scene)
  upgrade_.retire();
  st.upgradeRestarted = true;
  if (!job->items.empty()) launchUpgrade(std::move(job));
}

void Scene::adoptUpgrades(CommitStats& st) {
  if (!upgrade_.job || !upgrade_.job->finished) return;  // never waits: pressUpgrade decides that
  upgrade_.wait();                                       // the thread has finished: this only joins it
  for (Upgrade::Item& item : upgrade_.job->items) {
    if (item.object >= objects_.size()) continue;
    Object& o = objects_[item.object];
    if (!o.alive || o.dirty || o.refitPending || o.treeVersion != item.version) continue;  // changed since
    o.adoptTree(std::move(item.tree), item.valid, BvhBuildQuality::Sah);
    o.treeVersion = ++treeCounter_;
    ++st.objectsUpgraded;
  }
  upgrade_.job.reset();
}

}  // namespace whitted
