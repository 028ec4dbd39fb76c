#include "shapes.h"

#include <algorithm>
#include <utility>

namespace whitted {

namespace {

int maxAxis(const Vec3& v) {
  Vec3 a = glm::abs(v);
  return (a.x > a.y) ? (a.x > a.z ? 0 : 2) : (a.y > a.z ? 1 : 2);
}

/// Roots of a*t^2 + 2*hb*t + c = 0 computed without cancellation; false when there is no real root.
bool solveQuadraticHalfB(double a, double hb, double c, double& t0, double& t1) {
  if (a == 0.0) return false;
  double disc = hb * hb - a * c;
  if (disc < 0.0) return false;
  double q = -(hb + std::copysign(std::sqrt(disc), hb));
  if (q == 0.0) {
    t0 = t1 = 0.0;
    return true;
  }
  t0 = c / q;
  t1 = q / a;
  if (t0 > t1) std::swap(t0, t1);
  return true;
}

}  // namespace

TriangleRay::TriangleRay(const Ray& ray) {
  // Permute axes so the ray direction's largest component is z
  kz = maxAxis(ray.dir);
  kx = (kz + 1) % 3;
  ky = (kx + 1) % 3;
  if (ray.dir[kz] < 0.0) std::swap(kx, ky);
  double dz = ray.dir[kz];
  valid = dz != 0.0 && isFinite(ray.dir);
  if (!valid) return;
  sx = ray.dir[kx] / dz;
  sy = ray.dir[ky] / dz;
  sz = 1.0 / dz;
}

std::optional<PrimHit> intersectTriangle(const Ray& ray, const TriangleRay& tr, const Vec3& p0, const Vec3& p1,
                                         const Vec3& p2) {
  if (!tr.valid) return std::nullopt;
  const int kx = tr.kx, ky = tr.ky, kz = tr.kz;
  const double sx = tr.sx, sy = tr.sy, sz = tr.sz;

  // Translate vertices to the ray origin and shear so the ray becomes the +z axis
  Vec3 a = p0 - ray.origin, b = p1 - ray.origin, c = p2 - ray.origin;
  double ax = a[kx] - sx * a[kz], ay = a[ky] - sy * a[kz];
  double bx = b[kx] - sx * b[kz], by = b[ky] - sy * b[kz];
  double cx = c[kx] - sx * c[kz], cy = c[ky] - sy * c[kz];

  // Scaled barycentrics (edge functions)
  double u = cx * by - cy * bx;
  double v = ax * cy - ay * cx;
  double w = bx * ay - by * ax;
  if (u == 0.0 || v == 0.0 || w == 0.0) {
    // Re-evaluate exactly-on-edge cases in extended precision so the sign decision is consistent
    long double lu = (long double)cx * by - (long double)cy * bx;
    long double lv = (long double)ax * cy - (long double)ay * cx;
    long double lw = (long double)bx * ay - (long double)by * ax;
    u = (double)lu;
    v = (double)lv;
    w = (double)lw;
  }
  if ((u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0)) return std::nullopt;
  double det = u + v + w;
  if (det == 0.0 || !std::isfinite(det)) return std::nullopt;

  // Scaled hit distance and range test without division
  double az = sz * a[kz], bz = sz * b[kz], cz = sz * c[kz];
  double tScaled = u * az + v * bz + w * cz;
  double invDet = 1.0 / det;
  double t = tScaled * invDet;
  if (!(t > ray.tMin && t < ray.tMax)) return std::nullopt;

  // Reject t that is not conservatively positive given its rounding error (pbrt-v4, section 6.8.7): a ray
  // leaving a surface can then never re-hit that surface near t = 0, whatever the scene's scale
  double maxZt = std::max(std::abs(az), std::max(std::abs(bz), std::abs(cz)));
  double maxXt = std::max(std::abs(ax), std::max(std::abs(bx), std::abs(cx)));
  double maxYt = std::max(std::abs(ay), std::max(std::abs(by), std::abs(cy)));
  double deltaZ = gammaBound(3) * maxZt;
  double deltaX = gammaBound(5) * (maxXt + maxZt);
  double deltaY = gammaBound(5) * (maxYt + maxZt);
  double deltaE = 2.0 * (gammaBound(2) * maxXt * maxYt + deltaY * maxXt + deltaX * maxYt);
  double maxE = std::max(std::abs(u), std::max(std::abs(v), std::abs(w)));
  double deltaT = 3.0 * (gammaBound(3) * maxE * maxZt + deltaE * maxZt + deltaZ * maxE) * std::abs(invDet);
  if (t <= deltaT) return std::nullopt;
  return PrimHit{t, v * invDet, w * invDet};
}

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

std::optional<PrimHit> intersectCapsule(const Ray& ray, const Vec3& pa, const Vec3& pb, double radius) {
  if (!(radius > 0.0)) return std::nullopt;
  Vec3 axis = pb - pa;
  double len2 = glm::dot(axis, axis);
  if (len2 == 0.0) {
    auto h = intersectSphere(ray, pa, radius);
    if (h) h->u = 0.0;
    return h;
  }
  double a0 = glm::dot(ray.dir, ray.dir);
  if (!(a0 > 0.0)) return std::nullopt;

  // Re-centre the origin at the ray's closest approach to the segment midpoint to avoid cancellation
  Vec3 mid = 0.5 * (pa + pb);
  double tShift = -glm::dot(ray.origin - mid, ray.dir) / a0;
  Vec3 o = ray.origin + tShift * ray.dir;

  double best = ray.tMax;
  double bestU = 0.0;
  bool found = false;
  auto consider = [&](double tLocal, double u) {
    double t = tLocal + tShift;
    if (t > ray.tMin && t < best) {
      best = t;
      bestU = u;
      found = true;
    }
  };

  // Cylinder body: solve |perp(o - a) + t perp(d)|^2 = r^2
  Vec3 n = axis / std::sqrt(len2);
  Vec3 oa = o - pa;
  Vec3 oPerp = oa - glm::dot(oa, n) * n;
  Vec3 dPerp = ray.dir - glm::dot(ray.dir, n) * n;
  double t0, t1;
  if (solveQuadraticHalfB(glm::dot(dPerp, dPerp), glm::dot(oPerp, dPerp), glm::dot(oPerp, oPerp) - radius * radius, t0,
                          t1)) {
    for (double t : {t0, t1}) {
      double y = glm::dot(oa + t * ray.dir, axis) / len2;
      if (y >= 0.0 && y <= 1.0) consider(t, y);
    }
  }

  // Spherical caps, each valid only on its own side of the body
  for (int e = 0; e < 2; ++e) {
    const Vec3& c = e ? pb : pa;
    Vec3 f = o - c;
    double hb = glm::dot(f, ray.dir);
    if (solveQuadraticHalfB(a0, hb, glm::dot(f, f) - radius * radius, t0, t1)) {
      for (double t : {t0, t1}) {
        double y = glm::dot(o + t * ray.dir - pa, axis) / len2;
        if ((e == 0 && y <= 0.0) || (e == 1 && y >= 1.0)) consider(t, e ? 1.0 : 0.0);
      }
    }
  }
  if (!found) return std::nullopt;
  return PrimHit{best, bestU, 0.0};
}

Vec3 triangleHitError(const Vec3& p0, const Vec3& p1, const Vec3& p2, double b0, double b1, double b2) {
  return gammaBound(7) * (glm::abs(b0 * p0) + glm::abs(b1 * p1) + glm::abs(b2 * p2));
}

}  // namespace whitted
