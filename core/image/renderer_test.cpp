// Renderer tests: identical output for any thread count and with block culling, depth = projected depth, adaptive
// sampling, image split between processes, abort, affinity, progress and exceptions. The safety nets are tested in
// safety_net_test.cpp, the camera's round trips in shading/camera_test.cpp, PNG output in image_test.cpp.
#include "image/renderer.h"
#include "image/report.h"
#include "scenes/scenes.h"

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#ifdef __linux__
#include <sched.h>
#endif

using namespace whitted;

namespace {
struct Classic {
  Scene scene;
  CameraSpec cs;
  Classic() {
    buildClassicScene(scene, cs);
    scene.commit();
  }
};
}  // namespace

TEST(Renderer, BitIdenticalForAnyThreadCount) {
  Classic c;
  Camera cam = c.cs.make(1.0, c.scene.bounds());
  RenderSettings rs;
  rs.samplesPerPixel = 4;
  rs.adaptive = true;
  rs.tileSize = 8;
  FrameBuffer ref;
  rs.threads = 1;
  FrameStats s1 = render(c.scene, cam, rs, 70, 50, ref);
  for (int t : {2, 3, 7}) {
    rs.threads = t;
    FrameBuffer fb;
    FrameStats st = render(c.scene, cam, rs, 70, 50, fb);
    ASSERT_EQ(0, std::memcmp(ref.color.data(), fb.color.data(), ref.color.size() * sizeof(Color4))) << t;
    ASSERT_EQ(0, std::memcmp(ref.depth.data(), fb.depth.data(), ref.depth.size() * sizeof(float))) << t;
    EXPECT_EQ(st.rays.traced(), s1.rays.traced());
    EXPECT_EQ(st.rays.savedByThreshold, s1.rays.savedByThreshold);
    EXPECT_EQ(st.truncation.rms, s1.truncation.rms);
    EXPECT_EQ(st.sampling.rms, s1.sampling.rms);
  }
}

// A plane facing the camera at eye distance z has OpenGL depth 0.5 * z_ndc + 0.5 with
// z_ndc = (f + n) / (f - n) - 2 f n / ((f - n) z).
// Block culling (RenderSettings::blockCulling: camera rays of 8x8 pixel blocks whose frustum misses every leaf box
// are not traced, their pixels written as misses) gives the traced image bit for bit: colour, depth and error
// arrays, for meshes, spheres and tubes, instances with transforms, far-off and tiny coordinates, cameras outside
// and inside the scene, perspective and parallel, tiles of 16, 20 and 64 pixels, 1 spp and adaptive; and it culls
// (a third or more of the pixels of a view that shows the scene small). Fails if a block with a hit is culled (a
// frustum that excluded boxes the rays reach: with the plane test taking a box's nearest corner for its farthest,
// 91 of the 108 frames differ).
TEST(Renderer, BlockCullingGivesTheTracedImageBitForBit) {
  struct Case {
    std::string name;
    Scene s;
  };
  std::vector<Case> cases(6);
  CameraSpec unused;
  cases[0].name = "classic";
  buildClassicScene(cases[0].s, unused);
  cases[1].name = "classic, mesh spheres";
  buildClassicScene(cases[1].s, unused, 12);
  // Instances with transforms (rotated, scaled), spheres and tubes, and a far-off and a tiny copy of a grid
  for (int k = 2; k < 6; ++k) {
    Scene& s = cases[std::size_t(k)].s;
    const double scale = k == 4 ? 1e-6 : 1.0;
    const Vec3 offset = k == 5 ? Vec3(1e7, -3e6, 2e6) : Vec3(0.0);
    Material m;
    m.diffuseColor = Color(0.8f, 0.5f, 0.3f);
    const uint32_t mat = s.addMaterial(m);
    const Mat4 place = glm::scale(glm::translate(Mat4(1.0), offset), Vec3(scale));
    s.addInstance(s.addMesh(makeGrid(Vec3(-4, -4, 0), Vec3(8, 0, 0), Vec3(0, 8, 0), 12, 12)),
                  k == 3 ? place : Mat4(1.0), mat);
    const uint32_t ball = s.addMesh(makeSphereMesh(Vec3(0.0), 0.6, 16, 8));
    s.addInstance(ball, glm::translate(place, Vec3(-1.2, 0.3, 0.8)), mat);
    s.addInstance(ball, glm::scale(glm::rotate(glm::translate(place, Vec3(1.1, -0.6, 0.9)), 0.7, Vec3(1, 1, 0)),
                                   Vec3(1.0, 0.5, 1.5)), mat);
    SphereSet spheres;
    for (int i = 0; i < 5; ++i) spheres.centers.push_back(offset + scale * Vec3(-2.5 + i, -2.0, 0.4 + 0.1 * i));
    spheres.radii = {0.3 * scale};
    s.addInstance(s.addSpheres(spheres), Mat4(1.0), mat);
    TubeSet tubes;
    tubes.p0 = {offset + scale * Vec3(-2, 2.5, 0.5)};
    tubes.p1 = {offset + scale * Vec3(2, 2.2, 0.3)};
    tubes.radii = {0.15 * scale};
    s.addInstance(s.addTubes(tubes), Mat4(1.0), mat);
    Light l;
    l.positional = true;
    l.coneAngle = 90.0;
    l.position = offset + scale * Vec3(2.0, -1.0, 5.0);
    s.lights().push_back(l);
    cases[std::size_t(k)].name = k == 2 ? "instances" : k == 3 ? "instances, transformed grid" : k == 4 ? "tiny" : "far off";
  }
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  uint64_t culledAll = 0, pixelsAll = 0, differing = 0;
  for (Case& c : cases) {
    c.s.commit();
    const Bounds3 b = c.s.bounds();
    const double size = glm::length(b.extent());
    for (int view = 0; view < 6; ++view) {
      // Outside (near and far) and inside the scene's box; perspective and parallel
      const double distance = size * (view < 2 ? 2.5 : view < 4 ? 0.9 : 0.15);
      const Vec3 dir = glm::normalize(Vec3(u(rng), u(rng), 0.3 + std::abs(u(rng))));
      const Vec3 focal = b.center() + 0.2 * size * Vec3(u(rng), u(rng), u(rng));
      const Vec3 eye = focal + distance * dir;
      const double aspect = 61.0 / 37.0;
      const Camera cam = view % 2 ? Camera::parallel(eye, focal, Vec3(0, 0, 1), 0.3 * size, aspect, 1e-3 * size,
                                                     10.0 * size)
                                  : Camera::perspective(eye, focal, Vec3(0, 0, 1), 30.0, aspect, 1e-3 * size,
                                                        10.0 * size);
      for (int variant = 0; variant < 3; ++variant) {
        RenderSettings rs;
        rs.threads = 2;
        rs.tileSize = variant == 0 ? 16 : variant == 1 ? 20 : 64;
        rs.adaptive = variant == 2;
        rs.samplesPerPixel = variant == 2 ? 4 : 1;
        rs.blockCulling = false;
        FrameBuffer traced, culled;
        const FrameStats off = render(c.s, cam, rs, 61, 37, traced);
        rs.blockCulling = true;
        const FrameStats on = render(c.s, cam, rs, 61, 37, culled);
        const std::string what = c.name + ", view " + std::to_string(view) + ", variant " + std::to_string(variant);
        EXPECT_EQ(off.pixelsCulled, 0u) << what;
        const bool same = traced.color == culled.color && traced.depth == culled.depth &&
                          traced.truncation == culled.truncation && traced.sampling == culled.sampling &&
                          traced.samplingRms == culled.samplingRms && traced.samples == culled.samples;
        EXPECT_TRUE(same) << what << ": " << on.pixelsCulled << " pixels culled";
        differing += !same;
        EXPECT_EQ(off.rays.primary, on.rays.primary) << what;
        culledAll += on.pixelsCulled;
        pixelsAll += 61 * 37;
      }
    }
  }
  EXPECT_EQ(differing, 0u);
  std::printf("block culling: %llu of %llu pixels culled\n", (unsigned long long)culledAll,
              (unsigned long long)pixelsAll);
  EXPECT_GT(culledAll, pixelsAll / 10);

  // A view that shows the classic scene small: most blocks around it are culled
  Classic c;
  RenderSettings rs;
  rs.threads = 2;
  FrameBuffer fb;
  const Vec3 away = c.cs.eye + 2.0 * (c.cs.eye - c.cs.focal);
  const Camera far = Camera::perspective(away, c.cs.focal, c.cs.up, 30.0, 4.0 / 3.0, 0.1, 1000.0);
  const FrameStats fs = render(c.scene, far, rs, 160, 120, fb);
  EXPECT_GT(fs.pixelsCulled, 160u * 120u / 3u);
}

TEST(Renderer, DepthIsOpenGLDepthOfTheProjection) {
  Scene s;
  const double z = 7.25, n = 0.5, f = 40.0;
  s.addInstance(s.addMesh(makeGrid(Vec3(-50, -50, -z), Vec3(100, 0, 0), Vec3(0, 100, 0), 1, 1)), Mat4(1.0),
                s.addMaterial(Material{}));
  s.commit();
  for (bool parallel : {false, true}) {
    Camera cam = parallel ? Camera::parallel(Vec3(0), Vec3(0, 0, -1), Vec3(0, 1, 0), 3.0, 1.5, n, f)
                          : Camera::perspective(Vec3(0), Vec3(0, 0, -1), Vec3(0, 1, 0), 50.0, 1.5, n, f);
    FrameBuffer fb;
    render(s, cam, RenderSettings{}, 30, 20, fb);
    double zNdc =
        parallel ? (-2.0 / (f - n)) * (-z) - (f + n) / (f - n) : (f + n) / (f - n) - 2.0 * f * n / ((f - n) * z);
    double expected = 0.5 * zNdc + 0.5;
    for (float d : fb.depth) EXPECT_NEAR(d, expected, 1e-6) << (parallel ? "parallel" : "perspective");
  }
}

// Misses: depth 1, alpha = background alpha, colour premultiplied by it.
TEST(Renderer, MissesGetDepthOneAndBackgroundAlpha) {
  for (float a : {0.0f, 0.5f, 1.0f}) {
    Scene s;
    s.background = Color(0.1f, 0.2f, 0.3f);
    s.backgroundAlpha = a;
    s.commit();
    FrameBuffer fb;
    render(s, Camera::perspective(Vec3(0, 0, 5), Vec3(0), Vec3(0, 1, 0), 30, 1, 0.1, 10), RenderSettings{}, 8, 8, fb);
    for (std::size_t i = 0; i < fb.color.size(); ++i) {
      EXPECT_EQ(fb.depth[i], 1.0f);
      EXPECT_EQ(fb.color[i].a, a);
      EXPECT_FLOAT_EQ(fb.color[i].z, 0.3f * a);
    }
  }
}

TEST(Renderer, AdaptiveSamplesOnlyWhereNeighboursDiffer) {
  Classic c;
  Camera cam = c.cs.make(1.0, c.scene.bounds());
  RenderSettings full, adaptive;
  full.samplesPerPixel = adaptive.samplesPerPixel = 9;
  adaptive.adaptive = true;
  FrameBuffer a, b;
  FrameStats fa = render(c.scene, cam, full, 160, 160, a);
  FrameStats fb = render(c.scene, cam, adaptive, 160, 160, b);
  EXPECT_EQ(fa.samples, 160u * 160u * 9u);
  EXPECT_LT(fb.samples, fa.samples / 2);   // most pixels are smooth
  EXPECT_GT(fb.pixelsSupersampled, 100u);  // edges are refined
  double err = 0.0;
  for (std::size_t i = 0; i < a.color.size(); ++i) err += std::abs(a.color[i].x - b.color[i].x);
  EXPECT_LT(err / double(a.color.size()), 0.01);
}

// A linear colour ramp (per-vertex colours across a plane facing the camera, constant lighting) changes by more
// than the threshold from pixel to pixel but has no second difference: adaptive sampling leaves it alone.
TEST(Renderer, AdaptiveLeavesSmoothRampsAlone) {
  Scene scene;
  TriangleMesh m;
  m.positions = {Vec3(-2, -2, 0), Vec3(2, -2, 0), Vec3(2, 2, 0), Vec3(-2, 2, 0)};
  m.triangles = {glm::uvec3(0, 1, 2), glm::uvec3(0, 2, 3)};
  m.vertexColors = {Color4(0, 0, 0, 1), Color4(1, 0.5f, 0, 1), Color4(1, 0.5f, 0, 1), Color4(0, 0, 0, 1)};
  Material mat;
  mat.colorSource = ColorSource::ScalarsAmbientAndDiffuse;
  scene.addInstance(scene.addMesh(m), Mat4(1.0), scene.addMaterial(mat));
  Light sun;  // directional, along -z: the same N.L everywhere
  scene.lights().push_back(sun);
  scene.commit();
  Camera cam = Camera::perspective(Vec3(0, 0, 5), Vec3(0), Vec3(0, 1, 0), 40.0, 1.0, 0.1, 20.0);
  RenderSettings rs;
  rs.samplesPerPixel = 4;
  rs.adaptive = true;
  FrameBuffer fb;
  FrameStats fs = render(scene, cam, rs, 64, 64, fb);
  const float step = fb.color[32 * 64 + 33].x - fb.color[32 * 64 + 32].x;
  EXPECT_GT(step, rs.adaptiveThreshold);  // a first-difference criterion would refine every pixel
  EXPECT_EQ(fs.pixelsSupersampled, 0u);
  EXPECT_EQ(fs.samples, 64u * 64u);
}

// Two processes each tracing every other tile assemble, by depth, exactly the single-process image.
TEST(Renderer, ImageSplitComposesToFullImage) {
  Classic c;
  Camera cam = c.cs.make(1.0, c.scene.bounds());
  RenderSettings rs;
  rs.tileSize = 8;
  FrameBuffer full, part[2];
  render(c.scene, cam, rs, 40, 40, full);
  for (int r = 0; r < 2; ++r) {
    rs.tileStride = 2;
    rs.tileOffset = r;
    render(c.scene, cam, rs, 40, 40, part[r]);
  }
  int fromEach[2] = {0, 0};
  for (std::size_t i = 0; i < full.color.size(); ++i) {
    int owner = part[0].traced[i] ? 0 : 1;
    ASSERT_NE(part[0].traced[i], part[1].traced[i]);
    ++fromEach[owner];
    EXPECT_EQ(part[1 - owner].depth[i], 1.0f);
    EXPECT_EQ(part[1 - owner].color[i].a, 0.0f);
    EXPECT_EQ(part[owner].color[i], full.color[i]);
    EXPECT_EQ(part[owner].depth[i], full.depth[i]);
  }
  EXPECT_GT(fromEach[0], 600);
  EXPECT_GT(fromEach[1], 600);
}

// An abort mid-frame stops the frame; the next frame is complete and equal to an uninterrupted one.
TEST(Renderer, AbortThenRenderAgainGivesTheRightImage) {
  Classic c;
  Camera cam = c.cs.make(1.0, c.scene.bounds());
  RenderSettings rs;
  rs.tileSize = 4;
  int calls = 0;
  rs.abortCheck = [&] { return ++calls >= 3; };
  // One thread: the check runs after every tile, so exactly three tiles are traced
  rs.threads = 1;
  FrameBuffer aborted;
  FrameStats fa = render(c.scene, cam, rs, 64, 64, aborted);
  EXPECT_TRUE(fa.aborted);
  EXPECT_EQ(fa.rays.primary, 3u * 4u * 4u);
  // Several threads: the calling thread checks between its own tiles, so how many tiles the workers finish before
  // a check is a matter of scheduling. The deterministic abort (RenderSettings::abortAfterTiles) stops the frame at
  // a fixed tile whatever the scheduling: exactly that many tiles are traced, by any number of threads.
  rs.abortCheck = nullptr;
  for (int threads : {2, 5}) {
    rs.threads = threads;
    rs.abortAfterTiles = 37;
    fa = render(c.scene, cam, rs, 512, 512, aborted);
    EXPECT_TRUE(fa.aborted) << threads;
    EXPECT_EQ(fa.rays.primary, 37u * 4u * 4u) << threads;
  }
  rs.abortAfterTiles = -1;
  rs.threads = 2;
  FrameBuffer again, ref;
  render(c.scene, cam, rs, 64, 64, again);
  rs.threads = 1;
  render(c.scene, cam, rs, 64, 64, ref);
  EXPECT_EQ(0, std::memcmp(again.color.data(), ref.color.data(), ref.color.size() * sizeof(Color4)));
}

// render() keeps a frame buffer of the same size: a frame into a buffer holding another frame (other settings, a
// full image) equals the same frame into a new buffer, in every array, for frames that trace only part of the image
// (an abort, another process's tiles) and for a resumed progressive frame.
TEST(Renderer, KeptFrameBufferEqualsNewOne) {
  Classic c;
  Camera cam = c.cs.make(1.0, c.scene.bounds());
  auto same = [](const FrameBuffer& a, const FrameBuffer& b) {
    return a.width == b.width && a.height == b.height && a.color == b.color && a.depth == b.depth &&
           a.traced == b.traced && a.truncation == b.truncation && a.sampling == b.sampling && a.samples == b.samples;
  };
  RenderSettings full;
  full.samplesPerPixel = 4;
  full.tileSize = 8;
  std::vector<RenderSettings> cases(4, RenderSettings{});
  cases[0].abortAfterTiles = 5;
  cases[0].threads = 2;
  cases[1].tileStride = 2;
  cases[1].tileOffset = 1;
  cases[2].samplesPerPixel = 4;
  cases[2].adaptive = true;
  cases[2].tileStride = 3;
  cases[3].abortAfterTiles = 3;
  cases[3].samplesPerPixel = 4;
  cases[3].adaptive = true;
  for (std::size_t k = 0; k < cases.size(); ++k) {
    cases[k].tileSize = 8;
    FrameBuffer kept, fresh;
    render(c.scene, cam, full, 48, 40, kept);
    FrameStats a = render(c.scene, cam, cases[k], 48, 40, kept);
    FrameStats b = render(c.scene, cam, cases[k], 48, 40, fresh);
    EXPECT_TRUE(same(kept, fresh)) << k;
    EXPECT_EQ(a.rays.primary, b.rays.primary) << k;
    EXPECT_LT(std::count(fresh.traced.begin(), fresh.traced.end(), 1), 48 * 40) << k;  // part of the image
  }
  // Progressive display resumed from kept sums of another process's tiles
  RefinementState state;
  RenderSettings prog;
  prog.tileStride = 2;
  prog.timeBudget = 1e-9;
  prog.refinement = &state;
  FrameBuffer kept, fresh;
  render(c.scene, cam, prog, 48, 40, fresh);
  render(c.scene, cam, full, 48, 40, kept);
  render(c.scene, cam, prog, 48, 40, kept);
  render(c.scene, cam, prog, 48, 40, fresh = FrameBuffer{});
  EXPECT_TRUE(same(kept, fresh));
}

#ifdef __linux__
// threads = 0 means the cores the process may run on (mpirun binds ranks to cores, taskset, cpusets).
TEST(Renderer, AllCoresMeansTheAffinityMask) {
  cpu_set_t saved;
  ASSERT_EQ(sched_getaffinity(0, sizeof saved, &saved), 0);
  int first = 0;
  while (!CPU_ISSET(first, &saved)) ++first;
  cpu_set_t one;
  CPU_ZERO(&one);
  CPU_SET(first, &one);
  ASSERT_EQ(sched_setaffinity(0, sizeof one, &one), 0);
  const int bound = hardwareThreads();
  const std::string report = frameReport(FrameStats(), SceneStats(), CommitStats(), 8, 8, 0.0, nullptr);
  ASSERT_EQ(sched_setaffinity(0, sizeof saved, &saved), 0);
  EXPECT_EQ(bound, 1);
  if (std::thread::hardware_concurrency() > 1) {  // the frame report says why fewer threads than cores are used
    EXPECT_NE(report.find("CPU affinity: 1 of"), std::string::npos) << report;
    EXPECT_LT(report.find("CPU affinity"), report.find("\n  time")) << report;
  }
  EXPECT_EQ(hardwareThreads(), CPU_COUNT(&saved));
}
#endif

// Progress is reported on the calling thread only, never decreases, and ends at exactly 1 even when the worker
// threads take every tile (tiny tiles, more threads than cores).
TEST(Renderer, ProgressIsMonotonicOnCallerAndReachesOne) {
  Classic c;
  Camera cam = c.cs.make(1.0, c.scene.bounds());
  for (int threads : {1, 2, 5}) {
    RenderSettings rs;
    rs.tileSize = 4;
    rs.threads = threads;
    std::vector<double> seen;
    const std::thread::id caller = std::this_thread::get_id();
    bool offThread = false;
    rs.progress = [&](double f) {
      offThread |= std::this_thread::get_id() != caller;
      seen.push_back(f);
    };
    FrameBuffer fb;
    FrameStats fs = render(c.scene, cam, rs, 64, 64, fb);
    EXPECT_FALSE(fs.aborted) << threads;
    EXPECT_FALSE(offThread) << threads;
    ASSERT_FALSE(seen.empty()) << threads;
    EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end())) << threads;
    EXPECT_EQ(seen.back(), 1.0) << threads;
  }
}

// An exception thrown while tiles are traced on several threads (here: by the progress callback) reaches the
// caller after all workers have stopped, instead of terminating the process.
TEST(Renderer, ExceptionInFrameIsRethrownAfterJoin) {
  Classic c;
  Camera cam = c.cs.make(1.0, c.scene.bounds());
  RenderSettings rs;
  rs.tileSize = 4;
  rs.threads = 3;
  rs.progress = [](double f) {
    if (f > 0.1) throw std::runtime_error("observer failed");
  };
  FrameBuffer fb;
  EXPECT_THROW(render(c.scene, cam, rs, 64, 64, fb), std::runtime_error);
  rs.progress = nullptr;
  FrameStats fs = render(c.scene, cam, rs, 64, 64, fb);  // and the next frame is complete
  EXPECT_EQ(fs.rays.primary, 64u * 64u);
}
