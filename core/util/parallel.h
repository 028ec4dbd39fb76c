// A fixed pool of worker threads for the parallel passes of builds and conversions: results never depend on the
// thread count (work is split in fixed chunks; see forChunks).
#pragma once

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <system_error>
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

/// A fixed set of threads for the duration of one build (or one object rebuild, one conversion); run() hands out job
/// indices and returns when every job has finished. It waits for jobs, not for workers: a worker that has not woken up
/// by the time the calling thread and the others have taken every job is not waited for (on a busy machine a
/// descheduled worker would otherwise add a time slice to each of the build's many passes: 2.3 s instead of 0.3 s for
/// 1M triangles at load 10). Job indices carry the pass's number, so a worker that wakes late can never take a later
/// pass's index for an earlier pass's job.
class WorkerPool {
 public:
  explicit WorkerPool(int threads) {
    try {
      for (int i = 1; i < threads; ++i) workers_.emplace_back([this] { loop(); });
    } catch (const std::system_error&) {
      // No more threads to be had (resource limits): build with the ones started
    } catch (...) {
      stop();
      throw;
    }
  }
  ~WorkerPool() { stop(); }
  int threads() const { return int(workers_.size()) + 1; }
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  /// Calls f(0) .. f(jobs - 1) on the workers and the calling thread, in any order; returns when all returned.
  /// The first exception a job threw (std::bad_alloc) is rethrown here.
  void run(uint32_t jobs, const std::function<void(uint32_t)>& f) {
    if (workers_.empty() || jobs <= 1) {
      for (uint32_t j = 0; j < jobs; ++j) f(j);
      return;
    }
    uint32_t pass;
    {
      std::lock_guard<std::mutex> lock(m_);
      job_ = &f;
      jobs_ = jobs;
      finished_ = 0;
      error_ = nullptr;
      pass = ++pass_;
      next_.store(uint64_t(pass) << 32);
    }
    wake_.notify_all();
    work(pass, &f, jobs);
    std::unique_lock<std::mutex> lock(m_);
    done_.wait(lock, [&] { return finished_ == jobs; });
    if (error_) std::rethrow_exception(error_);
  }

 private:
  /// Takes and runs jobs of the given pass until none is left.
  void work(uint32_t pass, const std::function<void(uint32_t)>* f, uint32_t jobs) {
    for (;;) {
      uint64_t v = next_.load();
      do {
        if (uint32_t(v >> 32) != pass || uint32_t(v) >= jobs) return;
      } while (!next_.compare_exchange_weak(v, v + 1));
      try {
        (*f)(uint32_t(v));
      } catch (...) {
        std::lock_guard<std::mutex> lock(m_);
        if (!error_) error_ = std::current_exception();
      }
      std::lock_guard<std::mutex> lock(m_);
      if (++finished_ == jobs) done_.notify_one();
    }
  }
  void loop() {
    uint32_t seen = 0;
    for (;;) {
      const std::function<void(uint32_t)>* f;
      uint32_t pass, jobs;
      {
        std::unique_lock<std::mutex> lock(m_);
        wake_.wait(lock, [&] { return stop_ || pass_ != seen; });
        if (stop_) return;
        seen = pass = pass_;
        f = job_;
        jobs = jobs_;
      }
      work(pass, f, jobs);  // *f is called only for a job taken while its pass runs: run() waits for that job
    }
  }
  void stop() {
    {
      std::lock_guard<std::mutex> lock(m_);
      stop_ = true;
    }
    wake_.notify_all();
    for (std::thread& t : workers_) t.join();
    workers_.clear();
  }

  std::vector<std::thread> workers_;
  std::mutex m_;
  std::condition_variable wake_, done_;
  const std::function<void(uint32_t)>* job_ = nullptr;
  uint32_t jobs_ = 0, finished_ = 0, pass_ = 0;
  std::atomic<uint64_t> next_{0};  ///< pass << 32 | next job index
  bool stop_ = false;
  std::exception_ptr error_;
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
