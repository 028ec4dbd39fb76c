// The process's one thread pool (sharedPool: started on first use, its workers sleep between passes) and the two
// ways the core uses it: WorkerPool, the parallel passes of builds and conversions, whose results never depend on
// the thread count (work is split in fixed chunks; see forChunks); and ThreadPool::alongside, the tile scheduler's
// worker loops beside the calling thread's.
#pragma once

#include <algorithm>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#ifdef __linux__
#include <sched.h>
#endif

namespace whitted {

/// Number of cores this process may run on (its CPU affinity on Linux, else the hardware threads; at least 1):
/// what RenderSettings::threads = 0 and the builds' default thread count use.
inline int hardwareThreads() {
#ifdef __linux__
  // The cores this process may run on: under mpirun (which binds each rank to a core by default), taskset or a
  // container's cpuset this is fewer than the machine has, and more threads would only time-slice one core.
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) == 0) {
    const int n = CPU_COUNT(&set);
    if (n > 0) return n;
  }
#endif
  return std::max(1u, std::thread::hardware_concurrency());
}

/// A fixed set of worker threads that sleep on a condition variable until a pass is posted. The calling thread of
/// a pass always takes part, and waits only for the jobs that workers took, never for a worker to wake up: on a
/// busy machine a descheduled worker would otherwise add a time slice to each of a build's many passes (2.3 s
/// instead of 0.3 s for 1M triangles at load 10); a job no worker took is run by the caller (run) or not at all
/// (alongside). Passes may be posted from several threads at once (two scenes rendering) and from inside a job (a
/// build inside a tile): each is a batch of its own that idle workers join, and its caller can always finish it
/// alone, so nothing waits for a worker held by another pass.
class ThreadPool {
 public:
  /// Starts the workers (fewer if the system refuses more threads; then the passes run on those started). They
  /// inherit the scheduling priority and CPU affinity of the thread that constructs the pool.
  explicit ThreadPool(int workers);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;
  int workers() const { return int(workers_.size()); }

  /// Calls f(0) .. f(jobs - 1), in any order, on the calling thread and at most threads - 1 workers; returns when
  /// all returned. The first exception a job threw (std::bad_alloc) is rethrown here, after every job ran.
  void run(uint32_t jobs, int threads, const std::function<void(uint32_t)>& f);

  /// Calls mine() on the calling thread while up to helpers workers each call helper(k) once (distinct k in
  /// [0, helpers)); a helper call that no worker has started when mine() returns never starts. Returns when mine()
  /// and every helper call started have returned; the first exception one of them threw is then rethrown.
  void alongside(int helpers, const std::function<void(uint32_t)>& helper, const std::function<void()>& mine);

 private:
  struct Batch;
  void loop();
  std::shared_ptr<Batch> post(uint32_t jobs, int seats, bool oneEach, const std::function<void(uint32_t)>& f);
  void finish(const std::shared_ptr<Batch>& b);

  std::vector<std::thread> workers_;
  std::mutex m_;
  std::condition_variable wake_;
  std::vector<std::shared_ptr<Batch>> open_;  ///< batches that workers may still join (guarded by m_)
  bool stop_ = false;                         ///< guarded by m_
};

/// The process's pool: hardwareThreads() - 1 workers (the calling thread is the last one), started on first use.
ThreadPool& sharedPool();

/// The thread count of one build (or one object rebuild, one conversion): run() runs its passes on at most that many
/// threads of the shared pool, the calling thread included. Cheap to make; with one thread nothing touches the pool
/// (the background upgrade builds that way at idle priority, and its priority must not reach the pool's workers).
class WorkerPool {
 public:
  explicit WorkerPool(int threads) : threads_(std::max(1, threads)) {}
  /// The requested count (passes split work by it; at most the pool's workers + 1 take jobs).
  int threads() const { return threads_; }

  /// Calls f(0) .. f(jobs - 1) on up to threads() threads, the calling one included, in any order; returns when all
  /// returned. The first exception a job threw (std::bad_alloc) is rethrown here.
  void run(uint32_t jobs, const std::function<void(uint32_t)>& f) {
    if (threads_ <= 1 || jobs <= 1) {
      for (uint32_t j = 0; j < jobs; ++j) f(j);
      return;
    }
    sharedPool().run(jobs, threads_, f);
  }

 private:
  int threads_;
};

/// Calls fn(begin, end) for the pieces [k chunk, (k+1) chunk) of [0, n) on the pool's threads. The pieces do not
/// depend on the thread count, so per-piece results combined in piece order are the same for any pool.
template <typename Fn>
void forChunks(WorkerPool& pool, std::size_t n, std::size_t chunk, Fn&& fn) {
  const std::size_t pieces = (n + chunk - 1) / chunk;
  pool.run(uint32_t(pieces),
           [&](uint32_t k) { fn(std::size_t(k) * chunk, std::min(n, (std::size_t(k) + 1) * chunk)); });
}

}  // namespace whitted
