#include "geometry/shape_tubes.h"

#include <algorithm>
#include <utility>

namespace whitted {

namespace {

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

std::optional<PrimHit> intersectTube(const Ray& ray, const Vec3& pa, const Vec3& pb, double radius) {
  if (!(radius > 0.0)) return std::nullopt;
  double a0 = glm::dot(ray.dir, ray.dir);
  if (!(a0 > 0.0)) return std::nullopt;
  Vec3 axis = pb - pa;
  double len2 = glm::dot(axis, axis);
  const double len = std::sqrt(len2);
  const bool point = len2 == 0.0;  // a zero-length tube is a sphere: its one cap, u = 0

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
    // Cylinder body: solve |perp(o - a) + t perp(d)|^2 = r^2, from the ray's closest approach to the axis line
    // within the segment's slab (0 <= y <= 1): from the midpoint's, a ray crossing a long thin tube near an end
    // passes far from the axis there, and |perp(o - a)|^2 carries more rounding than r^2 (a tube of radius 1e-6
    // and length 1.4e3 gave hits 8 radii off its surface near its ends)
    Vec3 n = axis / len;
    Vec3 dPerp = ray.dir - glm::dot(ray.dir, n) * n;
    double aPerp = glm::dot(dPerp, dPerp);
    double tAxis = 0.0;  // from o to the re-centred origin
    Vec3 oa = o - pa;
    Vec3 oPerp = oa - glm::dot(oa, n) * n;
    if (glm::dot(oPerp, oPerp) > 16.0 * radius * radius) {  // within 4 radii the rounding of |perp|^2 is harmless
      if (aPerp > 0.0) tAxis = -glm::dot(oPerp, dPerp) / aPerp;
      const double dn = glm::dot(ray.dir, n), on = glm::dot(oa, n);
      if (dn != 0.0) {  // keep the ray's point inside the slab, where the roots that count lie
        const double ty0 = -on / dn, ty1 = (len - on) / dn;
        tAxis = std::clamp(tAxis, std::min(ty0, ty1), std::max(ty0, ty1));
      }
      if (!std::isfinite(tAxis)) tAxis = 0.0;
      oa = (o + tAxis * ray.dir) - pa;
      oPerp = oa - glm::dot(oa, n) * n;
    }
    if (solveQuadraticHalfB(aPerp, glm::dot(oPerp, dPerp), glm::dot(oPerp, oPerp) - radius * radius, t0, t1, disc)) {
      for (double t : {t0, t1}) {
        double y = glm::dot(oa + t * ray.dir, axis) / len2;
        if (y >= 0.0 && y <= 1.0) consider(t + tAxis, y, aPerp, disc, false);
      }
    }
  }

  // Spherical caps, each valid only on its own side of the body (a point tube: its two identical caps are
  // the whole sphere; the second finds nothing closer). Each cap's quadratic is solved from the ray's closest
  // approach to that cap's centre (as for a sphere): from the midpoint's, |f|^2 of a long thin tube is so much
  // larger than r^2 that its rounding alone made phantom roots (a cap of radius 1e-6 at 500 units from the
  // midpoint: |f|^2 ~ 2.5e5 carries ~3e-11 of rounding against r^2 = 1e-12)
  for (int e = 0; e < 2; ++e) {
    const Vec3& c = e ? pb : pa;
    const double capShift = -glm::dot(ray.origin - c, ray.dir) / a0 - tShift;  // from o to c's closest approach
    const Vec3 oc = o + capShift * ray.dir;
    Vec3 f = oc - c;
    double hb = glm::dot(f, ray.dir);
    if (solveQuadraticHalfB(a0, hb, glm::dot(f, f) - radius * radius, t0, t1, disc)) {
      for (double tc : {t0, t1}) {
        const double t = tc + capShift;  // relative to o, as the body's roots
        double y = glm::dot(oc + tc * ray.dir - pa, axis) / len2;  // NaN for a point tube
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
  // A body hit within its error of an end lies on the seam where the next tube's cap meets this body
  bool boundary = bestCap || std::min(bestU, 1.0 - bestU) * len <= e + err * std::sqrt(a0);
  return PrimHit{best, bestU, 0.0, err, boundary};
}

bool TubeShape::bounds(const TubeSet& c, uint32_t i, Bounds3& box) {
  if (i >= c.p0.size() || i >= c.p1.size()) return false;
  double r = radiusAt(c.radii, i);
  if (!isFinite(c.p0[i]) || !isFinite(c.p1[i]) || !(r > 0.0) || !std::isfinite(r)) return false;
  box = Bounds3{glm::min(c.p0[i], c.p1[i]) - Vec3(r), glm::max(c.p0[i], c.p1[i]) + Vec3(r)};
  return true;
}

void TubeShape::surface(const TubeSet& cs, const Hit& hit, const Ray& r, const std::vector<Texture>&,
                           SurfacePoint& sp) {
  const Vec3 &a = cs.p0[hit.prim], &b = cs.p1[hit.prim];
  double rad = radiusAt(cs.radii, hit.prim);
  Vec3 q = r.origin + hit.t * r.dir;
  // Re-project onto the tube: the closest axis point, pushed out by the radius
  Vec3 ab = b - a;
  double len2 = glm::dot(ab, ab);
  double u = len2 > 0.0 ? std::clamp(glm::dot(q - a, ab) / len2, 0.0, 1.0) : 0.0;
  Vec3 axisPoint = a + u * ab;
  sp.ng = safeNormalize(q - axisPoint, Vec3(0, 0, 1));
  sp.p = axisPoint + rad * sp.ng;
  sp.pError = gammaBound(7) * (glm::abs(sp.p) + glm::abs(a) + glm::abs(b));
  sp.ns = sp.ng;
  if (!cs.colors0.empty()) {
    std::size_t i = std::min<std::size_t>(hit.prim, cs.colors0.size() - 1);
    Color4 c1 = cs.colors1.size() > i ? cs.colors1[i] : cs.colors0[i];
    sp.color = glm::mix(cs.colors0[i], c1, float(u));
    sp.hasColor = true;
  }
}

}  // namespace whitted
