// Shared by the integrator's tests (integrator_test.cpp, local_shading_test.cpp): materials, objects and rays.
#pragma once

#include "scene/scene.h"

#include <utility>

namespace whitted::integrator_test {

inline Material unlit(Color c) {
  Material m;
  m.lighting = false;
  m.ambient = 0.0f;
  m.diffuse = 1.0f;
  m.diffuseColor = c;
  return m;
}

inline Material glassMaterial(float ior, Color kt = Color(1.0f), Color kr = Color(0.0f)) {
  Material m;
  m.opacity = 0.0f;  // no local colour: only the transmitted / reflected rays contribute
  m.transmittance = kt;
  m.reflectance = kr;
  m.ior = ior;
  return m;
}

inline uint32_t addObject(Scene& s, TriangleMesh m, const Material& mat, const Mat4& xf = Mat4(1.0)) {
  return s.addInstance(s.addMesh(std::move(m)), xf, s.addMaterial(mat));
}

inline Ray ray(Vec3 o, Vec3 d) {
  Ray r;
  r.origin = o;
  r.dir = glm::normalize(d);
  return r;
}

}  // namespace whitted::integrator_test
