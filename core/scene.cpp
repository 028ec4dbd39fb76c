#include "scene.h"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <type_traits>

namespace whitted {

namespace {

double radiusAt(const std::vector<double>& radii, std::size_t i) {
  if (radii.empty()) return 0.0;
  return radii.size() == 1 ? radii[0] : (i < radii.size() ? radii[i] : 0.0);
}

bool isIdentity(const Mat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (m[c][r] != (c == r ? 1.0 : 0.0)) return false;
  return true;
}

/// Error bound of an affine transform applied to a point p with error e (pbrt-v4 Transform::operator()).
Vec3 transformError(const Mat4& m, const Vec3& p, const Vec3& e) {
  Vec3 out(0.0);
  for (int r = 0; r < 3; ++r) {
    double absMp = std::abs(m[3][r]), absMe = 0.0;
    for (int c = 0; c < 3; ++c) {
      absMp += std::abs(m[c][r] * p[c]);
      absMe += std::abs(m[c][r]) * e[c];
    }
    out[r] = (1.0 + gammaBound(3)) * absMe + gammaBound(3) * absMp;
  }
  return out;
}

/// Surface crossings of one instance already counted by a shadow ray, to recognise the same crossing reported again
/// by a neighbouring primitive (a shared edge or vertex, a tube joint). Fixed size, no allocation: boundary hits
/// are rare (only exact edge/vertex hits of triangles, caps and seams of capsules), and past kSize the oldest
/// entries are overwritten (a later duplicate of an overwritten crossing is then counted again).
class CountedCrossings {
 public:
  /// True if a crossing at t (rounding error tError) was counted already; otherwise records it and returns false.
  bool seenOrAdd(double t, double tError) {
    for (uint32_t i = 0, n = std::min(n_, kSize); i < n; ++i)
      if (std::abs(t - t_[i]) <= tError + error_[i]) return true;
    t_[n_ & (kSize - 1)] = t;
    error_[n_ & (kSize - 1)] = tError;
    ++n_;
    return false;
  }
  void clear() { n_ = 0; }

 private:
  static constexpr uint32_t kSize = 16;  // a power of two
  double t_[kSize];
  double error_[kSize];
  uint32_t n_ = 0;
};

/// Same size and same bytes (NaN compares equal to itself, -0 differs from 0: conservative for "unchanged").
template <typename T>
bool sameBits(const std::vector<T>& a, const std::vector<T>& b) {
  static_assert(std::is_trivially_copyable_v<T>);
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

Vec3 safeNormalize(const Vec3& v, const Vec3& fallback) {
  double l = glm::length(v);
  return (l > 0.0 && std::isfinite(l)) ? v / l : fallback;
}

}  // namespace

// Objects ---------------------------------------------------------------------------------------------------

uint32_t Scene::addMesh(TriangleMesh mesh) {
  objects_.emplace_back();
  setMesh(uint32_t(objects_.size() - 1), std::move(mesh));
  return uint32_t(objects_.size() - 1);
}
uint32_t Scene::addSpheres(SphereSet s) {
  objects_.emplace_back();
  setSpheres(uint32_t(objects_.size() - 1), std::move(s));
  return uint32_t(objects_.size() - 1);
}
uint32_t Scene::addCapsules(CapsuleSet c) {
  objects_.emplace_back();
  setCapsules(uint32_t(objects_.size() - 1), std::move(c));
  return uint32_t(objects_.size() - 1);
}

void Scene::setMesh(uint32_t id, TriangleMesh mesh) {
  Object& o = objects_[id];
  o = Object{};
  o.type = GeometryType::Triangles;
  o.mesh = std::move(mesh);
  topDirty_ = true;
}
void Scene::setSpheres(uint32_t id, SphereSet s) {
  Object& o = objects_[id];
  o = Object{};
  o.type = GeometryType::Spheres;
  o.spheres = std::move(s);
  topDirty_ = true;
}
void Scene::setCapsules(uint32_t id, CapsuleSet c) {
  Object& o = objects_[id];
  o = Object{};
  o.type = GeometryType::Capsules;
  o.capsules = std::move(c);
  topDirty_ = true;
}
bool Scene::updateMesh(uint32_t id, TriangleMesh mesh) {
  Object& o = objects_[id];
  if (!o.alive || o.dirty || o.type != GeometryType::Triangles || !sameBits(o.mesh.positions, mesh.positions) ||
      !sameBits(o.mesh.triangles, mesh.triangles)) {
    setMesh(id, std::move(mesh));
    return true;
  }
  o.mesh = std::move(mesh);  // the BVH, leaf order (leafTris) and bounds stay valid
  sanitizeColors(o);
  return false;
}
bool Scene::updateSpheres(uint32_t id, SphereSet s) {
  Object& o = objects_[id];
  if (!o.alive || o.dirty || o.type != GeometryType::Spheres || !sameBits(o.spheres.centers, s.centers) ||
      !sameBits(o.spheres.radii, s.radii)) {
    setSpheres(id, std::move(s));
    return true;
  }
  o.spheres = std::move(s);
  sanitizeColors(o);
  return false;
}
bool Scene::updateCapsules(uint32_t id, CapsuleSet c) {
  Object& o = objects_[id];
  if (!o.alive || o.dirty || o.type != GeometryType::Capsules || !sameBits(o.capsules.p0, c.p0) ||
      !sameBits(o.capsules.p1, c.p1) || !sameBits(o.capsules.radii, c.radii)) {
    setCapsules(id, std::move(c));
    return true;
  }
  o.capsules = std::move(c);
  sanitizeColors(o);
  return false;
}
void Scene::removeObject(uint32_t id) {
  objects_[id] = Object{};
  objects_[id].alive = false;
  objects_[id].dirty = false;
  topDirty_ = true;
}

void Scene::sanitizeColors(Object& o) {
  // Colours outside [0,1] or non-finite are clamped (alpha NaN -> 1) so no NaN can reach shading
  auto fixColors = [](std::vector<Color4>& cs) {
    for (Color4& c : cs)
      for (int k = 0; k < 4; ++k) c[k] = std::isfinite(c[k]) ? std::clamp(c[k], 0.0f, 1.0f) : (k == 3 ? 1.0f : 0.0f);
  };
  fixColors(o.mesh.vertexColors);
  fixColors(o.mesh.triangleColors);
  fixColors(o.spheres.colors);
  fixColors(o.capsules.colors0);
  fixColors(o.capsules.colors1);
}

void Scene::rebuildObject(Object& o, CommitStats& st) {
  std::vector<Bounds3> boxes;
  std::vector<Vec3> centroids;
  std::vector<uint32_t> valid;
  o.bounds = Bounds3();
  auto add = [&](uint32_t i, const Bounds3& b) {
    boxes.push_back(b);
    centroids.push_back(b.center());
    valid.push_back(i);
    o.bounds.extend(b);
  };

  sanitizeColors(o);

  // Boxes of valid primitives; non-finite and degenerate ones are left out of the BVH
  if (o.type == GeometryType::Triangles) {
    const auto& m = o.mesh;
    boxes.reserve(m.triangles.size());
    centroids.reserve(m.triangles.size());
    valid.reserve(m.triangles.size());
    for (uint32_t i = 0; i < m.triangles.size(); ++i) {
      const glm::uvec3& t = m.triangles[i];
      if (t.x >= m.positions.size() || t.y >= m.positions.size() || t.z >= m.positions.size()) continue;
      const Vec3 &a = m.positions[t.x], &b = m.positions[t.y], &c = m.positions[t.z];
      if (!isFinite(a) || !isFinite(b) || !isFinite(c)) continue;
      Vec3 n = glm::cross(b - a, c - a);
      if (!(glm::dot(n, n) > 0.0) || !isFinite(n)) continue;
      Bounds3 bb;
      bb.extend(a);
      bb.extend(b);
      bb.extend(c);
      add(i, bb);
    }
    st.invalidPrimitives += m.triangles.size() - valid.size();
  } else if (o.type == GeometryType::Spheres) {
    const auto& s = o.spheres;
    for (uint32_t i = 0; i < s.centers.size(); ++i) {
      double r = radiusAt(s.radii, i);
      if (!isFinite(s.centers[i]) || !(r > 0.0) || !std::isfinite(r)) continue;
      add(i, Bounds3{s.centers[i] - Vec3(r), s.centers[i] + Vec3(r)});
    }
    st.invalidPrimitives += s.centers.size() - valid.size();
  } else {
    const auto& c = o.capsules;
    std::size_t n = std::min(c.p0.size(), c.p1.size());
    for (uint32_t i = 0; i < n; ++i) {
      double r = radiusAt(c.radii, i);
      if (!isFinite(c.p0[i]) || !isFinite(c.p1[i]) || !(r > 0.0) || !std::isfinite(r)) continue;
      Bounds3 bb{glm::min(c.p0[i], c.p1[i]) - Vec3(r), glm::max(c.p0[i], c.p1[i]) + Vec3(r)};
      add(i, bb);
    }
    st.invalidPrimitives += std::max(c.p0.size(), c.p1.size()) - valid.size();
  }

  o.bvh.build(boxes, centroids);
  o.leafPrims.resize(valid.size());
  for (std::size_t i = 0; i < valid.size(); ++i) o.leafPrims[i] = valid[o.bvh.primIndices()[i]];
  o.leafTris.clear();
  if (o.type == GeometryType::Triangles) {
    o.leafTris.resize(valid.size());
    for (std::size_t i = 0; i < valid.size(); ++i) o.leafTris[i] = o.mesh.triangles[o.leafPrims[i]];
  }
  o.dirty = false;
  ++st.objectsRebuilt;
}

// Instances -------------------------------------------------------------------------------------------------

uint32_t Scene::addInstance(uint32_t object, const Mat4& toWorld, uint32_t material) {
  instances_.emplace_back();
  uint32_t id = uint32_t(instances_.size() - 1);
  instances_[id].object = object;
  instances_[id].material = material;
  setInstanceTransform(id, toWorld);
  return id;
}

void Scene::setInstanceTransform(uint32_t id, const Mat4& toWorld) {
  Instance& in = instances_[id];
  in.toWorld = toWorld;
  in.identity = isIdentity(toWorld);
  in.toObject = in.identity ? Mat4(1.0) : glm::inverse(toWorld);
  in.normalToWorld = glm::transpose(Mat3(in.toObject));
  topDirty_ = true;
}
void Scene::setInstanceMaterial(uint32_t id, uint32_t material) {
  instances_[id].material = material;
}
void Scene::setInstanceVisible(uint32_t id, bool visible) {
  if (instances_[id].visible != visible) topDirty_ = true;
  instances_[id].visible = visible;
}
void Scene::setInstanceObject(uint32_t id, uint32_t object) {
  instances_[id].object = object;
  topDirty_ = true;
}
void Scene::clearInstances() {
  instances_.clear();
  topDirty_ = true;
}

uint32_t Scene::addMaterial(const Material& m) {
  materials_.push_back(m);
  return uint32_t(materials_.size() - 1);
}
uint32_t Scene::addTexture(Texture t) {
  if (!freeTextures_.empty()) {
    uint32_t id = freeTextures_.back();
    freeTextures_.pop_back();
    textures_[id] = std::move(t);
    return id;
  }
  textures_.push_back(std::move(t));
  return uint32_t(textures_.size() - 1);
}
void Scene::setTexture(uint32_t id, Texture t) {
  textures_[id] = std::move(t);
}
void Scene::removeTexture(uint32_t id) {
  textures_[id] = Texture{};  // releases the texels
  freeTextures_.push_back(id);
}

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

template <typename Fn>
void Scene::forEachVisibleInstance(Fn&& fn) const {
  for (uint32_t i = 0; i < instances_.size(); ++i) {
    const Instance& in = instances_[i];
    if (!in.visible || in.object >= objects_.size() || !objects_[in.object].alive || objects_[in.object].bvh.empty() ||
        in.material >= materials_.size())
      continue;
    fn(i, in);
  }
}

// Commit ----------------------------------------------------------------------------------------------------

CommitStats Scene::commit() {
  CommitStats st;
  auto start = std::chrono::steady_clock::now();
  for (Object& o : objects_)
    if (o.alive && o.dirty) {
      rebuildObject(o, st);
      topDirty_ = true;
    }

  if (topDirty_) {
    std::vector<Bounds3> boxes;
    std::vector<Vec3> centroids;
    std::vector<uint32_t> ids;
    forEachVisibleInstance([&](uint32_t i, const Instance& in) {
      const Object& o = objects_[in.object];
      Bounds3 b = in.identity ? o.bounds : transformBounds(in.toWorld, o.bounds);
      if (!b.valid() || !isFinite(b.lo) || !isFinite(b.hi)) return;
      boxes.push_back(b);
      centroids.push_back(b.center());
      ids.push_back(i);
    });
    BvhBuildOptions opt;
    opt.maxLeafSize = 2;
    top_.build(boxes, centroids, opt);
    topInstances_.resize(ids.size());
    bounds_ = Bounds3();
    for (std::size_t i = 0; i < ids.size(); ++i) {
      topInstances_[i] = ids[top_.primIndices()[i]];
      bounds_.extend(boxes[i]);
    }
    topDirty_ = false;
    st.topLevelRebuilt = true;
  }
  st.secondsBuild = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  // Sanitise what shading reads, so no input can produce a NaN pixel (cheap: once per material and light)
  for (Material& m : materials_) st.invalidMaterials += sanitizeMaterial(m) != 0;
  auto fixColor = [](Color& c) {
    bool bad = false;
    for (int k = 0; k < 3; ++k)
      if (!std::isfinite(c[k]) || c[k] < 0.0f || c[k] > 1e6f) {
        c[k] = std::isfinite(c[k]) ? std::clamp(c[k], 0.0f, 1e6f) : 0.0f;
        bad = true;
      }
    return bad;
  };
  fixColor(background);
  fixColor(background2);
  if (!std::isfinite(backgroundAlpha)) backgroundAlpha = 1.0f;
  backgroundAlpha = std::clamp(backgroundAlpha, 0.0f, 1.0f);
  for (Light& l : lights_) {
    bool bad = fixColor(l.color);
    if (!std::isfinite(l.intensity) || l.intensity < 0.0f || l.intensity > 1e6f) {
      l.intensity = std::isfinite(l.intensity) ? std::clamp(l.intensity, 0.0f, 1e6f) : 0.0f;
      bad = true;
    }
    if (!isFinite(l.position) || !isFinite(l.focalPoint) || !isFinite(l.attenuation) || !std::isfinite(l.coneAngle) ||
        !std::isfinite(l.exponent)) {
      l.intensity = 0.0f;  // cannot be placed: switched off
      bad = true;
    }
    if (l.attenuation.x < 0.0 || l.attenuation.y < 0.0 || l.attenuation.z < 0.0) {
      l.attenuation = glm::max(l.attenuation, Vec3(0.0));
      bad = true;
    }
    // vtkLight's own range (SetExponent clamps to [0, 128]): a negative spot exponent would make the cone factor
    // infinite (pow(cos, -e))
    if (l.exponent < 0.0 || l.exponent > 128.0) {
      l.exponent = std::clamp(l.exponent, 0.0, 128.0);
      bad = true;
    }
    st.invalidLights += bad;
  }

  // Features and radiance bounds (cheap: once per instance and light)
  features_ = Features{};
  float lightSum = 0.0f;
  for (const Light& l : lights_) {
    float li = std::max(0.0f, l.intensity) * maxComponent(glm::max(l.color, Color(0.0f)));
    lightSum += li;
    if (l.castShadows && li > 0.0f) features_.shadowLights = true;
  }
  float bound = std::max(maxComponent(background), gradientBackground ? maxComponent(background2) : 0.0f);
  if (environmentMap.projection != EnvironmentMap::Projection::None) bound = std::max(bound, 1.0f);  // texels <= 1
  maxSecondary_ = 0.0f;
  for (uint32_t slot : topInstances_) {
    const Instance& in = instances_[slot];
    const Material& m = materials_[in.material];
    const Object& o = objects_[in.object];
    if (maxComponent(m.reflectance) > 0.0f) features_.reflective = true;
    if (maxComponent(m.transmittance) > 0.0f) features_.transmissive = true;
    if (o.type == GeometryType::Spheres) features_.spheres = true;
    if (o.type == GeometryType::Capsules) features_.capsules = true;
    if (!in.identity) features_.transforms = true;
    if (m.texture >= 0 && size_t(m.texture) < textures_.size() && o.type == GeometryType::Triangles &&
        !o.mesh.texcoords.empty())
      features_.textures = true;
    float colorMax = 1.0f;  // geometry colours and texels are in [0,1]
    float amb = m.ambient * std::max(colorMax, maxComponent(m.ambientColor));
    float dif = m.diffuse * std::max(colorMax, maxComponent(m.diffuseColor));
    float spe = m.specular * maxComponent(m.specularColor);
    float local = m.lighting ? amb + lightSum * (dif + spe) : amb + dif;
    bound = std::max(bound, local);
    maxSecondary_ = std::max(maxSecondary_, maxComponent(m.reflectance + m.transmittance));
  }
  localBound_ = bound;
  return st;
}

SceneStats Scene::stats() const {
  SceneStats s;
  s.instances = instances_.size();
  for (const Object& o : objects_) {
    if (!o.alive) continue;
    ++s.objects;
    s.triangles += o.type == GeometryType::Triangles ? o.leafTris.size() : 0;
    s.spheres += o.type == GeometryType::Spheres ? o.leafPrims.size() : 0;
    s.capsules += o.type == GeometryType::Capsules ? o.leafPrims.size() : 0;
    s.bvhNodes += o.bvh.nodes().size();
    s.bvhBytes += o.bvh.memoryBytes() + o.leafPrims.capacity() * sizeof(uint32_t);
    s.geometryBytes += o.mesh.colorCoords.capacity() * sizeof(float) + o.mesh.positions.capacity() * sizeof(Vec3) +
                       o.mesh.triangles.capacity() * sizeof(glm::uvec3) + o.leafTris.capacity() * sizeof(glm::uvec3) +
                       o.mesh.normals.capacity() * sizeof(Vec3f) + o.mesh.vertexColors.capacity() * sizeof(Color4) +
                       o.mesh.triangleColors.capacity() * sizeof(Color4) + o.mesh.texcoords.capacity() * sizeof(Vec2f) +
                       o.spheres.centers.capacity() * sizeof(Vec3) + o.capsules.p0.capacity() * 2 * sizeof(Vec3);
  }
  s.bvhNodes += top_.nodes().size();
  s.bvhBytes += top_.memoryBytes();
  for (const Texture& t : textures_) {
    s.textures += !t.rgba.empty();
    s.textureBytes += t.rgba.capacity();
  }
  return s;
}

// Queries ---------------------------------------------------------------------------------------------------

std::optional<PrimHit> Scene::intersectLeafSlot(const Object& o, uint32_t slot, const Ray& r, const TriangleRay& tr) {
  // One dispatch per primitive test, shared by closest-hit and shadow queries (the switch is on a per-object
  // constant, so it predicts perfectly)
  switch (o.type) {
    case GeometryType::Triangles: {
      const glm::uvec3& t = o.leafTris[slot];
      return intersectTriangle(r, tr, o.mesh.positions[t.x], o.mesh.positions[t.y], o.mesh.positions[t.z]);
    }
    case GeometryType::Spheres: {
      uint32_t p = o.leafPrims[slot];
      return intersectSphere(r, o.spheres.centers[p], radiusAt(o.spheres.radii, p));
    }
    case GeometryType::Capsules: {
      uint32_t p = o.leafPrims[slot];
      return intersectCapsule(r, o.capsules.p0[p], o.capsules.p1[p], radiusAt(o.capsules.radii, p));
    }
  }
  return std::nullopt;
}

bool Scene::intersectObject(const Object& o, uint32_t instance, const Ray& ray, double& tMax, Hit& hit,
                            uint64_t* nodes) const {
  // Hits within kTieRelative * t of the best one count as the same distance: the lower (instance, primitive) wins,
  // as the first-drawn surface wins OpenGL's depth test, so coplanar overlapping surfaces never speckle.
  // Performance note: the traversal bound is widened by the same tolerance so tying candidates are not culled.
  constexpr double kTieRelative = 1e-10;
  const double tLimit = ray.tMax;
  return o.bvh.traverse<false>(
      ray, tMax,
      [&, tr = TriangleRay(ray)](uint32_t first, uint32_t count, double& tm) {
        Ray r = ray;
        bool found = false;
        for (uint32_t s = first; s < first + count; ++s) {
          r.tMax = tm;
          std::optional<PrimHit> h;
          h = intersectLeafSlot(o, s, r, tr);
          if (h) {
            uint32_t prim = o.leafPrims[s];
            double tie = kTieRelative * std::abs(hit.t);
            bool better = !(h->t >= hit.t - tie);  // clearly closer (or the first hit)
            if (!better && h->t <= hit.t + tie)
              better = instance < hit.instance || (instance == hit.instance && prim < hit.prim);
            if (better) {
              hit.t = h->t;
              hit.instance = instance;
              hit.prim = prim;
              hit.u = h->u;
              hit.v = h->v;
              tm = std::min(tLimit, hit.t + kTieRelative * std::abs(hit.t));
              found = true;
            }
          }
        }
        return found;
      },
      nodes);
}

bool Scene::intersect(const Ray& ray, Hit& hit, uint64_t* nodes) const {
  hit = Hit{};
  double tMax = ray.tMax;
  auto instancesInLeaf = [&](uint32_t first, uint32_t count, double& tm) {
        bool any = false;
        for (uint32_t s = first; s < first + count; ++s) {
          uint32_t id = topInstances_[s];
          const Instance& in = instances_[id];
          Ray r = ray;
          if (!in.identity) {
            r.origin = transformPoint(in.toObject, ray.origin);
            r.dir = transformVector(in.toObject, ray.dir);
          }
          r.tMax = tm;
          if (intersectObject(objects_[in.object], id, r, tm, hit, nodes)) any = true;
        }
        return any;
  };
  // A single instance needs no top level (its object's root node tests the same box)
  if (topInstances_.size() == 1) return instancesInLeaf(0, 1, tMax);
  return top_.traverse<false>(ray, tMax, instancesInLeaf, nodes);
}

Color Scene::transmittance(const Ray& ray, float cutoff, uint64_t* nodes) const {
  Color atten(1.0f);
  CountedCrossings counted;
  double tMax = ray.tMax;
  auto instancesInLeaf = [&](uint32_t first, uint32_t count, double&) {
        for (uint32_t s = first; s < first + count; ++s) {
          const Instance& in = instances_[topInstances_[s]];
          const Object& o = objects_[in.object];
          const Color kt = materials_[in.material].transmittance;
          const bool opaque = maxComponent(kt) <= 0.0f;
          Ray r = ray;
          if (!in.identity) {
            r.origin = transformPoint(in.toObject, ray.origin);
            r.dir = transformVector(in.toObject, ray.dir);
          }
          double tm = r.tMax;
          const TriangleRay tr(r);
          counted.clear();  // crossings are shared only between primitives of one object
          bool stop = o.bvh.traverse<true>(
              r, tm,
              [&](uint32_t f, uint32_t c, double&) {
                for (uint32_t k = f; k < f + c; ++k) {
                  // Every crossing of a transmissive surface multiplies by kt once; an opaque one blocks. A hit on a
                  // primitive boundary that coincides (within both rounding bounds) with a boundary hit counted
                  // already is the same crossing seen by a neighbour (shared edge or vertex, tube joint): skipped.
                  Ray rr = r;
                  for (int guard = 0; guard < 4; ++guard) {
                    std::optional<PrimHit> h;
                    h = intersectLeafSlot(o, k, rr, tr);
                    if (!h) break;
                    if (opaque) return true;
                    if (!h->boundary || !counted.seenOrAdd(h->t, h->tError)) {
                      atten *= kt;
                      if (maxComponent(atten) < cutoff) return true;
                    }
                    if (o.type == GeometryType::Triangles) break;  // a triangle is crossed once
                    rr.tMin = h->t;
                  }
                }
                return false;
              },
              nodes);
          if (stop) return true;
        }
        return false;
  };
  const bool blocked = topInstances_.size() == 1 ? instancesInLeaf(0, 1, tMax)
                                                 : top_.traverse<true>(ray, tMax, instancesInLeaf, nodes);
  return blocked ? Color(0.0f) : atten;
}

SurfacePoint Scene::surface(const Ray& ray, const Hit& hit) const {
  const Instance& in = instances_[hit.instance];
  const Object& o = objects_[in.object];
  SurfacePoint sp;
  sp.material = in.material;
  Vec3 p, err, ng, ns;
  Ray r = ray;
  if (!in.identity) {
    r.origin = transformPoint(in.toObject, ray.origin);
    r.dir = transformVector(in.toObject, ray.dir);
  }

  switch (o.type) {
    case GeometryType::Triangles: {
      const TriangleMesh& m = o.mesh;
      const glm::uvec3& t = m.triangles[hit.prim];
      double b1 = hit.u, b2 = hit.v, b0 = 1.0 - b1 - b2;
      const Vec3 &p0 = m.positions[t.x], &p1 = m.positions[t.y], &p2 = m.positions[t.z];
      // Hit point from barycentrics (more accurate than o + t d) and its error bound
      p = b0 * p0 + b1 * p1 + b2 * p2;
      err = triangleHitError(p0, p1, p2, b0, b1, b2);
      ng = safeNormalize(glm::cross(p1 - p0, p2 - p0), Vec3(0, 0, 1));
      ns = ng;
      if (!m.normals.empty() && m.normals.size() == m.positions.size()) {
        Vec3 n = b0 * Vec3(m.normals[t.x]) + b1 * Vec3(m.normals[t.y]) + b2 * Vec3(m.normals[t.z]);
        ns = safeNormalize(n, ng);
      }
      if (m.colorMap >= 0 && size_t(m.colorMap) < textures_.size() && m.colorCoords.size() == m.positions.size()) {
        float c = float(b0) * m.colorCoords[t.x] + float(b1) * m.colorCoords[t.y] + float(b2) * m.colorCoords[t.z];
        const Texture& lut = textures_[size_t(m.colorMap)];
        int w = std::max(1, lut.width);
        int i = std::isfinite(c) ? std::clamp(int(std::floor(c * float(w))), 0, w - 1) : 0;
        sp.color = lut.sample((float(i) + 0.5f) / float(w), 0.5f / float(std::max(1, lut.height)));
        sp.hasColor = true;
      } else if (!m.triangleColors.empty() && hit.prim < m.triangleColors.size()) {
        sp.color = m.triangleColors[hit.prim];
        sp.hasColor = true;
      } else if (!m.vertexColors.empty() && m.vertexColors.size() == m.positions.size()) {
        sp.color = float(b0) * m.vertexColors[t.x] + float(b1) * m.vertexColors[t.y] + float(b2) * m.vertexColors[t.z];
        sp.hasColor = true;
      }
      if (!m.texcoords.empty() && m.texcoords.size() == m.positions.size()) {
        sp.uv = float(b0) * m.texcoords[t.x] + float(b1) * m.texcoords[t.y] + float(b2) * m.texcoords[t.z];
        sp.hasUV = true;
      }
      break;
    }
    case GeometryType::Spheres: {
      const SphereSet& s = o.spheres;
      const Vec3& c = s.centers[hit.prim];
      double rad = radiusAt(s.radii, hit.prim);
      Vec3 q = r.origin + hit.t * r.dir;
      // Re-project onto the surface; the remaining error is a few ulps of |p| (pbrt-v4, sphere)
      ng = safeNormalize(q - c, Vec3(0, 0, 1));
      p = c + rad * ng;
      err = gammaBound(5) * (glm::abs(p) + glm::abs(c));
      ns = ng;
      if (!s.colors.empty()) {
        sp.color = s.colors[std::min<std::size_t>(hit.prim, s.colors.size() - 1)];
        sp.hasColor = true;
      }
      break;
    }
    case GeometryType::Capsules: {
      const CapsuleSet& cs = o.capsules;
      const Vec3 &a = cs.p0[hit.prim], &b = cs.p1[hit.prim];
      double rad = radiusAt(cs.radii, hit.prim);
      Vec3 q = r.origin + hit.t * r.dir;
      Vec3 ab = b - a;
      double len2 = glm::dot(ab, ab);
      double u = len2 > 0.0 ? std::clamp(glm::dot(q - a, ab) / len2, 0.0, 1.0) : 0.0;
      Vec3 axisPoint = a + u * ab;
      ng = safeNormalize(q - axisPoint, Vec3(0, 0, 1));
      p = axisPoint + rad * ng;
      err = gammaBound(7) * (glm::abs(p) + glm::abs(a) + glm::abs(b));
      ns = ng;
      if (!cs.colors0.empty()) {
        std::size_t i = std::min<std::size_t>(hit.prim, cs.colors0.size() - 1);
        Color4 c1 = cs.colors1.size() > i ? cs.colors1[i] : cs.colors0[i];
        sp.color = glm::mix(cs.colors0[i], c1, float(u));
        sp.hasColor = true;
      }
      break;
    }
  }

  // Object -> world
  if (!in.identity) {
    err = transformError(in.toWorld, p, err);
    p = transformPoint(in.toWorld, p);
    ng = safeNormalize(in.normalToWorld * ng, Vec3(0, 0, 1));
    ns = safeNormalize(in.normalToWorld * ns, ng);
  }
  sp.p = p;
  sp.pError = err;
  sp.ng = ng;
  sp.ns = ns;
  return sp;
}

}  // namespace whitted
