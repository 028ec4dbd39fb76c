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

double Camera::glDepth(const Vec3& world) const {
  // Rows z and w of worldToClip_ * (world, 1), summed in glm's order (same bits, half the work)
  const Mat4& m = worldToClip_;
  const double z = (m[0][2] * world.x + m[1][2] * world.y) + (m[2][2] * world.z + m[3][2]);
  const double w = (m[0][3] * world.x + m[1][3] * world.y) + (m[2][3] * world.z + m[3][3]);
  return 0.5 * (z / w) + 0.5;
}

}  // namespace whitted
