#include "bench_embree.h"

#ifdef WHITTED_HAVE_EMBREE

#include "bench_common.h"

#include <cstdio>
#include <string>

namespace whitted::bench {

namespace {

void errorHandler(void*, RTCError code, const char* str) {
  std::fprintf(stderr, "embree error %d: %s\n", int(code), str);
}

}  // namespace

EmbreeDevice::EmbreeDevice(int threads) {
  std::string config = threads > 0 ? "threads=" + std::to_string(threads) : "";
  device_ = rtcNewDevice(config.c_str());
  rtcSetDeviceErrorFunction(device_, errorHandler, nullptr);
  rtcSetDeviceMemoryMonitorFunction(device_, &EmbreeDevice::monitor, this);
}

EmbreeDevice::~EmbreeDevice() {
  rtcReleaseDevice(device_);
}

bool EmbreeDevice::monitor(void* self, ssize_t bytes, bool) {
  auto* d = static_cast<EmbreeDevice*>(self);
  long long now = d->bytes_.fetch_add(bytes) + bytes;
  long long p = d->peak_.load();
  while (now > p && !d->peak_.compare_exchange_weak(p, now)) {
  }
  return true;
}

EmbreeScene::EmbreeScene(EmbreeDevice& device, const Scene& scene, RTCBuildQuality quality, RTCSceneFlags flags)
    : device_(device) {
  long long before = device.bytes();
  scene_ = rtcNewScene(device.get());
  rtcSetSceneBuildQuality(scene_, quality);
  rtcSetSceneFlags(scene_, flags);
  for (uint32_t i = 0; i < scene.instanceCount(); ++i) {
    uint32_t o = scene.instanceObject(i);
    RTCGeometry g = nullptr;
    switch (scene.objectType(o)) {
      case GeometryType::Triangles: {
        const TriangleMesh& m = scene.mesh(o);
        g = rtcNewGeometry(device.get(), RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                              3 * sizeof(float), m.positions.size()));
        for (std::size_t k = 0; k < m.positions.size(); ++k)
          for (int c = 0; c < 3; ++c) v[3 * k + c] = float(m.positions[k][c]);
        auto* t = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                 3 * sizeof(uint32_t), m.triangles.size()));
        for (std::size_t k = 0; k < m.triangles.size(); ++k)
          for (int c = 0; c < 3; ++c) t[3 * k + c] = m.triangles[k][c];
        break;
      }
      case GeometryType::Spheres: {
        const SphereSet& s = scene.spheres(o);
        g = rtcNewGeometry(device.get(), RTC_GEOMETRY_TYPE_SPHERE_POINT);
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                                                              4 * sizeof(float), s.centers.size()));
        for (std::size_t k = 0; k < s.centers.size(); ++k) {
          for (int c = 0; c < 3; ++c) v[4 * k + c] = float(s.centers[k][c]);
          v[4 * k + 3] = float(s.radii.size() == 1 ? s.radii[0] : s.radii[k]);
        }
        break;
      }
      case GeometryType::Tubes: {
        const TubeSet& c = scene.tubes(o);
        std::size_t n = std::min(c.p0.size(), c.p1.size());
        g = rtcNewGeometry(device.get(), RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE);
        auto* v = static_cast<float*>(
            rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), 2 * n));
        auto* idx = static_cast<uint32_t*>(
            rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, sizeof(uint32_t), n));
        for (std::size_t k = 0; k < n; ++k) {
          float r = float(c.radii.size() == 1 ? c.radii[0] : c.radii[k]);
          for (int e = 0; e < 2; ++e) {
            const Vec3& p = e ? c.p1[k] : c.p0[k];
            for (int a = 0; a < 3; ++a) v[4 * (2 * k + e) + a] = float(p[a]);
            v[4 * (2 * k + e) + 3] = r;
          }
          idx[k] = uint32_t(2 * k);  // segments share no vertex: each is a full tube with both caps
        }
        break;
      }
    }
    rtcSetGeometryBuildQuality(g, quality);
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(scene_, g, i);
    rtcReleaseGeometry(g);
  }
  bufferBytes_ = device.bytes() - before;
}

EmbreeScene::~EmbreeScene() {
  rtcReleaseScene(scene_);
}

double EmbreeScene::commit() {
  long long before = device_.bytes();
  device_.resetPeak();
  double t0 = now(), c0 = processCpuNow();
  rtcCommitScene(scene_);
  double t = now() - t0;
  commitCpu_ = processCpuNow() - c0;
  buildBytes_ = device_.bytes() - before;
  buildPeak_ = device_.peak() - before;
  return t;
}

}  // namespace whitted::bench

#endif  // WHITTED_HAVE_EMBREE
