// Embree 3 anchor for the benchmark (compiled only when WHITTED_HAVE_EMBREE is defined). Mirrors a committed
// whitted::Scene: one Embree geometry per instance, geomID == instance index, primID == our primitive index, so
// hits can be compared one to one. Triangles -> RTC_GEOMETRY_TYPE_TRIANGLE, spheres -> SPHERE_POINT, tubes ->
// ROUND_LINEAR_CURVE with unshared end points (a cone with both spherical caps = our tube).
#pragma once

#ifdef WHITTED_HAVE_EMBREE

#include "scene/scene.h"

#include <embree3/rtcore.h>

#include <atomic>
#include <string>

namespace whitted::bench {

/// An Embree device whose allocations are tracked.
class EmbreeDevice {
 public:
  /// threads = 0: Embree's default (all cores); otherwise its build thread pool size.
  explicit EmbreeDevice(int threads = 0);
  ~EmbreeDevice();
  EmbreeDevice(const EmbreeDevice&) = delete;
  EmbreeDevice& operator=(const EmbreeDevice&) = delete;
  RTCDevice get() const { return device_; }
  /// Bytes currently allocated by Embree on this device, and the peak since resetPeak().
  long long bytes() const { return bytes_.load(); }
  long long peak() const { return peak_.load(); }
  void resetPeak() { peak_.store(bytes_.load()); }

 private:
  static bool monitor(void* self, ssize_t bytes, bool post);
  RTCDevice device_ = nullptr;
  std::atomic<long long> bytes_{0}, peak_{0};
};

/// Embree scene built from the visible instances of a committed whitted::Scene (identity transforms assumed, as
/// in all benchmark scenes). flags: RTC_SCENE_FLAG_ROBUST selects Embree's robust mode (conservative box tests,
/// watertight triangles: the like-for-like anchor of our exact traversal).
class EmbreeScene {
 public:
  EmbreeScene(EmbreeDevice& device, const Scene& scene, RTCBuildQuality quality = RTC_BUILD_QUALITY_MEDIUM,
              RTCSceneFlags flags = RTC_SCENE_FLAG_NONE);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;
  /// Builds the BVH; returns wall seconds. Bytes allocated by the build are available afterwards.
  double commit();
  RTCScene get() const { return scene_; }
  long long buildBytes() const { return buildBytes_; }
  long long buildPeakBytes() const { return buildPeak_; }
  long long bufferBytes() const { return bufferBytes_; }
  /// CPU seconds of the whole process during the last commit (Embree's TBB workers included).
  double commitCpuSeconds() const { return commitCpu_; }

 private:
  EmbreeDevice& device_;
  RTCScene scene_ = nullptr;
  long long bufferBytes_ = 0, buildBytes_ = 0, buildPeak_ = 0;
  double commitCpu_ = 0.0;
};

}  // namespace whitted::bench

#endif  // WHITTED_HAVE_EMBREE
