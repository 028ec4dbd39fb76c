// Tile scheduler: runs the passes of a frame over its tile slots on a fixed number of threads (the calling one and
// workers of the shared pool, util/parallel.h), each thread taking the next slot from a shared counter. The caller's abort check and progress run on the calling thread between
// tiles (VTK's must run on the GL thread); a deadline and a time slice stop new tiles from starting; a test can
// ask for a deterministic abort. Which slot a tile function gets never depends on the thread count, so results
// kept per slot are the same for any thread count.
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <functional>
#include <optional>

namespace whitted {

class TileScheduler {
 public:
  using Clock = std::chrono::steady_clock;

  /// threads: threads per pass, the calling thread included (at least 1; at most the shared pool's workers + 1
  /// run). abortCheck (true = abort) and progress (fraction done) are called on the calling thread between tiles
  /// and may be empty; both are kept by reference.
  /// abortAfterTiles: testing, a deterministic abort: a pass that checks for aborts aborts when a thread would
  /// start slot abortAfterTiles, so exactly slots 0..abortAfterTiles-1 run; -1: never.
  TileScheduler(int threads, const std::function<bool()>& abortCheck, const std::function<void(double)>& progress,
                long long abortAfterTiles);

  /// Runs tileFn(0) .. tileFn(tiles - 1) on the threads and returns when every tile taken has finished. Progress
  /// is reported if reportProgress; the abort check, the deterministic abort and the time slice apply if
  /// checkAbort; past the deadline (any pass) no new tile starts. Does nothing once aborted. The first exception
  /// a tile or a callback threw (std::bad_alloc, a VTK observer) aborts and is rethrown here after the join.
  void run(std::size_t tiles, const std::function<void(int)>& tileFn, bool reportProgress = true,
           bool checkAbort = true);

  bool aborted() const { return aborted_; }
  int threads() const { return threads_; }
  /// Wall time of the slowest tile run so far.
  double longestTileSeconds() const { return longestTile_.load(); }

  /// No tile of any pass starts past the deadline (a time budget); none by default.
  void setDeadline(std::optional<Clock::time_point> t) { deadline_ = t; }
  const std::optional<Clock::time_point>& deadline() const { return deadline_; }
  bool pastDeadline() const { return deadline_ && Clock::now() >= *deadline_; }
  /// No tile of a pass that checks for aborts starts past the slice's end, except one per thread each pass (a
  /// call's share of a progressive frame); none by default.
  void setSliceEnd(std::optional<Clock::time_point> t) { sliceEnd_ = t; }
  bool sliceOver() const { return sliceEnd_ && Clock::now() >= *sliceEnd_; }

 private:
  int threads_;
  const std::function<bool()>& abortCheck_;
  const std::function<void(double)>& progress_;
  long long abortAfterTiles_;
  std::optional<Clock::time_point> deadline_, sliceEnd_;
  std::atomic<double> longestTile_{0.0};
  bool aborted_ = false;
};

}  // namespace whitted
