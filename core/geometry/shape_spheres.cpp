#include "geometry/shape_spheres.h"

#include <algorithm>
#include <utility>

namespace whitted {

std::optional<PrimHit> intersectSphere(const Ray& ray, const Vec3& center, double radius) {
  // Stable form (Haines et al., Ray Tracing Gems ch. 7): discriminant from the perpendicular distance
  Vec3 f = ray.origin - center;
  double a = glm::dot(ray.dir, ray.dir);
  if (!(a > 0.0) || !(radius > 0.0)) return std::nullopt;
  double hb = glm::dot(f, ray.dir);
  Vec3 perp = f - (hb / a) * ray.dir;
  double r2 = radius * radius;
  double discOverA = r2 - glm::dot(perp, perp);
  if (discOverA < 0.0) return std::nullopt;
  double c = glm::dot(f, f) - r2;
  double q = -(hb + std::copysign(std::sqrt(a * discOverA), hb));
  double t0, t1;
  if (q == 0.0) {
    t0 = t1 = 0.0;
  } else {
    t0 = c / q;
    t1 = q / a;
  }
  if (t0 > t1) std::swap(t0, t1);
  if (t0 > ray.tMin && t0 < ray.tMax) return PrimHit{t0, 0.0, 0.0};
  if (t1 > ray.tMin && t1 < ray.tMax) return PrimHit{t1, 0.0, 0.0};
  return std::nullopt;
}

bool SphereShape::bounds(const SphereSet& s, uint32_t i, Bounds3& box) {
  double r = radiusAt(s.radii, i);
  if (!isFinite(s.centers[i]) || !(r > 0.0) || !std::isfinite(r)) return false;
  box = Bounds3{s.centers[i] - Vec3(r), s.centers[i] + Vec3(r)};
  return true;
}

void SphereShape::surface(const SphereSet& s, const Hit& hit, const Ray& r, const std::vector<Texture>&,
                          SurfacePoint& sp) {
  const Vec3& c = s.centers[hit.prim];
  double rad = radiusAt(s.radii, hit.prim);
  Vec3 q = r.origin + hit.t * r.dir;
  // Re-project onto the surface; the remaining error is a few ulps of |p| (pbrt-v4, sphere)
  sp.ng = safeNormalize(q - c, Vec3(0, 0, 1));
  sp.p = c + rad * sp.ng;
  sp.pError = gammaBound(5) * (glm::abs(sp.p) + glm::abs(c));
  sp.ns = sp.ng;
  if (!s.colors.empty()) {
    sp.color = s.colors[std::min<std::size_t>(hit.prim, s.colors.size() - 1)];
    sp.hasColor = true;
  }
}

}  // namespace whitted
