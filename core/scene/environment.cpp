#include "scene/scene.h"

#include <algorithm>

namespace whitted {

namespace {

// Direction -> (face, s, t) of an OpenGL cube map (the GL specification's major-axis table)
void cubeMapLookup(const Vec3& r, int& face, double& s, double& t) {
  const double ax = std::abs(r.x), ay = std::abs(r.y), az = std::abs(r.z);
  double sc, tc, ma;
  if (ax >= ay && ax >= az) {
    face = r.x >= 0.0 ? 0 : 1;
    sc = r.x >= 0.0 ? -r.z : r.z;
    tc = -r.y;
    ma = ax;
  } else if (ay >= az) {
    face = r.y >= 0.0 ? 2 : 3;
    sc = r.x;
    tc = r.y >= 0.0 ? r.z : -r.z;
    ma = ay;
  } else {
    face = r.z >= 0.0 ? 4 : 5;
    sc = r.z >= 0.0 ? r.x : -r.x;
    tc = -r.y;
    ma = az;
  }
  s = 0.5 * (sc / ma + 1.0);
  t = 0.5 * (tc / ma + 1.0);
}

}  // namespace

Color Scene::environment(const Vec3& dir, const Vec3& up) const {
  const Vec3 d = glm::normalize(dir);
  const EnvironmentMap& e = environmentMap;
  auto face = [&](int i) -> const Texture* {
    const int32_t id = e.faces[i];
    return id >= 0 && std::size_t(id) < textures_.size() && textures_[id].width > 0 ? &textures_[id] : nullptr;
  };
  if (std::isfinite(d.x) && std::isfinite(d.y) && std::isfinite(d.z)) {
    switch (e.projection) {
      case EnvironmentMap::Projection::Sphere:
        if (const Texture* t = face(0)) {
          const double x = glm::dot(d, e.right), y = glm::dot(d, e.up), z = glm::dot(d, e.front);
          const double u = 0.5 * std::atan2(x, z) / kPi + 0.5;
          const double v = std::atan2(y, std::hypot(x, z)) / kPi + 0.5;
          return Color(t->sample(float(u), float(std::clamp(v, 0.0, 1.0))));
        }
        break;
      case EnvironmentMap::Projection::Cube: {
        int f = 0;
        double s = 0.0, t = 0.0;
        cubeMapLookup(Vec3(glm::dot(d, e.right), glm::dot(d, e.up), -glm::dot(d, e.front)), f, s, t);
        if (const Texture* tex = face(f)) return Color(tex->sample(float(s), float(t)));
        break;
      }
      case EnvironmentMap::Projection::Screen:
        if (const Texture* t = face(0)) {
          // The backdrop where the direction projects on screen; a direction behind the camera is mirrored
          // through the image plane, and a parallel camera (which projects no direction) uses the direction's
          // components along the screen axes. Clamped to the image's edges.
          const Vec3 f = e.viewDirection, r = glm::normalize(glm::cross(f, e.viewUp));
          Vec3 dd = glm::dot(d, f) < 0.0 ? d - 2.0 * glm::dot(d, f) * f : d;
          glm::dvec4 clip = e.worldToClip * glm::dvec4(dd, 0.0);
          double x, y;
          if (clip.w > 1e-12) {
            x = clip.x / clip.w;
            y = clip.y / clip.w;
          } else {
            x = glm::dot(dd, r);
            y = glm::dot(dd, e.viewUp);
          }
          return Color(t->sample(float(std::clamp(0.5 * x + 0.5, 0.0, 1.0)),
                                 float(std::clamp(0.5 * y + 0.5, 0.0, 1.0))));
        }
        break;
      case EnvironmentMap::Projection::None:
        break;
    }
  }
  if (!gradientBackground) return background;
  float s = float(0.5 * (1.0 + glm::dot(d, up)));
  return glm::mix(background, background2, std::clamp(std::isfinite(s) ? s : 0.5f, 0.0f, 1.0f));
}

}  // namespace whitted
