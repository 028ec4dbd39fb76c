// Resources: a 10M-triangle mesh renders, with bytes per triangle and peak memory reported; an allocation failure
// while building a scene surfaces as std::bad_alloc from Scene::commit() (which adapters turn into a clear error)
// instead of a crash. Labelled "large": not run under the sanitizers (ASan's shadow memory and an address-space
// limit do not mix).
#include "image/renderer.h"
#include "scenes/scenes.h"

#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>

using namespace whitted;

namespace {
double peakRssMiB() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return ru.ru_maxrss / 1024.0;  // kilobytes on Linux
}

/// n x n grid of quads (2 n^2 triangles) over [-1,1]^2 with a bump, so the BVH is not trivially flat.
TriangleMesh bumpyGrid(int n) {
  TriangleMesh m;
  m.positions.reserve(std::size_t(n + 1) * (n + 1));
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      double x = -1.0 + 2.0 * i / n, y = -1.0 + 2.0 * j / n;
      m.positions.push_back(Vec3(x, y, 0.1 * std::sin(7 * x) * std::cos(5 * y)));
    }
  m.triangles.reserve(std::size_t(2) * n * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      uint32_t a = uint32_t(j * (n + 1) + i), b = a + 1, c = a + uint32_t(n + 1), d = c + 1;
      m.triangles.push_back({a, b, d});
      m.triangles.push_back({a, d, c});
    }
  return m;
}
}  // namespace

TEST(Large, TenMillionTriangles) {
  const int n = 2237;  // 2 * 2237^2 = 10 008 338 triangles
  auto t0 = std::chrono::steady_clock::now();
  Scene s;
  s.addInstance(s.addMesh(bumpyGrid(n)), Mat4(1.0), s.addMaterial(Material{}));
  s.lights().push_back(Light{});
  CommitStats cs = s.commit();
  SceneStats st = s.stats();
  ASSERT_GE(st.triangles, 10000000u);
  FrameBuffer fb;
  FrameStats fs = render(s, Camera::perspective(Vec3(0, -2, 2), Vec3(0), Vec3(0, 0, 1), 40, 1, 0.1, 10),
                         RenderSettings{}, 128, 128, fb);
  double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  double bvhPerTri = double(st.bvhBytes) / st.triangles, geoPerTri = double(st.geometryBytes) / st.triangles;
  std::printf(
      "[large] %zu triangles: build %.2f s, trace 128x128 %.3f s, total %.2f s; BVH %.1f B/tri, geometry "
      "%.1f B/tri, total %.1f B/tri; peak RSS %.0f MiB\n",
      st.triangles, cs.secondsBuild, fs.secondsTrace, total, bvhPerTri, geoPerTri, bvhPerTri + geoPerTri, peakRssMiB());
  int hits = 0;
  for (float d : fb.depth) hits += d < 1.0f;
  EXPECT_GT(hits, 128 * 128 / 4);
  EXPECT_LT(bvhPerTri + geoPerTri, 160.0);  // the budget this design is held to
}

// In a child process limited to 512 MiB of address space, committing a 10M-triangle scene must throw
// std::bad_alloc (caught here: exit 3), not crash.
TEST(Large, AllocationFailureIsAnExceptionNotACrash) {
  pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    rlimit lim{512ull << 20, 512ull << 20};
    setrlimit(RLIMIT_AS, &lim);
    try {
      Scene s;
      s.addInstance(s.addMesh(bumpyGrid(2237)), Mat4(1.0), s.addMaterial(Material{}));
      s.commit();
      _exit(0);
    } catch (const std::bad_alloc&) {
      _exit(3);
    }
  }
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status)) << "child died from signal " << (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
  EXPECT_EQ(WEXITSTATUS(status), 3);
}
