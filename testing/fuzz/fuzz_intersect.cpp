// libFuzzer target: the intersection routines and BVH on arbitrary doubles (NaN, Inf, denormals, huge values).
// Invariants: no crash, no sanitizer report; any reported hit has t inside the ray's (tMin, tMax) and finite
// barycentrics that sum to <= 1 (+ rounding); the BVH-accelerated closest hit equals brute force; the mesh seen
// at 8x8 from the ray's origin along its direction passes the frame checks of fuzz_checks.h (the depth net and the
// hit depths where origin, direction and vertices are finite and within 1e3, the valid domain there).
#include "geometry/shapes.h"
#include "image/renderer.h"
#include "scene/scene.h"
#include "fuzz_bytes.h"
#include "fuzz_checks.h"

#include <algorithm>
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
  if (m.triangles.empty()) {
    whitted_fuzz::endOfInput();
    return 0;
  }
  TriangleMesh copy = m;
  Scene scene;
  scene.addInstance(scene.addMesh(std::move(copy)), Mat4(1.0), scene.addMaterial(Material{}));
  scene.commit();
  // The mesh seen from the ray's origin along its direction, a perspective camera (near 0.5, far 5e3)
  {
    auto tame = [](const Vec3& v) { return isFinite(v) && std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)}) <= 1e3; };
    bool valid = tame(ray.origin) && tame(ray.dir) && glm::length(ray.dir) >= 1e-3;
    for (const Vec3& p : m.positions) valid = valid && tame(p);
    const Vec3 dir = ray.dir / glm::length(ray.dir);
    const Vec3 up = std::abs(dir.y) < 0.9 ? Vec3(0.0, 1.0, 0.0) : Vec3(1.0, 0.0, 0.0);
    const Camera camera = Camera::perspective(ray.origin, ray.origin + dir, up, 60.0, 1.0, 0.5, 5e3);
    RenderSettings rs;
    rs.threads = 1;
    FrameBuffer fb;
    const FrameStats fs = render(scene, camera, rs, 8, 8, fb);
    whitted_fuzz::checkFrame(scene, camera, 1, valid, fs, fb);
  }
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
  if (inDomain) {
    CHECK(found == std::isfinite(best));
    if (found) CHECK(std::abs(hit.t - best) <= 1e-10 * std::abs(best));
  }
  whitted_fuzz::endOfInput();
  return 0;
}
