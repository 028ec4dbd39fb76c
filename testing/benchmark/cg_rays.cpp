// whitted_cg_rays --scene NAME [--data DIR] [--size WxH]: the rays of `whitted_bench rays` (camera, shadow,
// incoherent), each kind traced once on the calling thread by its own non-inlined function, for instruction counts
// per ray under callgrind (inclusive cost of traceClosest / traceShadow divided by the ray counts printed), and a
// hash of every result (instance, primitive, t, u, v; transmittance) to check that a kernel change finds the same
// hits bit for bit. Not installed; built on request (target whitted_cg_rays).
#include "bench_commands.h"
#include "bench_trace.h"

#include <cinttypes>
#include <cstdio>
#include <cstring>

namespace whitted::bench {
namespace {

struct Fnv {
  uint64_t h = 1469598103934665603ull;
  template <typename T>
  void add(const T& v) {
    unsigned char b[sizeof(T)];
    std::memcpy(b, &v, sizeof b);
    for (unsigned char c : b) h = (h ^ c) * 1099511628211ull;
  }
};

template <int Kind>  // one instance per batch kind (primary, incoherent): separate callgrind totals
[[gnu::noinline]] uint64_t traceClosest(const Scene& scene, const std::vector<Ray>& rays) {
  Fnv f;
  f.add(Kind);  // (also keeps the compiler from folding the two instances into one)
  for (const Ray& r : rays) {
    Hit h;
    const bool found = scene.intersect(r, h);
    f.add(found);
    if (found) f.add(h.instance), f.add(h.prim), f.add(h.t), f.add(h.u), f.add(h.v);
  }
  return f.h;
}

[[gnu::noinline]] uint64_t traceShadow(const Scene& scene, const std::vector<Ray>& rays) {
  Fnv f;
  for (const Ray& r : rays) {
    const Color c = scene.transmittance(r, 1.0f / 255.0f);
    f.add(c.r), f.add(c.g), f.add(c.b);
  }
  return f.h;
}

}  // namespace
}  // namespace whitted::bench

int main(int argc, char** argv) {
  using namespace whitted;
  using namespace whitted::bench;
  Args a(argc, argv, 1);
  BenchScene bs;
  if (!loadScene(a, bs)) return 2;
  int w = 256, h = 192;
  a.size("size", w, h);
  for (uint32_t m = 0; m < bs.scene.materialCount(); ++m) bs.scene.material(m).transmittance = Color(0.0f);
  bs.scene.commit();
  const Camera cam = bs.camera.make(double(w) / h, bs.scene.bounds());
  const std::vector<RayBatch> batches = makeRays(bs.scene, cam, w, h);
  for (const RayBatch& b : batches) {
    if (b.packets) continue;
    const uint64_t hash = b.occlusion              ? traceShadow(bs.scene, b.rays)
                          : b.kind == "primary" ? traceClosest<0>(bs.scene, b.rays)
                                                : traceClosest<1>(bs.scene, b.rays);
    std::printf("%s %s rays %zu hash %016" PRIx64 "\n", bs.name.c_str(), b.kind.c_str(), b.rays.size(), hash);
  }
  return 0;
}
