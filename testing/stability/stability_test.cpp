// Numerical stability on stiff and extreme scenes (core level). Every case asserts; the figures it measures (rays
// tried, leaks, differing pixels) are printed so the closing notes can quote them.
#include "image/image.h"
#include "image/renderer.h"
#include "scenes/scenes.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <random>

using namespace whitted;

namespace {

/// Applies p -> s * p + t to every position of every object and to the lights (double precision, as VTK emits).
struct Similarity {
  double s = 1.0;
  Vec3 t{0.0};
  Vec3 operator()(const Vec3& p) const { return s * p + t; }
};

void buildScaledClassic(Scene& scene, CameraSpec& cs, const Similarity& x) {
  Scene tmp;
  buildClassicScene(tmp, cs, 24);  // meshes, so every primitive goes through the triangle path
  for (uint32_t i = 0; i < tmp.objectCount(); ++i) {
    TriangleMesh m = tmp.mesh(i);
    for (Vec3& p : m.positions) p = x(p);
    scene.addMesh(std::move(m));
  }
  for (uint32_t i = 0; i < tmp.materialCount(); ++i) scene.addMaterial(tmp.material(i));
  for (uint32_t i = 0; i < tmp.instanceCount(); ++i) scene.addInstance(tmp.instanceObject(i), Mat4(1.0), i);
  for (Light l : tmp.lights()) {
    l.position = x(l.position);
    l.focalPoint = x(l.focalPoint);
    scene.lights().push_back(l);
  }
  scene.background = tmp.background;
  cs.eye = x(cs.eye);
  cs.focal = x(cs.focal);
}

std::vector<uint8_t> renderScaled(const Similarity& x, int w, int h, FrameStats* stats = nullptr) {
  Scene scene;
  CameraSpec cs;
  buildScaledClassic(scene, cs, x);
  scene.commit();
  FrameBuffer fb;
  FrameStats fs = render(scene, cs.make(double(w) / h, scene.bounds()), RenderSettings{}, w, h, fb);
  if (stats) *stats = fs;
  // The safety nets must catch nothing (else they would hide from the finiteness check what it looks for)
  EXPECT_EQ(fs.rays.safetyNetCatches(), 0u);
  for (const Color4& c : fb.color)
    for (int k = 0; k < 4; ++k) EXPECT_TRUE(std::isfinite(c[k]));
  return toRgba8(fb);
}

/// Pixels whose 8-bit colour differs by more than tol in any channel.
int differingPixels(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b, int tol) {
  int n = 0;
  for (std::size_t i = 0; i < a.size(); i += 4)
    for (int c = 0; c < 3; ++c)
      if (std::abs(int(a[i + c]) - int(b[i + c])) > tol) {
        ++n;
        break;
      }
  return n;
}

Material unlitColor(Color c) {
  Material m;
  m.lighting = false;
  m.diffuseColor = c;
  return m;
}

}  // namespace

// The classic scene scaled by 1e-6, 1e6 and translated by 1e7 renders the same image as at scale 1: no acne (a
// self-shadowed speckle would differ from the reference), no leaks, no lost reflections or refractions.
TEST(Stability, ScaleAndOffsetInvariance) {
  const int w = 160, h = 120;
  FrameStats refStats;
  auto ref = renderScaled(Similarity{}, w, h, &refStats);
  struct Case {
    const char* name;
    Similarity x;
  } cases[] = {{"scale 1e-6", {1e-6, Vec3(0.0)}},
               {"scale 1e6", {1e6, Vec3(0.0)}},
               {"translate 1e7", {1.0, Vec3(1e7, -1e7, 1e7)}},
               {"scale 1e-3 at 1e4", {1e-3, Vec3(1e4, 0.0, 0.0)}}};
  for (const Case& c : cases) {
    FrameStats st;
    auto img = renderScaled(c.x, w, h, &st);
    int diff = differingPixels(ref, img, 2);
    std::printf("[stability] %-18s pixels differing by >2/255: %d of %d; reflection rays %llu (ref %llu)\n", c.name,
                diff, w * h, (unsigned long long)st.rays.reflection, (unsigned long long)refStats.rays.reflection);
    // Only silhouette pixels may flip when coordinates round differently: < 0.5 % of the image
    EXPECT_LT(diff, w * h / 200) << c.name;
    EXPECT_NEAR(double(st.rays.reflection), double(refStats.rays.reflection), 0.01 * refStats.rays.reflection)
        << c.name;
    EXPECT_NEAR(double(st.rays.refraction), double(refStats.rays.refraction), 0.01 * refStats.rays.refraction)
        << c.name;
  }
}

// 1e6 rays per scale aimed at vertices and edge points of a closed mesh from outside: none may pass through.
TEST(Stability, WatertightMillionRaysPerScale) {
  for (Similarity x :
       {Similarity{1e-6, Vec3(0.0)}, Similarity{}, Similarity{1e6, Vec3(0.0)}, Similarity{1.0, Vec3(1e7, 1e7, -1e7)}}) {
    TriangleMesh m = makeSphereMesh(Vec3(0.0), 1.0, 64, 32);
    for (Vec3& p : m.positions) p = x(p);
    Scene scene;
    scene.addInstance(scene.addMesh(m), Mat4(1.0), scene.addMaterial(Material{}));
    scene.commit();
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> U(-1.0, 1.0), W(0.0, 1.0);
    const Vec3 center = x(Vec3(0.0));
    long tried = 0, leaks = 0;
    while (tried < 1000000) {
      for (const glm::uvec3& t : m.triangles) {
        const Vec3 ps[3] = {m.positions[t.x], m.positions[t.y], m.positions[t.z]};
        int k = int(tried % 3);
        // Vertices, and exact points on edges (convex combinations of the two end points)
        Vec3 target = (tried % 2) ? ps[k] : glm::mix(ps[k], ps[(k + 1) % 3], W(rng));
        Vec3 outward = glm::normalize(target - center);
        Vec3 origin = target + 2.0 * x.s * glm::normalize(outward + 0.5 * Vec3(U(rng), U(rng), U(rng)));
        Ray r;
        r.origin = origin;
        r.dir = target - origin;
        r.tMax = 1.5;  // past the target
        Hit hit;
        if (!scene.intersect(r, hit)) ++leaks;
        if (++tried >= 1000000) break;
      }
    }
    std::printf("[stability] watertight scale %g offset %g: %ld rays, %ld leaks\n", x.s, x.t.x, tried, leaks);
    EXPECT_EQ(leaks, 0) << "scale " << x.s;
  }
}

// Rays grazing a huge plane at 1e-6 rad, and coplanar overlapping triangles: deterministic, no speckle.
TEST(Stability, GrazingRaysAndCoplanarTriangles) {
  Scene scene;
  // A 1e6 x 1e6 plane
  scene.addInstance(scene.addMesh(makeGrid(Vec3(-5e5, 0, 5e5), Vec3(1e6, 0, 0), Vec3(0, 0, -1e6), 4, 4)), Mat4(1.0),
                    scene.addMaterial(unlitColor(Color(1, 0, 0))));
  // Two coplanar overlapping squares of different colour at z = 0 (red twice so the choice is deterministic)
  uint32_t a = scene.addMesh(makeGrid(Vec3(-1, 1, 0), Vec3(2, 0, 0), Vec3(0, 2, 0), 7, 7));
  uint32_t b = scene.addMesh(makeGrid(Vec3(-1.5, 0.5, 0), Vec3(3, 0, 0), Vec3(0, 3, 0), 5, 5));
  scene.addInstance(a, Mat4(1.0), scene.addMaterial(unlitColor(Color(0, 1, 0))));
  scene.addInstance(b, Mat4(1.0), scene.addMaterial(unlitColor(Color(0, 0, 1))));
  scene.commit();
  // Grazing: every ray from above at 1e-6 rad hits the plane at the analytic distance
  for (double y : {1e-4, 1e-2, 0.1}) {  // hits at 100 .. 1e5 units, inside the plane
    Ray r;
    r.origin = Vec3(0.3, y, 0.7);
    double ang = 1e-6;
    r.dir = Vec3(std::cos(ang), -std::sin(ang), 0.0);
    Hit h;
    ASSERT_TRUE(scene.intersect(r, h));
    EXPECT_NEAR(h.t, y / std::sin(ang), y / std::sin(ang) * 1e-9);
  }
  // Coplanar: the same ray always picks the same surface, and neighbouring rays do not alternate randomly
  Camera cam = Camera::perspective(Vec3(0, 1.5, 4), Vec3(0, 1.5, 0), Vec3(0, 1, 0), 30, 1, 0.1, 100);
  FrameBuffer f1, f2;
  RenderSettings rs;
  rs.threads = 1;
  render(scene, cam, rs, 64, 64, f1);
  rs.threads = 2;
  render(scene, cam, rs, 64, 64, f2);
  ASSERT_EQ(f1.color, f2.color);
  int flips = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 1; x < 63; ++x) {
      // A speckle: a pixel whose colour differs from both horizontal neighbours that agree with each other
      const Color4 &l = f1.color[y * 64 + x - 1], &c = f1.color[y * 64 + x], &r = f1.color[y * 64 + x + 1];
      if (l == r && c != l) ++flips;
    }
  std::printf("[stability] coplanar overlap speckles: %d\n", flips);
  EXPECT_EQ(flips, 0);
}

// Very thin slabs, tiny and huge spheres and tubes, spheres far from the origin: hits where analytic.
TEST(Stability, ThinSlabsTinyHugeAndFarPrimitives) {
  for (double thickness : {1e-9, 1e-6, 1e-3}) {
    Scene s;
    TriangleMesh top = makeGrid(Vec3(-1, 0, 1), Vec3(2, 0, 0), Vec3(0, 0, -2), 1, 1);
    TriangleMesh bottom = makeGrid(Vec3(-1, -thickness, -1), Vec3(2, 0, 0), Vec3(0, 0, 2), 1, 1);
    s.addInstance(s.addMesh(top), Mat4(1.0), s.addMaterial(Material{}));
    s.addInstance(s.addMesh(bottom), Mat4(1.0), s.addMaterial(Material{}));
    s.commit();
    Ray r;
    r.origin = Vec3(0.1, 1, 0.2);
    r.dir = Vec3(0, -1, 0);
    Hit h;
    ASSERT_TRUE(s.intersect(r, h));
    EXPECT_EQ(h.t, 1.0) << thickness;
    // From inside the slab, the offset origin of a downward ray finds the bottom, never the top again
    SurfacePoint sp = s.surface(r, h);
    Ray down;
    down.origin = offsetRayOrigin(sp.p, sp.pError, sp.ng, Vec3(0, -1, 0));
    down.dir = Vec3(0, -1, 0);
    Hit h2;
    ASSERT_TRUE(s.intersect(down, h2)) << thickness;
    EXPECT_NEAR(h2.t, thickness, thickness * 1e-6);
  }
  for (double radius : {1e-7, 1e-3, 1e3, 1e7})
    for (double offset : {0.0, 1e6, 1e8}) {
      Scene s;
      SphereSet sp;
      sp.centers = {Vec3(offset, -offset, offset)};
      sp.radii = {radius};
      TubeSet cs;
      cs.p0 = {Vec3(offset, -offset, offset) + Vec3(0, 0, -3 * radius)};
      cs.p1 = {Vec3(offset, -offset, offset) + Vec3(0, 0, -3 * radius) + Vec3(radius * 10, 0, 0)};
      cs.radii = {radius};
      s.addInstance(s.addSpheres(sp), Mat4(1.0), s.addMaterial(Material{}));
      s.addInstance(s.addTubes(cs), Mat4(1.0), s.addMaterial(Material{}));
      s.commit();
      Ray r;
      r.origin = Vec3(offset + 0.5 * radius, -offset, offset + 10 * radius);
      r.dir = Vec3(0, 0, -1);
      Hit h;
      ASSERT_TRUE(s.intersect(r, h)) << radius << " " << offset;
      double expect = 10 * radius - std::sqrt(0.75) * radius;
      // Absolute accuracy is limited by the coordinates' own resolution (ulp of the offset)
      double tol = 1e-9 * radius + 8 * std::numeric_limits<double>::epsilon() * (offset + 10 * radius);
      EXPECT_NEAR(h.t, expect, tol) << radius << " " << offset;
      // The tube behind the sphere is hit by a ray that misses the sphere
      r.origin.x = offset + 5 * radius;
      ASSERT_TRUE(s.intersect(r, h)) << "tube " << radius << " " << offset;
      EXPECT_NEAR(h.t, 12 * radius, tol + 1e-9 * radius) << radius;
    }
}

// Optics at the edge: IOR 10, nested and touching glass, camera inside a glass sphere, a light inside a closed
// mesh, kr + kt > 1. Every frame finishes, is finite, and the relations asserted hold.
TEST(Stability, OpticsAtTheEdge) {
  auto base = [](Scene& s) {
    Color4 c0(1, 1, 1, 1), c1(0.2f, 0.2f, 0.2f, 1);
    Material floor;
    floor.ambient = 0.3f;
    floor.colorSource = ColorSource::ScalarsAmbientAndDiffuse;
    s.addInstance(s.addMesh(makeGrid(Vec3(-6, -1, 6), Vec3(12, 0, 0), Vec3(0, 0, -12), 12, 12, &c0, &c1)), Mat4(1.0),
                  s.addMaterial(floor));
    Light l;
    l.positional = true;
    l.position = Vec3(2, 5, 3);
    l.coneAngle = 180;
    s.lights().push_back(l);
    s.background = Color(0.3f, 0.4f, 0.6f);
  };
  auto glass = [](float ior, float kt, float kr) {
    Material m;
    m.opacity = 0.0f;
    m.transmittance = Color(kt);
    m.reflectance = Color(kr);
    m.ior = ior;
    return m;
  };
  auto sphere = [](Scene& s, Vec3 c, double r, const Material& m) {
    SphereSet sp;
    sp.centers = {c};
    sp.radii = {r};
    s.addInstance(s.addSpheres(sp), Mat4(1.0), s.addMaterial(m));
  };
  struct Case {
    const char* name;
    std::function<void(Scene&)> build;
    Vec3 eye;
  };
  std::vector<Case> cases = {
      {"ior 10", [&](Scene& s) { sphere(s, Vec3(0), 1, glass(10, 0.9f, 0.1f)); }, Vec3(0, 1, 5)},
      {"nested glass",
       [&](Scene& s) {
         sphere(s, Vec3(0), 1, glass(1.5f, 0.9f, 0.1f));
         sphere(s, Vec3(0), 0.5, glass(1.33f, 0.9f, 0.1f));
       },
       Vec3(0, 1, 5)},
      {"touching glass",
       [&](Scene& s) {
         sphere(s, Vec3(-0.5, 0, 0), 0.5, glass(1.5f, 0.9f, 0.1f));
         sphere(s, Vec3(0.5, 0, 0), 0.5, glass(1.5f, 0.9f, 0.1f));
       },
       Vec3(0, 1, 5)},
      {"camera inside glass", [&](Scene& s) { sphere(s, Vec3(0, 0, 3), 3, glass(1.5f, 0.9f, 0.1f)); }, Vec3(0, 0.5, 3)},
      {"light inside closed mesh",
       [&](Scene& s) {
         s.addInstance(s.addMesh(makeSphereMesh(Vec3(2, 5, 3), 0.5, 16, 8)), Mat4(1.0), s.addMaterial(Material{}));
       },
       Vec3(0, 1, 5)},
      {"kr + kt > 1", [&](Scene& s) { sphere(s, Vec3(0), 1, glass(1.5f, 1.0f, 1.0f)); }, Vec3(0, 1, 5)},
  };
  for (const Case& c : cases) {
    Scene s;
    base(s);
    c.build(s);
    s.commit();
    RenderSettings rs;
    rs.integrator.maxDepth = 8;
    FrameBuffer fb;
    FrameStats fs = render(s, Camera::perspective(c.eye, Vec3(0), Vec3(0, 1, 0), 40, 1, 0.05, 50), rs, 48, 48, fb);
    int nonFinite = 0;
    for (const Color4& px : fb.color)
      for (int k = 0; k < 4; ++k) nonFinite += !std::isfinite(px[k]);
    std::printf("[stability] %-24s rays %llu, saved at depth cap %llu, non-finite %d\n", c.name,
                (unsigned long long)fs.rays.traced(), (unsigned long long)fs.rays.savedByDepth, nonFinite);
    EXPECT_EQ(nonFinite, 0) << c.name;
    EXPECT_EQ(fs.rays.safetyNetCatches(), 0u) << c.name;
    EXPECT_FALSE(fs.aborted);
    if (std::string(c.name) == "light inside closed mesh") {
      // Every point outside is in the shadow of the closed mesh around the light: the image equals the same
      // scene with the light switched off (ambient only)
      Scene dark;
      base(dark);
      c.build(dark);
      dark.lights()[0].intensity = 0.0f;
      dark.commit();
      FrameBuffer ref;
      render(dark, Camera::perspective(c.eye, Vec3(0), Vec3(0, 1, 0), 40, 1, 0.05, 50), rs, 48, 48, ref);
      EXPECT_EQ(fb.color, ref.color);
    }
  }
}

// Camera extremes: huge parallel scale, very near/far clipping, tiny and huge view angles. Finite, and the
// object in view is found.
TEST(Stability, CameraExtremes) {
  Scene s;
  SphereSet sp;
  sp.centers = {Vec3(0)};
  sp.radii = {1.0};
  s.addInstance(s.addSpheres(sp), Mat4(1.0), s.addMaterial(Material{}));
  s.lights().push_back(Light{});  // directional, from +z
  s.background = Color(0.5f, 0.0f, 0.0f);
  s.commit();
  struct Case {
    const char* name;
    Camera cam;
    bool expectHitAtCentre;
  } cases[] = {
      // One pixel is 1e8 units wide, yet the exact centre ray still meets the unit sphere
      {"parallel scale 1e9", Camera::parallel(Vec3(0, 0, 5), Vec3(0), Vec3(0, 1, 0), 1e9, 1, 0.1, 10), true},
      {"parallel scale 1e-9", Camera::parallel(Vec3(0, 0, 5), Vec3(0), Vec3(0, 1, 0), 1e-9, 1, 0.1, 10), true},
      {"near 1e-9 far 1e9", Camera::perspective(Vec3(0, 0, 5), Vec3(0), Vec3(0, 1, 0), 30, 1, 1e-9, 1e9), true},
      {"near 3.9999 far 4.0001", Camera::perspective(Vec3(0, 0, 5), Vec3(0), Vec3(0, 1, 0), 30, 1, 3.9999, 4.0001),
       true},
      {"view angle 1e-6", Camera::perspective(Vec3(0, 0, 5), Vec3(0), Vec3(0, 1, 0), 1e-6, 1, 0.1, 10), true},
      {"view angle 179", Camera::perspective(Vec3(0, 0, 5), Vec3(0), Vec3(0, 1, 0), 179, 1, 0.1, 10), true},
  };
  const int n = 17, centre = 8 * n + 8;  // odd size: pixel 8's centre is the exact image centre
  for (const Case& c : cases) {
    FrameBuffer fb;
    const FrameStats fs = render(s, c.cam, RenderSettings{}, n, n, fb);
    EXPECT_EQ(fs.rays.safetyNetCatches(), 0u) << c.name;
    for (const Color4& px : fb.color)
      for (int k = 0; k < 4; ++k) ASSERT_TRUE(std::isfinite(px[k])) << c.name;
    for (float d : fb.depth) ASSERT_TRUE(d >= 0.0f && d <= 1.0f) << c.name;
    // The sphere is lit white-grey from the front; the background is red. (Depth alone cannot tell: with
    // near 1e-9 / far 1e9 the GL depth of a point 4 units away rounds to 1.0 in float, as in OpenGL itself.)
    bool hit = fb.color[centre].y > 0.5f;
    EXPECT_EQ(hit, c.expectHitAtCentre) << c.name;
  }
}

// Bad input in the core: NaN / Inf positions, normals, colours; degenerate triangles; out-of-range indices;
// zero/negative radii; bad materials. No crash, no non-finite pixel, the rest of the scene renders unchanged.
TEST(Stability, BadInputIsSkippedAndTheRestRenders) {
  auto build = [](Scene& s, bool withBad) {
    s.addInstance(s.addMesh(makeSphereMesh(Vec3(0), 1, 24, 12)), Mat4(1.0), s.addMaterial(Material{}));
    if (!withBad) return;
    const double nan = std::nan(""), inf = std::numeric_limits<double>::infinity();
    TriangleMesh bad;
    bad.positions = {Vec3(nan, 0, 0), Vec3(1, inf, 0), Vec3(0, 1, 0), Vec3(2, 2, 2), Vec3(2, 2, 2),
                     Vec3(3, 3, 3),   Vec3(5, 5, 5),   Vec3(6, 5, 5), Vec3(5, 6, 5)};
    bad.triangles = {{0, 1, 2}, {3, 4, 5}, {6, 7, 99}, {3, 3, 3}};
    bad.normals = std::vector<Vec3f>(bad.positions.size(), Vec3f(std::nanf(""), 0, 0));
    bad.vertexColors = std::vector<Color4>(bad.positions.size(), Color4(std::nanf(""), 1, 1, 1));
    s.addInstance(s.addMesh(bad), Mat4(1.0), s.addMaterial(Material{}));
    SphereSet sp;
    sp.centers = {Vec3(nan), Vec3(3, 0, 0), Vec3(-3, 0, 0)};
    sp.radii = {1.0, 0.0, -1.0};
    s.addInstance(s.addSpheres(sp), Mat4(1.0), s.addMaterial(Material{}));
    Material m;
    m.ior = -1.0f;
    m.specularPower = -5.0f;
    m.opacity = 7.0f;
    m.reflectance = Color(std::nanf(""));
    EXPECT_NE(sanitizeMaterial(m), 0u);
    EXPECT_EQ(m.ior, 1.0f);
    EXPECT_EQ(m.opacity, 1.0f);
    EXPECT_TRUE(std::isfinite(m.reflectance.x));
    TubeSet cs;
    cs.p0 = {Vec3(0, 0, inf)};
    cs.p1 = {Vec3(0, 0, 0)};
    cs.radii = {1.0};
    s.addInstance(s.addTubes(cs), Mat4(1.0), s.addMaterial(m));
  };
  Scene good, bad;
  build(good, false);
  build(bad, true);
  for (Scene* s : {&good, &bad}) {
    Light l;
    s->lights().push_back(l);
  }
  good.commit();
  CommitStats cst = bad.commit();
  EXPECT_EQ(cst.invalidPrimitives, 4u /*triangles*/ + 3u /*spheres*/ + 1u /*tube*/);
  Camera cam = Camera::perspective(Vec3(0, 0, 5), Vec3(0), Vec3(0, 1, 0), 30, 1, 0.1, 100);
  FrameBuffer a, b;
  render(good, cam, RenderSettings{}, 40, 40, a);
  // Bad input is rejected at commit: nothing is left for the frame's safety nets to catch
  EXPECT_EQ(render(bad, cam, RenderSettings{}, 40, 40, b).rays.safetyNetCatches(), 0u);
  for (std::size_t i = 0; i < a.color.size(); ++i) {
    for (int k = 0; k < 4; ++k) ASSERT_TRUE(std::isfinite(b.color[i][k]));
    EXPECT_EQ(a.color[i], b.color[i]);
  }
}
