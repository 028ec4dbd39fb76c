#include "util/math.h"

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

}  // namespace whitted
