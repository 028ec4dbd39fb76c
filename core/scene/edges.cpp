#include "scene/edges.h"

#include "scene/scene.h"

#include <algorithm>
#include <cmath>

namespace whitted {

double edgeDistance(const Vec3 v[3], uint8_t flags, const Vec3& p, const Vec3& dir) {
  // Project the vertices, relative to p, on the plane perpendicular to the ray: p is the origin there
  Vec3 q[3];
  for (int i = 0; i < 3; ++i) {
    const Vec3 r = v[i] - p;
    q[i] = r - glm::dot(r, dir) * dir;
  }
  // Distance from the origin to each flagged segment
  double best = kInfinity;
  for (int k = 0; k < 3; ++k) {
    if (!(flags & (1u << k))) continue;
    const Vec3 &a = q[k], &b = q[(k + 1) % 3];
    const Vec3 ab = b - a;
    const double len2 = glm::dot(ab, ab);
    const double s = len2 > 0.0 ? std::clamp(-glm::dot(a, ab) / len2, 0.0, 1.0) : 0.0;
    best = std::min(best, glm::length(a + s * ab));
  }
  return best;
}

double Scene::edgeDistance(const Ray& ray, const Hit& hit, const Vec3& p) const {
  const Instance& in = instances_[hit.instance];
  const TriangleMesh* mesh = std::get_if<TriangleMesh>(&objects_[in.object].geometry);
  if (!mesh) return kInfinity;  // spheres and tubes have no edges
  // The triangle sits at the hit's leaf slot; per-triangle attributes use the original index
  const glm::uvec3& t = mesh->triangles[hit.slot];
  const uint8_t flags = mesh->edgeFlags.size() == mesh->triangles.size() ? mesh->edgeFlags[hit.prim] : uint8_t(7);
  Vec3 v[3] = {mesh->positions[t.x], mesh->positions[t.y], mesh->positions[t.z]};
  if (!in.identity)
    for (Vec3& x : v) x = transformPoint(in.toWorld, x);
  return whitted::edgeDistance(v, flags, p, glm::normalize(ray.dir));
}

}  // namespace whitted
