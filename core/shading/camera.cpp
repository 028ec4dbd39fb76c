#include "shading/camera.h"

#include <glm/gtc/matrix_transform.hpp>

namespace whitted {

namespace {

Vec3 unproject(const Mat4& clipToWorld, double x, double y, double z) {
  Vec4 h = clipToWorld * Vec4(x, y, z, 1.0);
  return Vec3(h) / h.w;
}

}  // namespace

Camera Camera::fromViewProjection(const Mat4& worldToClip) {
  Camera c;
  c.worldToClip_ = worldToClip;
  c.clipToWorld_ = glm::inverse(worldToClip);
  c.nearZW_ = c.clipToWorld_[2] * -1.0 + c.clipToWorld_[3];
  c.farZW_ = c.clipToWorld_[2] * 1.0 + c.clipToWorld_[3];
  Vec3 up = unproject(c.clipToWorld_, 0.0, 1.0, -1.0) - unproject(c.clipToWorld_, 0.0, -1.0, -1.0);
  Vec3 fwd = unproject(c.clipToWorld_, 0.0, 0.0, 1.0) - unproject(c.clipToWorld_, 0.0, 0.0, -1.0);
  if (glm::length(up) > 0.0) c.up_ = glm::normalize(up);
  if (glm::length(fwd) > 0.0) c.viewDir_ = glm::normalize(fwd);
  return c;
}

Camera Camera::perspective(const Vec3& eye, const Vec3& focal, const Vec3& up, double viewAngleDeg, double aspect,
                           double nearDist, double farDist) {
  Mat4 view = glm::lookAt(eye, focal, up);
  Mat4 proj = glm::perspective(glm::radians(viewAngleDeg), aspect, nearDist, farDist);
  return fromViewProjection(proj * view);
}

Camera Camera::parallel(const Vec3& eye, const Vec3& focal, const Vec3& up, double parallelScale, double aspect,
                        double nearDist, double farDist) {
  Mat4 view = glm::lookAt(eye, focal, up);
  Mat4 proj =
      glm::ortho(-parallelScale * aspect, parallelScale * aspect, -parallelScale, parallelScale, nearDist, farDist);
  return fromViewProjection(proj * view);
}

Ray Camera::rayNdc(double x, double y) const { return rayNdcRow(x, rowTerm(y)); }

Ray Camera::rayNdcRow(double x, const Vec4& row) const {
  // unproject() at z = -1 and z = 1, sharing the x and y terms (bit-identical: see nearZW_)
  const Vec4 xy = clipToWorld_[0] * x + row;
  const Vec4 hNear = xy + nearZW_, hFar = xy + farZW_;
  Vec3 pNear = Vec3(hNear) / hNear.w;
  Vec3 pFar = Vec3(hFar) / hFar.w;
  Ray r;
  r.origin = pNear;
  Vec3 d = pFar - pNear;
  double len = glm::length(d);
  r.dir = len > 0.0 ? d / len : viewDir_;
  r.tMin = 0.0;
  r.tMax = len > 0.0 ? len : kInfinity;
  return r;
}

Frustum Camera::pixelBlockFrustum(double x0, double y0, double x1, double y1, int width, int height) const {
  Frustum f;
  const Ray r[4] = {rayPixel(x0, y0, width, height), rayPixel(x1, y0, width, height),
                    rayPixel(x1, y1, width, height), rayPixel(x0, y1, width, height)};
  const Ray centre = rayPixel(0.5 * (x0 + x1), 0.5 * (y0 + y1), width, height);
  const Vec3 inside = centre.origin + centre.dir;
  for (int k = 0; k < 4; ++k) {
    const Ray &a = r[k], &b = r[(k + 1) % 4];
    // The plane through ray a's line and a point of ray b's line (both through the eye, or parallel)
    Vec3 n = glm::cross(a.dir, (b.origin + b.dir) - a.origin);
    const double side = glm::dot(n, inside - a.origin);
    const double scale = glm::length(n) * glm::length(inside - a.origin);
    if (!(std::abs(side) > 1e-9 * scale) || !isFinite(n)) return f;  // degenerate: excludes nothing
    if (side < 0.0) n = -n;
    f.point[k] = a.origin;
    f.normal[k] = n;
  }
  f.valid = true;
  return f;
}

double Camera::glDepth(const Vec3& world) const {
  // Rows z and w of worldToClip_ * (world, 1), summed in glm's order (same bits, half the work)
  const Mat4& m = worldToClip_;
  const double z = (m[0][2] * world.x + m[1][2] * world.y) + (m[2][2] * world.z + m[3][2]);
  const double w = (m[0][3] * world.x + m[1][3] * world.y) + (m[2][3] * world.z + m[3][3]);
  return 0.5 * (z / w) + 0.5;
}

}  // namespace whitted
