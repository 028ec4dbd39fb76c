// The shared thread pool (util/parallel.h) and the tile scheduler on it: every job runs once, the thread limit,
// exceptions, and no deadlock when a job uses the pool again or two threads use it at once.
#include "util/parallel.h"
#include "util/tile_scheduler.h"

#include <gtest/gtest.h>

#include <atomic>
#include <functional>
#include <numeric>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

using namespace whitted;

namespace {

/// Sum of f(k) over k < n computed on a WorkerPool of `threads` in fixed chunks (the same for any thread count).
uint64_t chunkedSum(int threads, std::size_t n, const std::function<uint64_t(std::size_t)>& f) {
  WorkerPool pool(threads);
  constexpr std::size_t kChunk = 64;
  std::vector<uint64_t> sums((n + kChunk - 1) / kChunk, 0);
  forChunks(pool, n, kChunk, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) sums[b / kChunk] += f(i);
  });
  return std::accumulate(sums.begin(), sums.end(), uint64_t(0));
}

/// A frame-like pass: tiles slots on a TileScheduler of `threads`, each marked once; true if all were.
bool tilePass(int threads, std::size_t tiles) {
  const std::function<bool()> abortCheck;
  const std::function<void(double)> progress;
  TileScheduler s(threads, abortCheck, progress, -1);
  std::vector<std::atomic<int>> hits(tiles);
  s.run(tiles, [&](int i) { hits[std::size_t(i)]++; });
  for (auto& h : hits)
    if (h != 1) return false;
  return !s.aborted();
}

}  // namespace

TEST(ThreadPool, EveryJobRunsOnceOnAtMostTheRequestedThreads) {
  for (int threads : {1, 2, 3, 8}) {
    std::vector<std::atomic<int>> runs(1000);
    std::mutex m;
    std::set<std::thread::id> ids;
    WorkerPool(threads).run(1000, [&](uint32_t j) {
      runs[j]++;
      std::lock_guard<std::mutex> lock(m);
      ids.insert(std::this_thread::get_id());
    });
    for (auto& r : runs) EXPECT_EQ(r, 1) << threads;
    EXPECT_LE(int(ids.size()), threads);
    EXPECT_LE(int(ids.size()), sharedPool().workers() + 1);
  }
}

TEST(ThreadPool, JobExceptionIsRethrownAfterEveryJobRan) {
  std::atomic<int> ran{0};
  EXPECT_THROW(WorkerPool(4).run(100,
                                 [&](uint32_t j) {
                                   ran++;
                                   if (j % 10 == 3) throw std::runtime_error("job failed");
                                 }),
               std::runtime_error);
  EXPECT_EQ(ran, 100);
  EXPECT_EQ(chunkedSum(4, 1000, [](std::size_t i) { return i; }), 999u * 1000u / 2);  // still usable
}

// A job that runs a pass of its own (a build inside a job, a frame inside a job) finishes: the nested pass's caller
// can always run it alone.
TEST(ThreadPool, NestedUseDoesNotDeadlock) {
  const uint64_t inner = chunkedSum(1, 5000, [](std::size_t i) { return i * i; });
  std::vector<uint64_t> got(16, 0);
  std::vector<char> tilesOk(16, 0);
  WorkerPool(hardwareThreads() + 1).run(16, [&](uint32_t j) {
    got[j] = chunkedSum(3, 5000, [](std::size_t i) { return i * i; });
    tilesOk[j] = tilePass(3, 37);
  });
  for (int j = 0; j < 16; ++j) {
    EXPECT_EQ(got[j], inner) << j;
    EXPECT_TRUE(tilesOk[j]) << j;
  }
  // And a frame whose tiles run passes
  const std::function<bool()> abortCheck;
  const std::function<void(double)> progress;
  TileScheduler s(4, abortCheck, progress, -1);
  std::vector<uint64_t> perTile(40, 0);
  s.run(40, [&](int i) { perTile[std::size_t(i)] = chunkedSum(2, 3000, [](std::size_t k) { return k; }); });
  for (uint64_t v : perTile) EXPECT_EQ(v, 2999u * 3000u / 2);
}

// Two threads using the pool at once (two scenes rendering, a conversion beside a frame) both finish, with the
// same results as alone.
TEST(ThreadPool, ConcurrentUseFromTwoThreads) {
  const uint64_t expected = chunkedSum(1, 20000, [](std::size_t i) { return i ^ (i >> 3); });
  std::atomic<int> wrong{0};
  auto user = [&] {
    for (int round = 0; round < 200; ++round) {
      if (chunkedSum(4, 20000, [](std::size_t i) { return i ^ (i >> 3); }) != expected) wrong++;
      if (!tilePass(3, 50)) wrong++;
    }
  };
  std::thread a(user), b(user);
  a.join();
  b.join();
  EXPECT_EQ(wrong, 0);
}
