// Intersector tests against analytic answers, edge/vertex hits, far-away origins, watertightness.
#include "geometry/shapes.h"
#include "scene/scene.h"
#include "scenes/scenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

using namespace whitted;

namespace {
Ray makeRay(Vec3 o, Vec3 d) {
  Ray r;
  r.origin = o;
  r.dir = d;
  return r;
}
}  // namespace

TEST(Triangle, AnalyticHitAndBarycentrics) {
  Vec3 p0(0, 0, 0), p1(1, 0, 0), p2(0, 1, 0);
  auto h = intersectTriangle(makeRay(Vec3(0.25, 0.5, 2.0), Vec3(0, 0, -1)), p0, p1, p2);
  ASSERT_TRUE(h);
  EXPECT_DOUBLE_EQ(h->t, 2.0);
  EXPECT_DOUBLE_EQ(h->u, 0.25);
  EXPECT_DOUBLE_EQ(h->v, 0.5);
  EXPECT_FALSE(intersectTriangle(makeRay(Vec3(0.75, 0.75, 2.0), Vec3(0, 0, -1)), p0, p1, p2));
  // Behind the origin
  EXPECT_FALSE(intersectTriangle(makeRay(Vec3(0.25, 0.25, -1.0), Vec3(0, 0, -1)), p0, p1, p2));
}

TEST(Triangle, EdgeAndVertexHitsCountOnce) {
  // Two triangles sharing the diagonal of a unit square: rays exactly through the shared edge and the shared
  // vertices must hit at least one of them (watertight), and rays inside must hit exactly one.
  Vec3 a(0, 0, 0), b(1, 0, 0), c(1, 1, 0), d(0, 1, 0);
  for (double s : {0.0, 0.125, 0.5, 0.875, 1.0}) {
    Ray r = makeRay(Vec3(s, s, 1.0), Vec3(0, 0, -1));
    bool h1 = bool(intersectTriangle(r, a, b, c)), h2 = bool(intersectTriangle(r, a, c, d));
    EXPECT_TRUE(h1 || h2) << "leak through shared edge at s=" << s;
  }
}

TEST(Triangle, FarOriginKeepsPrecision) {
  // Camera 1e7 units away along the axis; the hit point must be exact to double rounding.
  Vec3 p0(-1, -1, 0), p1(1, -1, 0), p2(0, 1, 0);
  auto h = intersectTriangle(makeRay(Vec3(0.1, 0.2, 1e7), Vec3(0, 0, -1)), p0, p1, p2);
  ASSERT_TRUE(h);
  EXPECT_NEAR(h->t, 1e7, 1e-8);
}

TEST(Triangle, DegenerateAndNaNNeverHit) {
  Vec3 p0(0, 0, 0), p1(1, 0, 0);
  EXPECT_FALSE(intersectTriangle(makeRay(Vec3(0.5, 0, 1), Vec3(0, 0, -1)), p0, p1, p1));
  Vec3 nan(std::nan(""), 0, 0);
  EXPECT_FALSE(intersectTriangle(makeRay(Vec3(0.2, 0.2, 1), Vec3(0, 0, -1)), nan, p1, Vec3(0, 1, 0)));
  EXPECT_FALSE(intersectTriangle(makeRay(Vec3(0.2, 0.2, 1), Vec3(0, 0, 0)), p0, p1, Vec3(0, 1, 0)));
}

TEST(Sphere, AnalyticHits) {
  auto h = intersectSphere(makeRay(Vec3(0, 0, 5), Vec3(0, 0, -1)), Vec3(0), 1.0);
  ASSERT_TRUE(h);
  EXPECT_DOUBLE_EQ(h->t, 4.0);
  // From inside: the far side
  h = intersectSphere(makeRay(Vec3(0), Vec3(1, 0, 0)), Vec3(0), 2.0);
  ASSERT_TRUE(h);
  EXPECT_DOUBLE_EQ(h->t, 2.0);
  // Tangent miss just outside
  EXPECT_FALSE(intersectSphere(makeRay(Vec3(1.0000001, 0, 5), Vec3(0, 0, -1)), Vec3(0), 1.0));
  // Zero / negative radius
  EXPECT_FALSE(intersectSphere(makeRay(Vec3(0, 0, 5), Vec3(0, 0, -1)), Vec3(0), 0.0));
  EXPECT_FALSE(intersectSphere(makeRay(Vec3(0, 0, 5), Vec3(0, 0, -1)), Vec3(0), -1.0));
}

TEST(Sphere, FarOriginNoCancellation) {
  // A unit sphere seen from 1e8 away: the naive quadratic (b^2 - c with c ~ 1e16) loses the hit entirely.
  for (double dist : {1e4, 1e6, 1e8}) {
    auto h = intersectSphere(makeRay(Vec3(0.5, 0, dist), Vec3(0, 0, -1)), Vec3(0), 1.0);
    ASSERT_TRUE(h) << dist;
    EXPECT_NEAR(h->t, dist - std::sqrt(0.75), dist * 1e-15 + 1e-9) << dist;
  }
  // Tiny sphere far away
  auto h = intersectSphere(makeRay(Vec3(0, 0, 1e6), Vec3(0, 0, -1)), Vec3(0), 1e-6);
  ASSERT_TRUE(h);
  EXPECT_NEAR(h->t, 1e6 - 1e-6, 1e-9);
}

TEST(Tube, BodyAndCaps) {
  // Tube along x from -1 to 1, radius 0.5
  Vec3 a(-1, 0, 0), b(1, 0, 0);
  auto h = intersectTube(makeRay(Vec3(0.3, 0, 5), Vec3(0, 0, -1)), a, b, 0.5);
  ASSERT_TRUE(h);
  EXPECT_NEAR(h->t, 4.5, 1e-12);
  EXPECT_NEAR(h->u, 0.65, 1e-12);
  // Cap: along the axis from +x
  h = intersectTube(makeRay(Vec3(5, 0, 0), Vec3(-1, 0, 0)), a, b, 0.5);
  ASSERT_TRUE(h);
  EXPECT_NEAR(h->t, 3.5, 1e-12);
  // From inside: exits through the body
  h = intersectTube(makeRay(Vec3(0, 0, 0), Vec3(0, 1, 0)), a, b, 0.5);
  ASSERT_TRUE(h);
  EXPECT_NEAR(h->t, 0.5, 1e-12);
  // Far origin
  h = intersectTube(makeRay(Vec3(0.3, 0, 1e7), Vec3(0, 0, -1)), a, b, 0.5);
  ASSERT_TRUE(h);
  EXPECT_NEAR(h->t, 1e7 - 0.5, 1e-7);
  EXPECT_FALSE(intersectTube(makeRay(Vec3(0, 0.6, 5), Vec3(0, 0, -1)), a, b, 0.5));
}

// A long thin tube (length 1.4e3, far end at 1e3 from the origin) seen by rays from every direction aimed within 10
// radii of either end, radii 1e-3 down to 1e-9 (1e-12 of its length): every hit lies on the capsule's surface within
// the hit's own error bound, and every ray passing within 0.99 radii of the segment hits. Radii 1e-16 and 4e-303,
// far below the coordinates' rounding (1e-13 here): rays may miss, but no hit lies off the surface. The body's quadratic was
// solved from the ray's closest approach to the midpoint, where a ray crossing near an end passes far from the axis
// and |perp|^2 drowned r^2: 4241 of 20000 hits off the surface at radius 1e-3 (4e-5 radii, beyond their bound),
// 6009 at 1e-6 (up to 8.6 radii) and 600 missed rays there.
TEST(Tube, ThinLongTubeExactNearItsEnds) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  const Vec3 a(1.2e3, -0.7e3, 0.4e3), b(1e-3, 2e-3, -1e-3), ab = b - a;
  for (double r : {1e-3, 1e-6, 1e-9, 1e-16, 4e-303}) {
    const bool resolvable = r >= 1e-9;
    int hits = 0, off = 0, missed = 0;
    for (int k = 0; k < 4000; ++k) {
      const Vec3 end = (k & 1) ? a : b;
      const Vec3 target = end + Vec3(uni(rng), uni(rng), uni(rng)) * (10.0 * r * std::pow(10.0, -2.0 * std::abs(uni(rng))));
      const Vec3 origin = target + glm::normalize(Vec3(uni(rng), uni(rng), uni(rng))) * 10.0;
      const Ray ray = makeRay(origin, glm::normalize(target - origin));
      auto distance = [&](double t) {  // from the ray's point at t to the segment
        const Vec3 q = origin + t * ray.dir;
        const double u = std::clamp(glm::dot(q - a, ab) / glm::dot(ab, ab), 0.0, 1.0);
        return glm::length(q - (a + u * ab));
      };
      // The ray's closest approach to the segment: the distance is convex in t (a line against a convex set), so a
      // golden-section search over the whole ray segment [0, 20] finds it (the target end lies at t = 10)
      double lo = 0.0, hi = 20.0;
      for (int j = 0; j < 200; ++j) {
        const double m1 = hi - 0.6180339887 * (hi - lo), m2 = lo + 0.6180339887 * (hi - lo);
        (distance(m1) < distance(m2) ? hi : lo) = distance(m1) < distance(m2) ? m2 : m1;
      }
      const double closest = distance(0.5 * (lo + hi));
      const auto h = intersectTube(ray, a, b, r);
      if (!h) {
        missed += closest < 0.99 * r;
        continue;
      }
      ++hits;
      off += std::abs(distance(h->t) - r) > h->tError + 1e-12;  // + the rounding of the check's own point
    }
    EXPECT_EQ(off, 0) << "radius " << r << ": hits off the surface beyond their error bound";
    if (resolvable) {
      EXPECT_GT(hits, 1000) << r;
      EXPECT_EQ(missed, 0) << "radius " << r << ": rays passing within 0.99 radii that missed";
    }
  }
}

// Rays aimed exactly at the vertices and edge midpoints of a closed mesh from outside must hit it.
TEST(Watertight, ClosedSphereMeshEdgesAndVertices) {
  Scene scene;
  TriangleMesh m = makeSphereMesh(Vec3(0.0), 1.0, 24, 12);
  scene.addInstance(scene.addMesh(m), Mat4(1.0), scene.addMaterial(Material{}));
  scene.commit();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  int tried = 0, leaks = 0;
  for (const glm::uvec3& t : m.triangles) {
    const Vec3 ps[3] = {m.positions[t.x], m.positions[t.y], m.positions[t.z]};
    for (int k = 0; k < 3; ++k) {
      for (Vec3 target : {ps[k], 0.5 * (ps[k] + ps[(k + 1) % 3])}) {
        // Origins in a cone around the outward normal, so every ray crosses the surface (a ray grazing a
        // silhouette edge merely touches it and is not a leak). cos(angle to normal) >= 0.45 here.
        Vec3 jitter(U(rng), U(rng), U(rng));
        Vec3 origin = target + 2.0 * glm::normalize(glm::normalize(target) + 0.5 * jitter);
        Ray r = makeRay(origin, target - origin);
        r.tMax = 2.0;  // well past the target
        Hit h;
        ++tried;
        if (!scene.intersect(r, h)) ++leaks;
      }
    }
  }
  EXPECT_GT(tried, 1500);
  EXPECT_EQ(leaks, 0);
}
