// Scene editing without rebuilds: attribute-only updates keep object BVHs, textures are replaced and freed in
// place (ids reused, memory not growing); rebuilt, refit and restored objects keep exact hits; instance colours.
// The background upgrade is tested in upgrade_test.cpp.
#include "scene/scene.h"
#include "scene/scene_test_util.h"
#include "scenes/scenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

using namespace whitted;
using namespace whitted::scene_test;

namespace {

Texture solid(int w, uint8_t r, uint8_t g, uint8_t b) {
  Texture t;
  t.width = w;
  t.height = 1;
  for (int i = 0; i < w; ++i) t.rgba.insert(t.rgba.end(), {r, g, b, 255});
  return t;
}

/// Closest hits of 2000 rays from above through the scene's one mesh equal a brute-force test over mesh.
void expectHitsMatchBruteForce(const Scene& s, const TriangleMesh& mesh) {
  std::mt19937 rng(9);
  int hits = 0;
  for (int k = 0; k < 2000; ++k) {
    const Ray r = rayFromAbove(rng, 1.5);
    double best = kInfinity;
    uint32_t bestPrim = 0;
    for (uint32_t i = 0; i < mesh.triangles.size(); ++i) {
      const glm::uvec3& t = mesh.triangles[i];
      if (!isFinite(mesh.positions[t.x]) || !isFinite(mesh.positions[t.y]) || !isFinite(mesh.positions[t.z])) continue;
      auto h = intersectTriangle(r, mesh.positions[t.x], mesh.positions[t.y], mesh.positions[t.z]);
      if (h && h->t < best) {
        best = h->t;
        bestPrim = i;
      }
    }
    Hit h;
    EXPECT_EQ(s.intersect(r, h), std::isfinite(best));
    if (std::isfinite(best)) {
      ++hits;
      EXPECT_EQ(h.t, best);
      EXPECT_EQ(h.prim, bestPrim);
      if (!mesh.triangleColors.empty()) EXPECT_EQ(s.surface(r, h).color, mesh.triangleColors[bestPrim]);
    }
  }
  EXPECT_GT(hits, 500);
}

}  // namespace

// New colours on the same positions and triangles: no object BVH and no top level rebuilt, the new colours are
// used; moved positions: rebuilt.
TEST(Scene, UpdateMeshKeepsBvhWhenOnlyAttributesChange) {
  Scene s;
  TriangleMesh m = makeSphereMesh(Vec3(0.0), 1.0, 16, 8);
  m.vertexColors.assign(m.positions.size(), Color4(1, 0, 0, 1));
  uint32_t o = s.addMesh(m);
  Material mat;
  mat.lighting = false;
  mat.colorSource = ColorSource::ScalarsAmbientAndDiffuse;
  s.addInstance(o, Mat4(1.0), s.addMaterial(mat));
  EXPECT_EQ(s.commit().objectsRebuilt, 1);

  m.vertexColors.assign(m.positions.size(), Color4(0, 2, 0, 1));  // out of range: clamped to 1
  EXPECT_FALSE(s.updateMesh(o, m));
  CommitStats st = s.commit();
  EXPECT_EQ(st.objectsRebuilt, 0);
  EXPECT_FALSE(st.topLevelRebuilt);
  Ray r;
  r.origin = Vec3(0.1, 0.2, 5.0);
  r.dir = Vec3(0, 0, -1);
  Hit h;
  ASSERT_TRUE(s.intersect(r, h));
  SurfacePoint sp = s.surface(r, h);
  EXPECT_EQ(sp.color, Color4(0, 1, 0, 1));

  m.positions[5].x += 1e-12;  // any change of geometry updates the BVH (same triangles: refit)
  EXPECT_TRUE(s.updateMesh(o, m));
  EXPECT_EQ(s.commit().objectsRefit, 1);

  // Spheres and tubes alike
  SphereSet sp1;
  sp1.centers = {Vec3(3, 0, 0)};
  sp1.radii = {0.5};
  uint32_t so = s.addSpheres(sp1);
  TubeSet cs;
  cs.p0 = {Vec3(-3, 0, 0)};
  cs.p1 = {Vec3(-3, 1, 0)};
  cs.radii = {0.2};
  uint32_t co = s.addTubes(cs);
  s.addInstance(so, Mat4(1.0), 0);
  s.addInstance(co, Mat4(1.0), 0);
  s.commit();
  sp1.colors = {Color4(0, 0, 1, 1)};
  cs.colors0 = {Color4(0, 0, 1, 1)};
  EXPECT_FALSE(s.updateSpheres(so, sp1));
  EXPECT_FALSE(s.updateTubes(co, cs));
  EXPECT_EQ(s.commit().objectsRebuilt, 0);
  cs.radii = {0.25};
  EXPECT_TRUE(s.updateTubes(co, cs));
  EXPECT_EQ(s.commit().objectsRefit, 1);
  cs.p0.push_back(Vec3(-3, 1, 0));  // one tube more: rebuilt
  cs.p1.push_back(Vec3(-2, 1, 0));
  EXPECT_TRUE(s.updateTubes(co, cs));
  EXPECT_EQ(s.commit().objectsRebuilt, 1);
}

// A committed mesh keeps its triangles in BVH leaf order internally: mesh() still returns them as given, hits
// report the index as given (triangle colours follow it), an unchanged update keeps the BVH, a reordered triangle
// list is a geometry change, and invalid triangles (left out of the BVH) keep their place too.
TEST(Scene, LeafOrderIsInvisibleOutsideTheObject) {
  TriangleMesh m = makeSphereMesh(Vec3(0.0), 1.0, 16, 8);
  m.triangles.insert(m.triangles.begin() + 7, glm::uvec3(0, 0, 0));  // degenerate: invalid
  m.triangles.push_back(glm::uvec3(0, 1, 99999));                    // index out of range: invalid
  for (std::size_t i = 0; i < m.triangles.size(); ++i) m.triangleColors.push_back(Color4(float(i) / 1024.0f, 0, 0, 1));
  Scene s;
  uint32_t o = s.addMesh(m);
  Material mat;
  mat.lighting = false;
  s.addInstance(o, Mat4(1.0), s.addMaterial(mat));
  CommitStats st = s.commit();
  EXPECT_EQ(st.invalidPrimitives, 2u);
  EXPECT_EQ(s.mesh(o).triangles, m.triangles);
  EXPECT_EQ(s.stats().triangles, m.triangles.size() - 2);

  // Every hit's primitive, checked by brute force over the mesh as given
  int hits = 0;
  for (int i = 0; i < 200; ++i) {
    Ray r;
    r.origin = Vec3(0.01 * (i % 20) - 0.1, 0.01 * (i / 20) - 0.05, 5.0);
    r.dir = Vec3(0.02 * (i % 7), -0.03 * (i % 5), -1.0);
    Hit h;
    if (!s.intersect(r, h)) continue;
    ++hits;
    const glm::uvec3& t = m.triangles[h.prim];
    auto ph = intersectTriangle(r, m.positions[t.x], m.positions[t.y], m.positions[t.z]);
    ASSERT_TRUE(ph);
    EXPECT_EQ(ph->t, h.t);
    EXPECT_EQ(s.surface(r, h).color, m.triangleColors[h.prim]);
  }
  EXPECT_GT(hits, 100);

  EXPECT_FALSE(s.updateMesh(o, m));
  EXPECT_EQ(s.mesh(o).triangles, m.triangles);
  std::swap(m.triangles[0], m.triangles[1]);
  EXPECT_TRUE(s.updateMesh(o, m));
  EXPECT_EQ(s.commit().objectsRebuilt, 1);
  EXPECT_EQ(s.mesh(o).triangles, m.triangles);
}

// setTexture replaces in place; removeTexture frees the texels and addTexture reuses the id: 1000 replace or
// remove/add cycles leave the slot count and the texture memory where they were.
TEST(Scene, TexturesAreReplacedAndFreedInPlace) {
  Scene s;
  uint32_t a = s.addTexture(solid(256, 255, 0, 0));
  uint32_t b = s.addTexture(solid(64, 0, 255, 0));
  EXPECT_EQ(s.stats().textures, 2u);
  const std::size_t bytes = s.stats().textureBytes;
  for (int i = 0; i < 1000; ++i) {
    s.setTexture(a, solid(256, uint8_t(i), 0, 0));
    s.removeTexture(b);
    EXPECT_EQ(s.addTexture(solid(64, 0, uint8_t(i), 0)), b);
  }
  EXPECT_EQ(s.textureCount(), 2u);
  EXPECT_EQ(s.stats().textureBytes, bytes);
  EXPECT_NEAR(s.texture(a).sample(0.5f, 0.5f).r, 999 % 256 / 255.0f, 1e-6f);
  s.removeTexture(a);
  EXPECT_EQ(s.stats().textures, 1u);
  EXPECT_EQ(s.stats().textureBytes, 64u * 4u);
  EXPECT_EQ(s.texture(a).sample(0.5f, 0.5f), Color4(1.0f));  // a removed texture samples white
}

// A geometry change on an object that had been built (a time step, a new contour value) is rebuilt with the fast
// builder; its first build, and a new object, use the SAH builder. Closest hits through the fast tree equal a
// brute-force test of every triangle.
TEST(Scene, ReplacedGeometryIsRebuiltFastAndStillExact) {
  Scene s;
  uint32_t o = s.addMesh(makeSphereMesh(Vec3(0.0), 1.0, 24, 12));
  s.addInstance(o, Mat4(1.0), s.addMaterial(Material{}));
  CommitStats st = s.commit();
  EXPECT_EQ(st.objectsRebuilt, 1);
  EXPECT_EQ(st.objectsFastBuilt, 0);

  const TriangleMesh moved = makeSphereMesh(Vec3(0.2, -0.1, 0.05), 0.9, 32, 16);
  EXPECT_TRUE(s.updateMesh(o, moved));
  st = s.commit();
  EXPECT_EQ(st.objectsRebuilt, 1);
  EXPECT_EQ(st.objectsFastBuilt, 1);

  uint32_t fresh = s.addMesh(makeSphereMesh(Vec3(5.0, 0.0, 0.0), 1.0, 8, 4));
  s.addInstance(fresh, Mat4(1.0), 0);
  st = s.commit();
  EXPECT_EQ(st.objectsRebuilt, 1);
  EXPECT_EQ(st.objectsFastBuilt, 0);

  expectHitsMatchBruteForce(s, moved);  // the fresh sphere at x = 5 is out of these rays' way
}

// Moved points on the same triangles (a deforming mesh's time step) refit the BVH instead of rebuilding it, and
// closest hits through the refit tree equal a brute-force test; a point moved to infinity (an invalid triangle)
// falls back to a rebuild, and hits stay exact.
TEST(Scene, MovedPointsOnSameTrianglesAreRefit) {
  Scene s;
  TriangleMesh m = makeSphereMesh(Vec3(0.0), 1.0, 24, 12);
  m.triangleColors.assign(m.triangles.size(), Color4(1.0f));
  uint32_t o = s.addMesh(m);
  s.addInstance(o, Mat4(1.0), s.addMaterial(Material{}));
  s.commit();

  // A wave over the sphere and a shift: every box moves
  for (Vec3& p : m.positions) p = p * (1.0 + 0.2 * std::sin(3.0 * p.y)) + Vec3(0.3, -0.2, 0.1);
  for (std::size_t i = 0; i < m.triangleColors.size(); ++i) m.triangleColors[i] = Color4(float(i % 7) / 7.0f, 0, 0, 1);
  EXPECT_TRUE(s.updateMesh(o, m));
  CommitStats st = s.commit();
  EXPECT_EQ(st.objectsRefit, 1);
  EXPECT_EQ(st.objectsRebuilt, 0);
  EXPECT_TRUE(st.topLevelRebuilt);
  expectHitsMatchBruteForce(s, m);
  EXPECT_EQ(s.mesh(o).triangles, m.triangles);  // the order given, as before

  m.positions[3].x = kInfinity;  // its triangles become invalid: rebuilt instead
  EXPECT_TRUE(s.updateMesh(o, m));
  st = s.commit();
  EXPECT_EQ(st.objectsRefit, 0);
  EXPECT_EQ(st.objectsRebuilt, 1);
  EXPECT_GT(st.invalidPrimitives, 0u);
  expectHitsMatchBruteForce(s, m);
}

// The same on a mesh large enough that the topology check and the refit's boxes run in pieces on all cores: the
// refit tree finds the hits a tree built from scratch finds; a triangle turned over is a new topology
// (rebuilt), and a point moved to infinity makes the refit fall back to a rebuild (the given triangles' leaf slots,
// and so the pieces they fall in, are the tree's choice).
TEST(Scene, LargeMeshTopologyCheckAndRefitInPieces) {
  TriangleMesh m = makeSphereMesh(Vec3(0.0), 1.0, 640, 240);
  ASSERT_GT(m.triangles.size(), 4u * 65536u);
  Scene s;
  const uint32_t o = s.addMesh(m);
  s.addInstance(o, Mat4(1.0), s.addMaterial(Material{}));
  s.commit();
  for (Vec3& p : m.positions) p = p * (1.0 + 0.2 * std::sin(3.0 * p.y)) + Vec3(0.3, -0.2, 0.1);
  EXPECT_TRUE(s.updateMesh(o, m));
  CommitStats st = s.commit();
  EXPECT_EQ(st.objectsRefit, 1);
  EXPECT_EQ(st.objectsRebuilt, 0);
  auto sameHitsAsFresh = [](const Scene& a, const TriangleMesh& mesh) {
    Scene fresh;
    fresh.addInstance(fresh.addMesh(mesh), Mat4(1.0), fresh.addMaterial(Material{}));
    fresh.commit();
    expectSameHits(a, fresh, 1.5, 4000);
  };
  sameHitsAsFresh(s, m);

  std::swap(m.triangles.back().y, m.triangles.back().z);  // the last triangle turned over: another topology
  EXPECT_TRUE(s.updateMesh(o, m));
  st = s.commit();
  EXPECT_EQ(st.objectsRefit, 0);
  EXPECT_EQ(st.objectsRebuilt, 1);
  sameHitsAsFresh(s, m);

  m.positions[m.triangles.back().x].x += 0.01;  // moved: refit
  EXPECT_TRUE(s.updateMesh(o, m));
  EXPECT_EQ(s.commit().objectsRefit, 1);
  m.positions[m.triangles.back().x].x = kInfinity;  // invalid: rebuilt instead
  EXPECT_TRUE(s.updateMesh(o, m));
  st = s.commit();
  EXPECT_EQ(st.objectsRefit, 0);
  EXPECT_EQ(st.objectsRebuilt, 1);
  EXPECT_GT(st.invalidPrimitives, 0u);
}

// A refit whose tree would trace much slower (points that trade places: every triangle now spans the sphere, the
// kept topology groups far-apart triangles) is rebuilt instead; a gentle deformation keeps its refit. Hits stay
// exact either way.
TEST(Scene, RefitThatTracesTooSlowlyIsRebuilt) {
  Scene s;
  TriangleMesh m = makeSphereMesh(Vec3(0.0), 1.0, 48, 24);
  uint32_t o = s.addMesh(m);
  s.addInstance(o, Mat4(1.0), s.addMaterial(Material{}));
  s.commit();

  for (Vec3& p : m.positions) p *= 1.0 + 0.05 * std::sin(4.0 * p.x);
  EXPECT_TRUE(s.updateMesh(o, m));
  CommitStats st = s.commit();
  EXPECT_EQ(st.objectsRefit, 1);
  EXPECT_EQ(st.objectsRefitRejected, 0);
  EXPECT_GT(st.refitCostRatio, 0.5);
  EXPECT_LE(st.refitCostRatio, Object::kRefitRebuildRatio);
  expectHitsMatchBruteForce(s, m);

  std::shuffle(m.positions.begin(), m.positions.end(), std::mt19937(4));
  EXPECT_TRUE(s.updateMesh(o, m));
  st = s.commit();
  EXPECT_EQ(st.objectsRefit, 0);
  EXPECT_EQ(st.objectsRefitRejected, 1);
  EXPECT_GT(st.refitCostRatio, Object::kRefitRebuildRatio);
  EXPECT_EQ(st.objectsRebuilt, 1);
  EXPECT_EQ(st.objectsFastBuilt, 1);
  expectHitsMatchBruteForce(s, m);
  EXPECT_NEAR(s.object(o).refitCostRatio(), 1.0, 1e-12);  // a fresh tree
}

// An object taken out of the scene (a time cache keeping an earlier step) leaves its id free for other geometry,
// and restored later it needs no rebuild: the same hits as before, only the top level is rebuilt.
TEST(Scene, TakenObjectIsRestoredWithoutRebuild) {
  Scene s;
  TriangleMesh first = makeSphereMesh(Vec3(0.0), 1.0, 24, 12);
  uint32_t o = s.addMesh(first);
  s.addInstance(o, Mat4(1.0), s.addMaterial(Material{}));
  s.commit();
  Object kept = s.takeObject(o);
  EXPECT_EQ(s.stats().triangles, 0u);

  TriangleMesh second = makeSphereMesh(Vec3(0.3, 0, 0), 1.1, 10, 5);  // another step: other topology
  s.setMesh(o, second);
  CommitStats st = s.commit();
  EXPECT_EQ(st.objectsRebuilt, 1);
  EXPECT_EQ(st.objectsFastBuilt, 1);  // the id had geometry before: a replacement
  expectHitsMatchBruteForce(s, second);

  Object copy = s.object(o);  // keep this step too (a copy), then bring the first back
  s.restoreObject(o, std::move(kept));
  st = s.commit();
  EXPECT_EQ(st.objectsRebuilt, 0);
  EXPECT_EQ(st.objectsRefit, 0);
  EXPECT_TRUE(st.topLevelRebuilt);
  expectHitsMatchBruteForce(s, first);
  EXPECT_EQ(s.mesh(o).triangles, first.triangles);
  s.restoreObject(o, std::move(copy));
  EXPECT_EQ(s.commit().objectsRebuilt, 0);
  expectHitsMatchBruteForce(s, second);
}

// Instance colours: many instances of one object with one material, each seen with its own colour (over the
// object's own colours), sanitised; clearing one restores the object's colour.
TEST(Scene, InstanceColorsReplaceObjectColors) {
  Scene s;
  SphereSet balls;
  balls.centers = {Vec3(0.0)};
  balls.radii = {0.4};
  balls.colors = {Color4(0.5f, 0.5f, 0.5f, 1.0f)};
  const uint32_t o = s.addSpheres(balls);
  Material mat;
  mat.colorSource = ColorSource::ScalarsAmbientAndDiffuse;
  const uint32_t m = s.addMaterial(mat);
  std::vector<uint32_t> ids;
  for (int i = 0; i < 3; ++i) {
    Mat4 place(1.0);
    place[3] = Vec4(2.0 * i, 0.0, 0.0, 1.0);
    ids.push_back(s.addInstance(o, place, m));
  }
  s.setInstanceColor(ids[0], Color4(1, 0, 0, 1));
  s.setInstanceColor(ids[1], Color4(0, std::nanf(""), 2, -1));  // sanitised like geometry colours
  s.commit();
  auto colorAt = [&](double x) {
    Ray r;
    r.origin = Vec3(x, 0.0, 5.0);
    r.dir = Vec3(0, 0, -1);
    Hit h;
    EXPECT_TRUE(s.intersect(r, h));
    return s.surface(r, h).color;
  };
  EXPECT_EQ(colorAt(0.0), Color4(1, 0, 0, 1));
  EXPECT_EQ(colorAt(2.0), Color4(0, 0, 1, 0));
  EXPECT_EQ(colorAt(4.0), Color4(0.5f, 0.5f, 0.5f, 1.0f));
  s.clearInstanceColor(ids[0]);
  EXPECT_EQ(colorAt(0.0), Color4(0.5f, 0.5f, 0.5f, 1.0f));
  EXPECT_EQ(s.stats().spheres, 1u);  // one object for every instance
}
