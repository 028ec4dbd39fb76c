#include "camera.h"

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

Ray Camera::rayNdc(double x, double y) const {
  Vec3 pNear = unproject(clipToWorld_, x, y, -1.0);
  Vec3 pFar = unproject(clipToWorld_, x, y, 1.0);
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
  Vec4 c = worldToClip_ * Vec4(world, 1.0);
  return 0.5 * (c.z / c.w) + 0.5;
}

}  // namespace whitted
