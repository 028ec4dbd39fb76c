#include "util/tile_scheduler.h"

#include "util/parallel.h"

#include <algorithm>
#include <exception>
#include <mutex>
#include <thread>

namespace whitted {

TileScheduler::TileScheduler(int threads, const std::function<bool()>& abortCheck,
                             const std::function<void(double)>& progress, long long abortAfterTiles)
    : threads_(std::max(1, threads)), abortCheck_(abortCheck), progress_(progress), abortAfterTiles_(abortAfterTiles) {}

void TileScheduler::run(std::size_t tiles, const std::function<void(int)>& tileFn, bool reportProgress,
                        bool checkAbort) {
  std::atomic<std::size_t> next{0};
  std::atomic<std::size_t> done{0};
  std::atomic<bool> abortFlag{aborted_};
  std::mutex errorMutex;
  std::exception_ptr error;
  const std::size_t total = tiles;
  std::size_t reported = 0;
  // VTK's abort check and progress must run on the calling (GL) thread
  auto report = [&](std::size_t d) {
    if (progress_ && reportProgress && d > reported) {
      reported = d;
      progress_(double(d) / double(total));
    }
  };
  auto poll = [&](std::size_t d) {
    if (abortCheck_ && checkAbort && abortCheck_()) abortFlag = true;
    report(d);
  };
  auto worker = [&](bool mainThread) {
    for (bool first = true;; first = false) {
      if (abortFlag.load(std::memory_order_relaxed)) return;
      if (pastDeadline()) break;                       // budget spent: no new tile
      if (checkAbort && !first && sliceOver()) break;  // slice over: no new tile (each worker takes one)
      std::size_t i = next.fetch_add(1);
      if (i >= total) break;
      if (checkAbort && abortAfterTiles_ >= 0 && i >= std::size_t(abortAfterTiles_)) {
        abortFlag = true;  // testing: the deterministic abort (every earlier slot was taken before this one)
        return;
      }
      try {
        const auto t0 = Clock::now();
        tileFn(int(i));
        const double dt = std::chrono::duration<double>(Clock::now() - t0).count();
        double seen = longestTile_.load(std::memory_order_relaxed);
        while (dt > seen && !longestTile_.compare_exchange_weak(seen, dt)) {
        }
      } catch (...) {
        // An exception (std::bad_alloc) stops the frame and is rethrown on the calling thread after the join
        std::lock_guard<std::mutex> lock(errorMutex);
        if (!error) error = std::current_exception();
        abortFlag = true;
        return;
      }
      std::size_t d = done.fetch_add(1) + 1;
      if (mainThread) poll(d);
    }
    // Out of tiles: the calling thread keeps polling until the workers finish their last tiles, so progress
    // always reaches 1 and an abort stays responsive even when the workers took every tile. Without callbacks
    // there is nothing to poll, and the join below waits without the up to 1 ms a polling step adds.
    const bool callbacks = (progress_ && reportProgress) || (abortCheck_ && checkAbort);
    while (mainThread && callbacks && !abortFlag.load()) {
      std::size_t d = done.load();
      if (d >= total) {  // complete: no abort check, which could only mark a finished frame as aborted
        report(d);
        break;
      }
      if (pastDeadline()) break;  // the join waits for tiles taken
      if (checkAbort && sliceOver()) break;
      poll(d);
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  };
  // The calling thread's loop beside threads_ - 1 worker loops on the shared pool's threads (fewer if it has fewer
  // idle workers: the slots a tile gets do not depend on it). An exception in the calling thread's loop (a callback:
  // a VTK observer) aborts at once, so the workers stop taking tiles; it is rethrown after they finished.
  auto onCaller = [&] {
    try {
      worker(true);
    } catch (...) {
      std::lock_guard<std::mutex> lock(errorMutex);
      if (!error) error = std::current_exception();
      abortFlag = true;
    }
  };
  const int helpers = total == 0 ? 0 : int(std::min<std::size_t>(std::size_t(threads_ - 1), total - 1));
  try {
    if (helpers > 0)
      sharedPool().alongside(helpers, [&](uint32_t) { worker(false); }, onCaller);
    else
      onCaller();
  } catch (...) {  // the pool could not post the pass (std::bad_alloc)
    std::lock_guard<std::mutex> lock(errorMutex);
    if (!error) error = std::current_exception();
    abortFlag = true;
  }
  aborted_ = abortFlag.load();
  if (error) std::rethrow_exception(error);
}

}  // namespace whitted
