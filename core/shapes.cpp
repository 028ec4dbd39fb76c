#include "shapes.h"

#include <algorithm>
#include <utility>

namespace whitted {

namespace {

int maxAxis(const Vec3& v) {
  Vec3 a = glm::abs(v);
  return (a.x > a.y) ? (a.x > a.z ? 0 : 2) : (a.y > a.z ? 1 : 2);
}

/// Roots of a*t^2 + 2*hb*t + c = 0 computed without cancellation; false when there is no real root. disc receives
/// the discriminant hb^2 - a*c.
bool solveQuadraticHalfB(double a, double hb, double c, double& t0, double& t1, double& disc) {
  if (a == 0.0) return false;
  disc = hb * hb - a * c;
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

double norm1(const Vec3& v) {
  return std::abs(v.x) + std::abs(v.y) + std::abs(v.z);
}

/// Bound on the error of a root of |o + t d - c|_perp^2 = r^2 (a sphere, or a cylinder with d and o projected
/// perpendicular to its axis) solved as a*t^2 + 2*hb*t + c = 0 with discriminant disc, when the inputs and the
/// arithmetic of the solve are off by at most e (absolute, in position units; backward error). Moving the
/// surface by e along its normal moves the root by e*r/sqrt(disc) (e over the cosine of incidence, in units of
/// |d|), or by at most sqrt(2*r*e/a) + e/sqrt(a) at grazing incidence, where the first form diverges.
double quadraticRootError(double a, double disc, double radius, double e) {
  double grazing = std::sqrt(2.0 * radius * e / a) + e / std::sqrt(a);
  double regular = disc > 0.0 ? e * radius / std::sqrt(disc) : grazing;
  return std::min(regular, grazing);
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
  // An edge function exactly zero: the ray meets an edge or vertex, which the neighbouring triangle accepts too
  return PrimHit{t, v * invDet, w * invDet, deltaT, u == 0.0 || v == 0.0 || w == 0.0};
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
  double a0 = glm::dot(ray.dir, ray.dir);
  if (!(a0 > 0.0)) return std::nullopt;
  Vec3 axis = pb - pa;
  double len2 = glm::dot(axis, axis);
  const double len = std::sqrt(len2);
  const bool point = len2 == 0.0;  // a zero-length capsule is a sphere: its one cap, u = 0

  // Re-centre the origin at the ray's closest approach to the segment midpoint to avoid cancellation
  Vec3 mid = 0.5 * (pa + pb);
  double tShift = -glm::dot(ray.origin - mid, ray.dir) / a0;
  Vec3 o = ray.origin + tShift * ray.dir;

  double best = ray.tMax;
  double bestU = 0.0, bestLocal = 0.0, bestA = 0.0, bestDisc = 0.0;
  bool bestCap = false;
  bool found = false;
  // tLocal: root of the solve with leading coefficient a and discriminant disc; cap: on an end cap
  auto consider = [&](double tLocal, double u, double a, double disc, bool cap) {
    double t = tLocal + tShift;
    if (t > ray.tMin && t < best) {
      best = t;
      bestU = u;
      bestLocal = tLocal;
      bestA = a;
      bestDisc = disc;
      bestCap = cap;
      found = true;
    }
  };

  double t0, t1, disc;
  if (!point) {
    // Cylinder body: solve |perp(o - a) + t perp(d)|^2 = r^2
    Vec3 n = axis / len;
    Vec3 oa = o - pa;
    Vec3 oPerp = oa - glm::dot(oa, n) * n;
    Vec3 dPerp = ray.dir - glm::dot(ray.dir, n) * n;
    double aPerp = glm::dot(dPerp, dPerp);
    if (solveQuadraticHalfB(aPerp, glm::dot(oPerp, dPerp), glm::dot(oPerp, oPerp) - radius * radius, t0, t1, disc)) {
      for (double t : {t0, t1}) {
        double y = glm::dot(oa + t * ray.dir, axis) / len2;
        if (y >= 0.0 && y <= 1.0) consider(t, y, aPerp, disc, false);
      }
    }
  }

  // Spherical caps, each valid only on its own side of the body (a point capsule: its two identical caps are
  // the whole sphere; the second finds nothing closer)
  for (int e = 0; e < 2; ++e) {
    const Vec3& c = e ? pb : pa;
    Vec3 f = o - c;
    double hb = glm::dot(f, ray.dir);
    if (solveQuadraticHalfB(a0, hb, glm::dot(f, f) - radius * radius, t0, t1, disc)) {
      for (double t : {t0, t1}) {
        double y = glm::dot(o + t * ray.dir - pa, axis) / len2;  // NaN for a point capsule
        if (point || (e == 0 && y <= 0.0) || (e == 1 && y >= 1.0)) consider(t, e ? 1.0 : 0.0, a0, disc, true);
      }
    }
  }
  if (!found) return std::nullopt;

  // Error bound of the hit found (computed once per hit, not per test). Backward error of the solves above as a
  // displacement of the surface (position units, first order, pbrt-v4 gamma bounds): the rounding of the
  // re-centred origin o, which is of the order of the coordinates, plus a few ulps (~12 dependent operations,
  // rounded up) of the local magnitudes formed from differences to o (end points, radius, t * d). Only o carries
  // the absolute coordinates' rounding: far from the origin the bound grows with the coordinates' ulp, not with
  // their magnitude times the operation count.
  const double dNorm = norm1(ray.dir);
  const double farError = gammaBound(3) * (norm1(o) + std::abs(tShift) * dNorm);
  const double local = norm1(o - mid) + len + radius;
  double e = farError + gammaBound(16) * (local + std::abs(bestLocal) * dNorm);
  // Factor 2: margin over the first-order bound
  double err =
      2.0 * quadraticRootError(bestA, bestDisc, radius, e) + gammaBound(2) * (std::abs(bestLocal) + std::abs(tShift));
  // A body hit within its error of an end lies on the seam where the next capsule's cap meets this body
  bool boundary = bestCap || std::min(bestU, 1.0 - bestU) * len <= e + err * std::sqrt(a0);
  return PrimHit{best, bestU, 0.0, err, boundary};
}

Vec3 triangleHitError(const Vec3& p0, const Vec3& p1, const Vec3& p2, double b0, double b1, double b2) {
  return gammaBound(7) * (glm::abs(b0 * p0) + glm::abs(b1 * p1) + glm::abs(b2 * p2));
}

}  // namespace whitted
