// Shadow-ray transmittance: a surface crossed once attenuates once, also when the ray passes exactly through an
// edge or vertex shared by several triangles, or through the joint of two tubes of a tube. Each case is built at
// scale 1, 1e-6 and 1e6 and far from the origin (1e7), with rays constructed to pass exactly through the shared
// edge / vertex / joint centre.
#include "scene/scene.h"
#include "scenes/scenes.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <limits>
#include <string>

using namespace whitted;

namespace {

const Color kKt(0.5f, 0.7f, 0.9f);

/// p -> s * p + t.
struct Similarity {
  double s = 1.0;
  Vec3 t{0.0};
  Vec3 operator()(const Vec3& p) const { return s * p + t; }
  std::string name() const {
    char buf[64];
    std::snprintf(buf, sizeof buf, "scale %g offset %g", s, t.x);
    return buf;
  }
};

const Similarity kSimilarities[] = {
    {1.0, Vec3(0.0)}, {1e-6, Vec3(0.0)}, {1e6, Vec3(0.0)}, {1.0, Vec3(1e7, -1e7, 1e7)}, {1e-6, Vec3(1e7, -1e7, 1e7)}};

Material glass() {
  Material m;
  m.opacity = 0.0f;
  m.transmittance = kKt;
  return m;
}

TriangleMesh transformed(TriangleMesh m, const Similarity& x) {
  for (Vec3& p : m.positions) p = x(p);
  return m;
}

/// Transmittance of one shadow ray from origin along dir (no cutoff) through a single glass object.
Color shadow(Scene& s, const Vec3& origin, const Vec3& dir) {
  s.commit();
  Ray r;
  r.origin = origin;
  r.dir = dir;
  return s.transmittance(r, 0.0f);
}

void expectCrossings(const Color& got, int crossings, const std::string& what) {
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(got[c], std::pow(kKt[c], float(crossings)), 1e-6f) << what << ", channel " << c;
}

}  // namespace

// Two triangles sharing an edge, ray in a plane containing the edge, oblique to the surface: one crossing.
TEST(Shadow, SharedEdgeAttenuatesOnce) {
  for (const Similarity& x : kSimilarities) {
    TriangleMesh m;
    // Edge from (-1,0,0) to (1,0,0); one triangle on each side
    m.positions = {x(Vec3(-1, 0, 0)), x(Vec3(1, 0, 0)), x(Vec3(0, 1, 0)), x(Vec3(0.2, -1, 0))};
    m.triangles = {{0, 1, 2}, {1, 0, 3}};
    Scene s;
    s.addInstance(s.addMesh(m), Mat4(1.0), s.addMaterial(glass()));
    // The ray stays in the plane y = t.y that contains the edge, so the edge function is exactly zero
    Vec3 origin = x(Vec3(0.25, 0.0, 1.0));
    Color got = shadow(s, origin, Vec3(0.3, 0.0, -1.0));
    std::printf("[shadow] shared edge, %s: %g (kt %g)\n", x.name().c_str(), got.x, kKt.x);
    expectCrossings(got, 1, "shared edge, " + x.name());
  }
}

// A fan of 8 triangles around an apex (a shallow cone), ray exactly through the apex: one crossing.
TEST(Shadow, SharedVertexOfFanAttenuatesOnce) {
  for (const Similarity& x : kSimilarities) {
    TriangleMesh m;
    m.positions.push_back(x(Vec3(0, 0, 0)));
    for (int i = 0; i < 8; ++i) {
      double a = 2.0 * kPi * i / 8;
      m.positions.push_back(x(Vec3(std::cos(a), std::sin(a), -0.3)));
    }
    for (uint32_t i = 0; i < 8; ++i) m.triangles.push_back({0u, 1 + i, 1 + (i + 1) % 8});
    Scene s;
    s.addInstance(s.addMesh(m), Mat4(1.0), s.addMaterial(glass()));
    Color got = shadow(s, x(Vec3(0, 0, 1)), Vec3(0, 0, -1));
    std::printf("[shadow] fan vertex, %s: %g (kt %g)\n", x.name().c_str(), got.x, kKt.x);
    expectCrossings(got, 1, "fan vertex, " + x.name());
  }
}

// A closed triangulated UV sphere (single pole vertices shared by 24 triangles each, as vtkSphereSource builds
// it), ray along the polar axis through both poles: entering and leaving, two crossings.
TEST(Shadow, PolesOfTriangulatedSphereAttenuateOncePerCrossing) {
  for (const Similarity& x : kSimilarities) {
    Scene s;
    s.addInstance(s.addMesh(transformed(makeSphereMesh(Vec3(0.0), 1.0, 24, 12), x)), Mat4(1.0), s.addMaterial(glass()));
    Color got = shadow(s, x(Vec3(0, 2, 0)), Vec3(0, -1, 0));
    std::printf("[shadow] sphere poles, %s: %g (kt^2 %g)\n", x.name().c_str(), got.x, kKt.x * kKt.x);
    expectCrossings(got, 2, "sphere poles, " + x.name());
    // The same sphere as an instance with a transform (object-space crossing test)
    Scene t;
    Mat4 shift(1.0);
    shift[3] = Vec4(x.t, 1.0);
    t.addInstance(t.addMesh(transformed(makeSphereMesh(Vec3(0.0), 1.0, 24, 12), Similarity{x.s, Vec3(0.0)})), shift,
                  t.addMaterial(glass()));
    expectCrossings(shadow(t, x(Vec3(0, 2, 0)), Vec3(0, -1, 0)), 2, "instanced sphere poles, " + x.name());
  }
}

// Two tubes of a tube sharing an end point (straight and bent), ray through the joint's centre perpendicular
// to both axes: it enters and leaves the tube once each, where both tubes' caps and bodies meet.
TEST(Shadow, TubeJointAttenuatesOncePerCrossing) {
  for (const Similarity& x : kSimilarities) {
    for (Vec3 end : {Vec3(1, 0, 0), Vec3(0.6, 0.8, 0)}) {
      TubeSet cs;
      cs.p0 = {x(Vec3(-1, 0, 0)), x(Vec3(0, 0, 0))};
      cs.p1 = {x(Vec3(0, 0, 0)), x(end)};
      cs.radii = {0.25 * x.s};
      Scene s;
      s.addInstance(s.addTubes(cs), Mat4(1.0), s.addMaterial(glass()));
      Color got = shadow(s, x(Vec3(0, 0, 1)), Vec3(0, 0, -1));
      std::string what = std::string(end.y != 0.0 ? "bent" : "straight") + " tube joint, " + x.name();
      std::printf("[shadow] %s: %g (kt^2 %g)\n", what.c_str(), got.x, kKt.x * kKt.x);
      expectCrossings(got, 2, what);
    }
  }
}

// Distinct surfaces are never merged: two sheets of one mesh, or two tubes of one set, a hair apart (1e-9 of
// the scale), the ray through an edge of each sheet / the end seam of each tube: one crossing per surface.
TEST(Shadow, CloseDistinctSheetsAttenuateTwice) {
  for (const Similarity& x : kSimilarities) {
    // Skip where the gap is below the coordinates' resolution (1e-9 at 1e7 rounds to 0 or one ulp)
    if (x.s * 1e-9 < 16.0 * std::numeric_limits<double>::epsilon() * glm::length(x.t)) continue;
    TriangleMesh m;
    for (double z : {0.0, -1e-9}) {
      uint32_t b = uint32_t(m.positions.size());
      m.positions.insert(m.positions.end(), {x(Vec3(-1, 0, z)), x(Vec3(1, 0, z)), x(Vec3(0, 1, z)), x(Vec3(0, -1, z))});
      m.triangles.push_back({b, b + 1, b + 2});
      m.triangles.push_back({b + 1, b, b + 3});
    }
    Scene s;
    s.addInstance(s.addMesh(m), Mat4(1.0), s.addMaterial(glass()));
    Color got = shadow(s, x(Vec3(0.25, 0.0, 1.0)), Vec3(0.0, 0.0, -1.0));
    expectCrossings(got, 2, "two sheets 1e-9 apart, " + x.name());

    // Two parallel tubes of one set, 1e-9 apart, ray through the seams at their ends: four crossings
    TubeSet cs;
    cs.p0 = {x(Vec3(-1, 0, 0)), x(Vec3(-1, 0, -0.5 - 1e-9))};
    cs.p1 = {x(Vec3(0, 0, 0)), x(Vec3(0, 0, -0.5 - 1e-9))};
    cs.radii = {0.25 * x.s};
    Scene t;
    t.addInstance(t.addTubes(cs), Mat4(1.0), t.addMaterial(glass()));
    expectCrossings(shadow(t, x(Vec3(0, 0, 1)), Vec3(0, 0, -1)), 4, "two tubes 1e-9 apart, " + x.name());
  }
}
