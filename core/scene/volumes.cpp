// The scene's volumes: registry, preparation at commit, and the march of a ray through all of them in order.
#include "scene/scene.h"

#include <algorithm>

namespace whitted {

uint32_t Scene::addVolume(Volume v) {
  volumes_.emplace_back();
  volumes_.back().volume = std::move(v);
  return uint32_t(volumes_.size() - 1);
}

void Scene::setVolume(uint32_t id, Volume v) {
  SceneVolume& sv = volumes_[id];
  sv = SceneVolume{};
  sv.volume = std::move(v);
}

VolumeScalars Scene::releaseVolumeScalars(uint32_t id) {
  SceneVolume& sv = volumes_[id];
  VolumeScalars scalars = std::move(sv.volume.grid.scalars);
  sv.volume.grid.scalars.clear();
  sv.dirty = true;  // (prepare then finds the grid empty and skips it, unless setVolume comes first)
  return scalars;
}

void Scene::setVolumeTransfer(uint32_t id, const TransferFunction& tf) {
  volumes_[id].volume.transfer = tf;
  volumes_[id].dirty = true;
}

void Scene::setVolumeVisible(uint32_t id, bool visible) {
  if (volumes_[id].volume.visible == visible) return;
  volumes_[id].volume.visible = visible;
  topDirty_ = true;
}

void Scene::removeVolume(uint32_t id) {
  volumes_[id] = SceneVolume{};
  volumes_[id].alive = false;
  volumes_[id].dirty = false;
  volumes_[id].volume.grid.scalars = VolumeScalars();
  topDirty_ = true;
}

void Scene::prepareVolumes(CommitStats& st) {
  for (SceneVolume& v : volumes_) {
    if (!v.alive || !v.dirty) continue;
    std::size_t invalid = 0;
    v.error = v.volume.prepare(invalid);
    v.dirty = false;
    st.invalidVoxels += invalid;
    st.invalidVolumes += !v.error.empty();
    topDirty_ = true;
  }
}

void Scene::prepareVolumeLights() {
  volumeLights_.clear();
  for (const Light& l : lights_) {
    if (!features_.volumes) break;
    VolumeLight v;
    v.radiance = std::max(0.0f, l.intensity) * glm::max(l.color, Color(0.0f));
    if (!(maxComponent(v.radiance) > 0.0f)) continue;
    v.positional = l.positional;
    v.toLight = -l.direction();
    v.position = l.position;
    v.attenuation = l.attenuation;
    v.axis = l.direction();
    // VTK's rule: a positional light is a spot light when its cone angle is below 90 degrees
    if (l.positional && l.coneAngle < 90.0) v.cosCone = std::cos(l.coneAngle * kPi / 180.0);
    v.exponent = l.exponent;
    volumeLights_.push_back(v);
  }
  volumeLighting_.ambient = glm::clamp(volumeAmbient, Color(0.0f), Color(1e6f));
  if (!isFinite(Vec3f(volumeLighting_.ambient))) volumeLighting_.ambient = Color(1.0f);
  volumeLighting_.alongRays = volumeLightsAlongRays;
}

void Scene::addVolumeBounds() {
  for (const SceneVolume& v : volumes_)
    if (v.traced()) bounds_.extend(v.volume.bounds());
}

int Scene::finestVolumeStepScale() const {
  int finest = 0;
  for (const SceneVolume& v : volumes_)
    if (v.traced()) finest = std::min(finest, v.volume.finestStepScale());
  return finest;
}

void Scene::volumeStats(SceneStats& s) const {
  for (const SceneVolume& v : volumes_) {
    if (!v.traced()) continue;
    ++s.volumes;
    s.volumeBytes += v.volume.grid.memoryBytes();
  }
}

void Scene::marchVolumes(const Ray& ray, double tEnd, bool emission, float stopBelow, VolumeMarch& acc,
                         int stepScale, bool coarser) const {
  // The segments of the ray in each traced volume, marched in the order they are entered
  struct Segment {
    double t0, t1;
    const Volume* v;
  };
  Segment local[8];  // no allocation for up to 8 volumes on a ray
  std::vector<Segment> many;
  std::size_t n = 0;
  for (const SceneVolume& sv : volumes_) {
    if (!sv.traced()) continue;
    double t0 = ray.tMin, t1 = std::min(tEnd, ray.tMax);
    if (!sv.volume.clip(ray, t0, t1)) continue;
    const Segment s{t0, t1, &sv.volume};
    if (n < 8) {
      local[n] = s;
    } else {
      if (many.empty()) many.assign(local, local + 8);
      many.push_back(s);
    }
    ++n;
  }
  if (n == 0) return;
  Segment* seg = n <= 8 ? local : many.data();
  std::sort(seg, seg + n, [](const Segment& a, const Segment& b) { return a.t0 < b.t0; });
  VolumeLighting lighting = volumeLighting_;  // (the lights' address taken here: a moved scene keeps them valid)
  lighting.lights = volumeLights_.data();
  lighting.count = volumeLights_.size();
  for (std::size_t i = 0; i < n && !acc.terminated; ++i)
    seg[i].v->march(ray, seg[i].t0, seg[i].t1, emission, stopBelow, acc, lighting,
                    coarser ? std::max(stepScale, seg[i].v->finestStepScale()) + 1 : stepScale);
}

}  // namespace whitted
