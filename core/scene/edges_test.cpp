// Surface with edges and back-face materials: the edge distance across a ray, edges drawn within half their width
// in pixels (from the footprint at the path length, also seen in a mirror), only marked edges drawn, and the back
// material on back faces.
#include "scene/edges.h"
#include "shading/integrator.h"
#include "scene/scene.h"

#include <gtest/gtest.h>

using namespace whitted;

namespace {

Material unlit(Color c) {
  Material m;
  m.lighting = false;
  m.diffuseColor = c;
  return m;
}

// A unit square in the z = 0 plane, facing +z, as two triangles whose diagonal (0,0)-(1,1) is not a polygon edge
TriangleMesh square(bool markBoundaryOnly) {
  TriangleMesh m;
  m.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
  m.triangles = {glm::uvec3(0, 1, 2), glm::uvec3(0, 2, 3)};
  if (markBoundaryOnly) m.edgeFlags = {0b011, 0b110};  // 0-1, 1-2 | 2-3, 3-0
  return m;
}

// A camera ray from the eye at (x, y, 10) down the z axis, starting at height z0 (a near plane below the eye)
Color traceDown(const Scene& s, IntegratorSettings is, double x, double y, double z0 = 10.0) {
  is.eye = Vec3(x, y, 10.0);
  Integrator integ(s, is, Vec3(0, 1, 0));
  RayStats st;
  Ray r;
  r.origin = Vec3(x, y, z0);
  r.dir = Vec3(0, 0, -1);
  return integ.trace(r, st, Color(0.0f)).color;
}

}  // namespace

TEST(Edges, DistanceAcrossTheRay) {
  const Vec3 v[3] = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  const Vec3 down(0, 0, -1);
  EXPECT_NEAR(edgeDistance(v, 0b001, Vec3(0.5, 0.1, 0), down), 0.1, 1e-12);       // to edge 0-1
  EXPECT_NEAR(edgeDistance(v, 0b100, Vec3(0.1, 0.5, 0), down), 0.1, 1e-12);       // to edge 2-0
  EXPECT_NEAR(edgeDistance(v, 0b010, Vec3(0.25, 0.25, 0), down), std::sqrt(0.125), 1e-12);  // to 1-2
  EXPECT_EQ(edgeDistance(v, 0, Vec3(0.25, 0.25, 0), down), kInfinity);
  // Segments, not lines: beyond the segment's end the distance is to the vertex
  EXPECT_NEAR(edgeDistance(v, 0b001, Vec3(1.5, 0.5, 0), down), std::sqrt(0.5), 1e-12);
  // Seen at 60 degrees from the normal across the edge, the distance shrinks by cos(60) (foreshortening)
  const Vec3 slanted = glm::normalize(Vec3(0, std::sin(1.0471975511965976), -std::cos(1.0471975511965976)));
  EXPECT_NEAR(edgeDistance(v, 0b001, Vec3(0.5, 0.2, 0), slanted), 0.2 * 0.5, 1e-12);
}

TEST(Edges, DrawnWithinHalfTheirWidthInPixels) {
  Scene s;
  Material m = unlit(Color(0, 0, 1));
  m.edgeWidth = 4.0f;  // pixels
  m.edgeColor = Color(1, 0, 0);
  s.addInstance(s.addMesh(square(true)), Mat4(1.0), s.addMaterial(m));
  s.commit();
  ASSERT_TRUE(s.features().edges);
  IntegratorSettings is;
  is.pixelAngle = 0.001;  // at distance 10: a pixel is 0.01 wide, the edge 0.04, so 0.02 on each side
  EXPECT_EQ(traceDown(s, is, 0.5, 0.015), Color(1, 0, 0));
  EXPECT_EQ(traceDown(s, is, 0.5, 0.025), Color(0, 0, 1));
  EXPECT_EQ(traceDown(s, is, 0.985, 0.5), Color(1, 0, 0));
  // The triangulation's diagonal is not drawn
  EXPECT_EQ(traceDown(s, is, 0.5, 0.505), Color(0, 0, 1));
  // The footprint grows from the eye, not from where a camera ray starts (its near plane)
  EXPECT_EQ(traceDown(s, is, 0.5, 0.015, 2.0), Color(1, 0, 0));
  EXPECT_EQ(traceDown(s, is, 0.5, 0.025, 2.0), Color(0, 0, 1));
  // Twice as far, twice as wide in world units
  is.pixelAngle = 0.002;
  EXPECT_EQ(traceDown(s, is, 0.5, 0.035), Color(1, 0, 0));
  // Parallel projection: a constant footprint
  is.pixelAngle = 0.0;
  is.pixelSize = 0.01;
  EXPECT_EQ(traceDown(s, is, 0.5, 0.015), Color(1, 0, 0));
  EXPECT_EQ(traceDown(s, is, 0.5, 0.025), Color(0, 0, 1));
  // Without a footprint (or without flags marking all edges: the diagonal too) nothing / everything is drawn
  is.pixelSize = 0.0;
  EXPECT_EQ(traceDown(s, is, 0.5, 0.015), Color(0, 0, 1));
  Scene all;
  all.addInstance(all.addMesh(square(false)), Mat4(1.0), all.addMaterial(m));
  all.commit();
  is.pixelSize = 0.01;
  EXPECT_EQ(traceDown(all, is, 0.5, 0.505), Color(1, 0, 0));
}

TEST(Edges, SeenInAMirrorAtThePathLength) {
  // The square faces +z at z = 0; a mirror at z = 10 facing -z, a camera ray from z = 5 going +z: the path to the
  // square is 5 + 10 = 15 long, so an edge 3 pixels wide at pixelAngle 0.001 covers 0.0225 on each side
  Scene s;
  Material m = unlit(Color(0, 0, 1));
  m.edgeWidth = 3.0f;
  m.edgeColor = Color(1, 0, 0);
  s.addInstance(s.addMesh(square(true)), Mat4(1.0), s.addMaterial(m));
  TriangleMesh mirror;
  mirror.positions = {Vec3(-5, -5, 10), Vec3(5, -5, 10), Vec3(5, 5, 10), Vec3(-5, 5, 10)};
  mirror.triangles = {glm::uvec3(0, 2, 1), glm::uvec3(0, 3, 2)};  // facing -z
  Material kr = unlit(Color(0.0f));
  kr.reflectance = Color(1.0f);
  s.addInstance(s.addMesh(mirror), Mat4(1.0), s.addMaterial(kr));
  s.commit();
  IntegratorSettings is;
  is.pixelAngle = 0.001;
  auto up = [&](double y) {
    is.eye = Vec3(0.5, y, 5.0);
    Integrator integ(s, is, Vec3(0, 1, 0));
    RayStats st;
    Ray r;
    r.origin = Vec3(0.5, y, 5.0);
    r.dir = Vec3(0, 0, 1);
    return integ.trace(r, st, Color(0.0f)).color;
  };
  EXPECT_EQ(up(0.02), Color(1, 0, 0));
  EXPECT_EQ(up(0.025), Color(0, 0, 1));
}

TEST(Edges, BackMaterialOnBackFaces) {
  Scene s;
  Material front = unlit(Color(1, 0, 0));
  const uint32_t back = s.addMaterial(unlit(Color(0, 1, 0)));
  front.backMaterial = int32_t(back);
  s.addInstance(s.addMesh(square(false)), Mat4(1.0), s.addMaterial(front));
  s.commit();
  IntegratorSettings is;
  EXPECT_EQ(traceDown(s, is, 0.3, 0.6), Color(1, 0, 0));  // front face (normal +z, ray going -z)
  Integrator integ(s, is, Vec3(0, 1, 0));
  RayStats st;
  Ray r;
  r.origin = Vec3(0.3, 0.6, -10.0);
  r.dir = Vec3(0, 0, 1);
  EXPECT_EQ(integ.trace(r, st, Color(0.0f)).color, Color(0, 1, 0));
  // An out-of-range back material is dropped at commit
  Scene bad;
  Material m = unlit(Color(1, 0, 0));
  m.backMaterial = 7;
  bad.addInstance(bad.addMesh(square(false)), Mat4(1.0), bad.addMaterial(m));
  EXPECT_EQ(bad.commit().invalidMaterials, 1u);
  EXPECT_EQ(bad.material(0).backMaterial, -1);
}

TEST(Edges, EveryQuadEdgeOfAGrid) {
  // An 8 x 8 grid of unit quads (two triangles each, diagonals not drawn): enough triangles for a BVH of several
  // leaves, so the hit triangle's slot (leaf order) and index (original order) differ
  const int n = 8;
  TriangleMesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.positions.push_back(Vec3(i, j, 0));
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const uint32_t a = uint32_t(j * (n + 1) + i), b = a + 1, c = a + uint32_t(n) + 2, d = a + uint32_t(n) + 1;
      m.triangles.push_back(glm::uvec3(a, b, c));
      m.edgeFlags.push_back(0b011);
      m.triangles.push_back(glm::uvec3(a, c, d));
      m.edgeFlags.push_back(0b110);
    }
  Scene s;
  Material mat = unlit(Color(0, 0, 1));
  mat.edgeWidth = 2.0f;
  mat.edgeColor = Color(1, 0, 0);
  s.addInstance(s.addMesh(m), Mat4(1.0), s.addMaterial(mat));
  s.commit();
  IntegratorSettings is;
  is.pixelAngle = 0.005;  // 0.05 per pixel at distance 10: edges 0.05 on each side
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      EXPECT_EQ(traceDown(s, is, i + 0.5, j + 0.03), Color(1, 0, 0)) << i << " " << j;  // bottom edge
      EXPECT_EQ(traceDown(s, is, i + 0.03, j + 0.5), Color(1, 0, 0)) << i << " " << j;  // left edge
      EXPECT_EQ(traceDown(s, is, i + 0.97, j + 0.4), Color(1, 0, 0)) << i << " " << j;  // right edge
      EXPECT_EQ(traceDown(s, is, i + 0.5, j + 0.5), Color(0, 0, 1)) << i << " " << j;   // centre, diagonal
      EXPECT_EQ(traceDown(s, is, i + 0.3, j + 0.6), Color(0, 0, 1)) << i << " " << j;
    }
}
