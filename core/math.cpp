#include "math.h"

namespace whitted {

Bounds3 transformBounds(const Mat4& m, const Bounds3& b) {
  Bounds3 out;
  if (!b.valid()) return out;
  for (int i = 0; i < 8; ++i) {
    Vec3 c((i & 1) ? b.hi.x : b.lo.x, (i & 2) ? b.hi.y : b.lo.y, (i & 4) ? b.hi.z : b.lo.z);
    out.extend(transformPoint(m, c));
  }
  // Account for rounding in the transform itself so the box stays conservative.
  Vec3 pad = gammaBound(3) * glm::max(glm::abs(out.lo), glm::abs(out.hi));
  out.lo -= pad;
  out.hi += pad;
  return out;
}

Vec3 offsetRayOrigin(const Vec3& p, const Vec3& pError, const Vec3& n, const Vec3& w) {
  // Distance along the normal that is guaranteed to clear the error box around p
  double d = glm::dot(glm::abs(n), pError);
  Vec3 offset = d * n;
  if (glm::dot(w, n) < 0.0) offset = -offset;
  Vec3 po = p + offset;
  // Round away from p so the addition's own rounding cannot bring the origin back inside the box
  for (int i = 0; i < 3; ++i) {
    if (offset[i] > 0.0)
      po[i] = std::nextafter(po[i], kInfinity);
    else if (offset[i] < 0.0)
      po[i] = std::nextafter(po[i], -kInfinity);
  }
  return po;
}

}  // namespace whitted
