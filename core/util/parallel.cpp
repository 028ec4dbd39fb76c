// The shared thread pool (see parallel.h).
// Performance note: written by hand rather than on oneTBB (tbb::task_arena + parallel_for, measured on 2 cores:
// whitted_bench build iso1m, Bvh::build 221 ms here against 201 ms with TBB, whose workers spin before they sleep;
// frames of iso60k at 1024x1024, 256x256, 128x128 within the runs' spread): the core keeps no dependency beyond
// GLM and the C++ library, and idle workers here sleep at once instead of taking cycles from the GL thread, the
// background upgrade or other MPI ranks.
#include "util/parallel.h"

#include <atomic>
#include <exception>
#include <system_error>

namespace whitted {

/// One pass: its jobs are taken from a counter by the caller and the workers that joined (seats). Workers hold it
/// by shared_ptr, so one that joined but wakes after the caller returned finds the counter spent and leaves without
/// touching the caller's (gone) function.
struct ThreadPool::Batch {
  const std::function<void(uint32_t)>* f = nullptr;
  uint32_t jobs = 0;
  bool oneEach = false;            ///< a worker runs one job, then leaves (alongside)
  int seats = 0;                   ///< workers that may still join (guarded by the pool's m_)
  std::atomic<uint64_t> next{0};   ///< next job index (>= jobs: none left, or withdrawn)
  std::mutex m;
  std::condition_variable done;
  uint32_t finished = 0;           ///< jobs returned (guarded by m)
  uint32_t target = 0;             ///< jobs to wait for: all of them until finish() withdraws the rest (guarded by m)
  std::exception_ptr error;        ///< the first exception a job threw (guarded by m)

  /// Takes and runs jobs until none is left (one at most if once).
  void work(bool once) {
    for (;;) {
      const uint64_t i = next.fetch_add(1);
      if (i >= jobs) return;
      std::exception_ptr e;
      try {
        (*f)(uint32_t(i));
      } catch (...) {
        e = std::current_exception();
      }
      {
        std::lock_guard<std::mutex> lock(m);
        if (e && !error) error = e;
        if (++finished == target) done.notify_one();
      }
      if (once) return;
    }
  }
};

ThreadPool::ThreadPool(int workers) {
  try {
    for (int i = 0; i < workers; ++i) workers_.emplace_back([this] { loop(); });
  } catch (const std::system_error&) {
    // No more threads to be had (resource limits): the passes run on the ones started
  }
}

ThreadPool::~ThreadPool() {
  {
    std::lock_guard<std::mutex> lock(m_);
    stop_ = true;
  }
  wake_.notify_all();
  for (std::thread& t : workers_) t.join();
}

void ThreadPool::loop() {
  std::unique_lock<std::mutex> lock(m_);
  for (;;) {
    wake_.wait(lock, [&] { return stop_ || !open_.empty(); });
    if (stop_) return;
    std::shared_ptr<Batch> b = open_.front();
    if (--b->seats == 0) open_.erase(open_.begin());
    lock.unlock();
    b->work(b->oneEach);
    b.reset();
    lock.lock();
  }
}

std::shared_ptr<ThreadPool::Batch> ThreadPool::post(uint32_t jobs, int seats, bool oneEach,
                                                    const std::function<void(uint32_t)>& f) {
  auto b = std::make_shared<Batch>();
  b->f = &f;
  b->jobs = b->target = jobs;
  b->oneEach = oneEach;
  seats = b->seats = std::min(seats, workers());  // b->seats belongs to the workers once posted
  if (seats <= 0) return b;
  {
    std::lock_guard<std::mutex> lock(m_);
    open_.push_back(b);
  }
  for (int i = 0; i < seats; ++i) wake_.notify_one();
  return b;
}

void ThreadPool::finish(const std::shared_ptr<Batch>& b) {
  // No worker joins any more; the jobs nobody took are withdrawn; wait for those taken
  {
    std::lock_guard<std::mutex> lock(m_);
    open_.erase(std::remove(open_.begin(), open_.end(), b), open_.end());
  }
  const uint64_t taken = std::min<uint64_t>(b->next.exchange(b->jobs), b->jobs);
  std::unique_lock<std::mutex> lock(b->m);
  b->target = uint32_t(taken);
  b->done.wait(lock, [&] { return b->finished == b->target; });
  if (b->error) std::rethrow_exception(b->error);
}

void ThreadPool::run(uint32_t jobs, int threads, const std::function<void(uint32_t)>& f) {
  const std::shared_ptr<Batch> b = post(jobs, threads - 1, false, f);
  b->work(false);  // every job is taken when this returns
  finish(b);
}

void ThreadPool::alongside(int helpers, const std::function<void(uint32_t)>& helper,
                           const std::function<void()>& mine) {
  const std::shared_ptr<Batch> b = post(uint32_t(std::max(0, helpers)), helpers, true, helper);
  std::exception_ptr error;
  try {
    mine();
  } catch (...) {
    error = std::current_exception();
  }
  finish(b);
  if (error) std::rethrow_exception(error);
}

ThreadPool& sharedPool() {
  static ThreadPool pool(hardwareThreads() - 1);
  return pool;
}

}  // namespace whitted
