#include "scene/scene.h"

#include <algorithm>
#include <chrono>

namespace whitted {

namespace {

bool isIdentity(const Mat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (m[c][r] != (c == r ? 1.0 : 0.0)) return false;
  return true;
}

}  // namespace

Scene::Scene() = default;
Scene::~Scene() {
  upgrade_.drop();  // before any member goes: the build may still read objects_
}
Scene::Scene(Scene&&) noexcept = default;
Scene& Scene::operator=(Scene&&) noexcept = default;

// Objects ---------------------------------------------------------------------------------------------------

uint32_t Scene::addMesh(TriangleMesh mesh) {
  settleUpgrade();
  objects_.emplace_back();
  setMesh(uint32_t(objects_.size() - 1), std::move(mesh));
  return uint32_t(objects_.size() - 1);
}
uint32_t Scene::addSpheres(SphereSet s) {
  settleUpgrade();
  objects_.emplace_back();
  setSpheres(uint32_t(objects_.size() - 1), std::move(s));
  return uint32_t(objects_.size() - 1);
}
uint32_t Scene::addTubes(TubeSet c) {
  settleUpgrade();
  objects_.emplace_back();
  setTubes(uint32_t(objects_.size() - 1), std::move(c));
  return uint32_t(objects_.size() - 1);
}

template <typename G>
void Scene::setGeometry(uint32_t id, G&& g) {
  settleUpgrade();
  Object& o = objects_[id];
  const bool replaced = o.replaced || (o.alive && !o.dirty);  // it had been built
  o = Object{};
  o.geometry = std::forward<G>(g);
  o.replaced = replaced;
  topDirty_ = true;
}
void Scene::setMesh(uint32_t id, TriangleMesh mesh) {
  setGeometry(id, std::move(mesh));
}
void Scene::setSpheres(uint32_t id, SphereSet s) {
  setGeometry(id, std::move(s));
}
void Scene::setTubes(uint32_t id, TubeSet c) {
  setGeometry(id, std::move(c));
}

template <typename G>
bool Scene::updateGeometry(uint32_t id, G&& g) {
  settleUpgrade();
  Object& o = objects_[id];
  if (o.sameGeometry(g)) {
    o.replaceAttributes(std::forward<G>(g));  // the BVH, leaf order and bounds stay valid
    return false;
  }
  if (o.sameTopology(g)) {
    // Moved points on the same connectivity (a deforming mesh's time step): the tree is refit at commit
    o.replaceAttributes(std::forward<G>(g));
    o.refitPending = true;
    topDirty_ = true;
    return true;
  }
  setGeometry(id, std::forward<G>(g));
  return true;
}
bool Scene::updateMesh(uint32_t id, TriangleMesh mesh) {
  return updateGeometry(id, std::move(mesh));
}
bool Scene::updateSpheres(uint32_t id, SphereSet s) {
  return updateGeometry(id, std::move(s));
}
bool Scene::updateTubes(uint32_t id, TubeSet c) {
  return updateGeometry(id, std::move(c));
}
void Scene::removeObject(uint32_t id) {
  settleUpgrade();
  objects_[id] = Object{};
  objects_[id].alive = false;
  objects_[id].dirty = false;
  topDirty_ = true;
}

Object Scene::takeObject(uint32_t id) {
  settleUpgrade();
  Object taken = std::move(objects_[id]);
  removeObject(id);
  objects_[id].replaced = true;  // the id's next geometry is a replacement (fast builder)
  return taken;
}
void Scene::restoreObject(uint32_t id, Object o) {
  settleUpgrade();
  objects_[id] = std::move(o);
  topDirty_ = true;
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
void Scene::setInstanceColor(uint32_t id, const Color4& c) {
  instances_[id].color = sanitizedColor(c);  // shading never sees a NaN
  instances_[id].hasColor = true;
}
void Scene::clearInstanceColor(uint32_t id) {
  instances_[id].hasColor = false;
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
  // A commit that rebuilds or refits nothing never waits for a background build reading the objects
  pressUpgrade(st);
  if (std::any_of(objects_.begin(), objects_.end(), [](const Object& o) { return o.dirty || o.refitPending; }))
    settleUpgrade();
  adoptUpgrades(st);
  buildObjects(st);
  prepareVolumes(st);
  if (topDirty_) {
    buildTopLevel(st);
    addVolumeBounds();
  }
  st.secondsBuild = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  sanitizeInputs(st);
  updateFeatures();
  prepareVolumeLights();
  return st;
}

void Scene::buildObjects(CommitStats& st) {
  for (Object& o : objects_) {
    // Moved points on the same connectivity: refit; a primitive that became invalid falls back to a rebuild
    if (o.alive && o.refitPending && !o.dirty) {
      o.refitPending = false;
      o.treeVersion = ++treeCounter_;
      if (o.refit()) {
        // Keep the refitted tree unless it traces much slower than the one built (SAH cost)
        const double ratio = o.refitCostRatio();
        st.refitCostRatio = std::max(st.refitCostRatio, ratio);
        topDirty_ = true;
        if (ratio <= Object::kRefitRebuildRatio) {
          ++st.objectsRefit;
          continue;
        }
        ++st.objectsRefitRejected;
      }
      o.markForRebuild();
    }
    // New or replaced geometry: rebuilt (replaced: with the replaced-geometry builder, fast by default)
    if (o.alive && o.dirty) {
      const bool fast =
          backgroundUpgrade_
              ? visitShape(o, [](auto shape, const auto& g) { return decltype(shape)::count(g) >= kUpgradeMin; })
              : o.replaced && replacedQuality_ == BvhBuildQuality::Fast;
      o.treeVersion = ++treeCounter_;
      st.objectsFastBuilt += fast;
      st.invalidPrimitives += o.rebuild(fast ? BvhBuildQuality::Fast : BvhBuildQuality::Sah);
      ++st.objectsRebuilt;
      topDirty_ = true;
    }
  }
}

void Scene::buildTopLevel(CommitStats& st) {
  // World boxes of the visible instances (finite ones only)
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

  // Tree over them; leaf slots map to instances
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

void Scene::sanitizeInputs(CommitStats& st) {
  // Cheap: once per material and light
  for (Material& m : materials_) {
    st.invalidMaterials += sanitizeMaterial(m) != 0;
    // A back material must be another material (one level: a back material's own is ignored)
    if (m.backMaterial >= 0 && std::size_t(m.backMaterial) >= materials_.size()) {
      m.backMaterial = -1;
      ++st.invalidMaterials;
    }
  }
  sanitizeColor(background, 0.0f, 1e6f);
  sanitizeColor(background2, 0.0f, 1e6f);
  if (!std::isfinite(backgroundAlpha)) backgroundAlpha = 1.0f;
  backgroundAlpha = std::clamp(backgroundAlpha, 0.0f, 1.0f);
  for (Light& l : lights_) st.invalidLights += sanitizeLight(l);
}

void Scene::updateFeatures() {
  // Lights: whether any that adds light casts shadows
  features_ = Features{};
  for (const SceneVolume& v : volumes_) features_.volumes = features_.volumes || v.traced();
  for (const Light& l : lights_) {
    float li = std::max(0.0f, l.intensity) * maxComponent(glm::max(l.color, Color(0.0f)));
    if (l.castShadows && li > 0.0f) features_.shadowLights = true;
  }

  // Traced instances: transforms, and what their materials use
  for (uint32_t slot : topInstances_) {
    const Instance& in = instances_[slot];
    const Object& o = objects_[in.object];
    if (!in.identity) features_.transforms = true;
    const TriangleMesh* mesh = std::get_if<TriangleMesh>(&o.geometry);
    // The instance's material and, for back faces, its back material
    const Material& front = materials_[in.material];
    const Material* back = front.backMaterial >= 0 ? &materials_[std::size_t(front.backMaterial)] : nullptr;
    for (const Material* mp : {&front, back}) {
      if (!mp) continue;
      const Material& m = *mp;
      if (maxComponent(m.reflectance) > 0.0f) features_.reflective = true;
      if (maxComponent(m.transmittance) > 0.0f) features_.transmissive = true;
      if (m.edgeWidth > 0.0f && mesh) features_.edges = true;
      if (m.texture >= 0 && size_t(m.texture) < textures_.size() && mesh && !mesh->texcoords.empty())
        features_.textures = true;
    }
  }
}

SceneStats Scene::stats() const {
  SceneStats s;
  s.instances = instances_.size();
  s.tracedInstances = topInstances_.size();
  for (const Object& o : objects_) {
    if (!o.alive) continue;
    ++s.objects;
    visitShape(o, [&](auto shape, const auto& g) {
      using Shape = decltype(shape);
      std::size_t& count = Shape::kType == GeometryType::Triangles ? s.triangles
                           : Shape::kType == GeometryType::Spheres ? s.spheres
                                                                   : s.tubes;
      count += o.bvh.primIndices().size();
      s.geometryBytes += Shape::bytes(g);
    });
    s.bvhNodes += o.bvh.nodes().size();
    s.fastTrees += o.builtQuality == BvhBuildQuality::Fast;
    s.bvhBytes += o.bvh.memoryBytes() + o.primOrder.capacity() * sizeof(uint32_t);
  }
  s.bvhNodes += top_.nodes().size();
  s.bvhBytes += top_.memoryBytes();
  for (const Texture& t : textures_) {
    s.textures += !t.rgba.empty();
    s.textureBytes += t.rgba.capacity();
  }
  volumeStats(s);
  return s;
}

}  // namespace whitted
