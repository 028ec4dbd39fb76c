// libFuzzer target: the intersection routines and BVH on arbitrary doubles (NaN, Inf, denormals, huge values).
// Invariants: no crash, no sanitizer report; any reported hit has t inside the ray's (tMin, tMax) and finite
// barycentrics that sum to <= 1 (+ rounding); the BVH-accelerated closest hit equals brute force.
#include "scene/scene.h"
#include "geometry/shapes.h"
#include "fuzz_bytes.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

using namespace whitted;

namespace {
using Reader = whitted_fuzz::Bytes;
}  // namespace

#define CHECK(cond)                                                           \
  do {                                                                        \
    if (!(cond)) {                                                            \
      std::fprintf(stderr, "check failed at line %d: %s\n", __LINE__, #cond); \
      std::abort();                                                           \
    }                                                                         \
  } while (0)

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  Reader r{data, size};
  Ray ray;
  ray.origin = r.v3();
  ray.dir = r.v3();
  // Specified behaviour: direction components below 1e-290 in magnitude count as 0 (a ray nearly parallel to a
  // face plane is traversed as parallel); the brute-force reference sees the same ray
  for (int i = 0; i < 3; ++i)
    if (std::abs(ray.dir[i]) < 1e-290) ray.dir[i] = 0.0;
  ray.tMin = 0.0;
  ray.tMax = kInfinity;
  Vec3 p0 = r.v3(), p1 = r.v3(), p2 = r.v3();
  if (auto h = intersectTriangle(ray, p0, p1, p2)) {
    CHECK(h->t > ray.tMin && h->t < ray.tMax);
    CHECK(std::isfinite(h->u) && std::isfinite(h->v));
    CHECK(h->u >= -1e-12 && h->v >= -1e-12 && h->u + h->v <= 1.0 + 1e-12);
  }
  double radius = r.d();
  if (auto h = intersectSphere(ray, p0, radius)) CHECK(h->t > ray.tMin && h->t < ray.tMax);
  if (auto h = intersectTube(ray, p0, p1, radius)) CHECK(h->t > ray.tMin && h->t < ray.tMax);

  // A small mesh from the remaining bytes: BVH closest hit must equal brute force
  TriangleMesh m;
  while (r.n >= 9 * sizeof(double) && m.positions.size() < 300) {
    uint32_t b = uint32_t(m.positions.size());
    m.positions.push_back(r.v3());
    m.positions.push_back(r.v3());
    m.positions.push_back(r.v3());
    m.triangles.push_back({b, b + 1, b + 2});
  }
  if (m.triangles.empty()) return 0;
  TriangleMesh copy = m;
  Scene scene;
  scene.addInstance(scene.addMesh(std::move(copy)), Mat4(1.0), scene.addMaterial(Material{}));
  scene.commit();
  Hit hit;
  bool found = scene.intersect(ray, hit);
  double best = kInfinity;
  for (uint32_t i = 0; i < m.triangles.size(); ++i) {
    const auto& t = m.triangles[i];
    const Vec3 &a = m.positions[t.x], &b = m.positions[t.y], &c = m.positions[t.z];
    if (!isFinite(a) || !isFinite(b) || !isFinite(c)) continue;  // the scene skips these
    Vec3 n = glm::cross(b - a, c - a);
    if (!(glm::dot(n, n) > 0.0) || !isFinite(n)) continue;
    if (auto h = intersectTriangle(ray, a, b, c)) best = std::min(best, h->t);
  }
  // Agreement is specified for magnitudes in [1e-100, 1e100]: beyond, products in the triangle test overflow or
  // underflow and the brute-force reference itself reports false hits (seen: 1e231 x 1e78)
  auto tame = [](const Vec3& v) {
    for (int i = 0; i < 3; ++i)
      if (v[i] != 0.0 && !(std::abs(v[i]) >= 1e-100 && std::abs(v[i]) <= 1e100)) return false;
    return true;
  };
  bool inDomain = tame(ray.origin) && tame(ray.dir);
  for (const Vec3& p : m.positions) inDomain = inDomain && tame(p);
  if (!inDomain) return 0;
  CHECK(found == std::isfinite(best));
  if (found) CHECK(std::abs(hit.t - best) <= 1e-10 * std::abs(best));
  return 0;
}
