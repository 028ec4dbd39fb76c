// Batches of rays traced by our Scene and by Embree under the same work-sharing loop (bench_common.h's
// parallelFor), so neither engine gets a better scheduler. Used by the rays and build sub-commands.
#pragma once

#include "bench_embree.h"
#include "shading/camera.h"
#include "scene/scene.h"

#include <cstdint>
#include <string>
#include <vector>

namespace whitted::bench {

/// A batch of rays of one kind, in our (double) form; Embree gets the same values rounded to float.
struct RayBatch {
  std::string kind;        ///< primary, shadow, incoherent
  bool occlusion = false;  ///< any-hit query (shadow rays)
  /// Traced four at a time (consecutive rays: 4 pixels of a row, or neighbouring pixels' shadow rays): ours
  /// through Scene::intersectPacket / Scene::occludedPacket, Embree through rtcIntersect4 / rtcOccluded4.
  bool packets = false;
  std::vector<Ray> rays;
};

/// What one engine reported for each ray of a batch.
struct RayResults {
  std::vector<uint8_t> hit;
  std::vector<uint32_t> geom, prim;
  std::vector<float> t;
  void resize(std::size_t n);
};

/// Primary rays through the pixel centres of a w x h image.
RayBatch primaryRays(const Camera& cam, int w, int h);

/// Primary rays, then shadow rays to the first light and incoherent rays (uniform random directions on the
/// hemisphere facing the viewer) from every primary hit. Secondary rays start at our robust offset origin with
/// tMin = 1e-5 x scene diagonal so Embree's float traversal does not re-hit the surface it leaves; both engines
/// get exactly these rays.
std::vector<RayBatch> makeRays(const Scene& scene, const Camera& cam, int w, int h);

/// Traces a batch with Scene::intersect (closest hit), Scene::transmittance (any hit; materials must be opaque) or
/// Scene::intersectPacket / Scene::occludedPacket (packet batches) on `threads` threads; returns wall seconds,
/// *cpu = CPU seconds of the tracing threads.
double traceOurs(const Scene& scene, const RayBatch& b, int threads, RayResults& out, double* cpu = nullptr);

#ifdef WHITTED_HAVE_EMBREE
/// Our ray rounded to Embree's float ray.
void toEmbree(const Ray& r, RTCRay& e);
std::vector<RTCRay> toEmbree(const std::vector<Ray>& rays);

/// Traces with rtcIntersect1 / rtcOccluded1 (rtcIntersect4 / rtcOccluded4 for a packet batch); same contract as
/// traceOurs.
double traceEmbree(RTCScene scene, const std::vector<RTCRay>& rays, bool occlusion, bool packets, int threads,
                   RayResults& out, double* cpu = nullptr);
#endif

}  // namespace whitted::bench
