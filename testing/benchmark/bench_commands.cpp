#include "bench_commands.h"

#include "image/image.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>

namespace whitted::bench {

bool loadScene(const Args& a, BenchScene& bs) {
  std::string err;
  if (!buildBenchScene(a.str("scene", "classic"), a.list("data", "."), bs, err)) {
    std::fprintf(stderr, "whitted_bench: %s\n", err.c_str());
    return false;
  }
  return true;
}

std::vector<int> threadList(const Args& a) {
  std::vector<int> t;
  for (const std::string& s : a.list("threads-list", "1,0")) {
    int n = std::atoi(s.c_str());
    t.push_back(n <= 0 ? hardwareThreads() : n);
  }
  std::sort(t.begin(), t.end());
  t.erase(std::unique(t.begin(), t.end()), t.end());
  return t;
}

RenderSettings settingsFrom(const Args& a) {
  RenderSettings rs;
  rs.samplesPerPixel = a.integer("spp", 1);
  rs.adaptive = a.has("adaptive");
  rs.integrator.maxDepth = a.integer("depth", 5);
  rs.integrator.contributionThreshold = float(a.real("threshold", 1.0 / 255.0));
  rs.integrator.shadows = !a.has("no-shadows");
  rs.integrator.packets = !a.has("no-packets");
  rs.integrator.primaryPackets = !a.has("no-primary-packets");
  rs.errorEstimates = !a.has("no-error-estimates");  // as interactive frames of the VTK pass
  rs.integrator.truncationLookahead = a.integer("lookahead", rs.integrator.truncationLookahead);
  rs.integrator.truncationTolerance = float(a.real("tolerance", rs.integrator.truncationTolerance));
  rs.integrator.truncationLookaheadMax = a.integer("lookahead-max", rs.integrator.truncationLookaheadMax);
  rs.integrator.truncationRelativeTolerance =
      float(a.real("relative-tolerance", rs.integrator.truncationRelativeTolerance));
  rs.targetError = a.real("target-error", 0.0);
  rs.timeBudget = a.real("time-budget", 0.0);
  // The volumes' step estimate where refinement steers, as the VTK pass sets it
  rs.integrator.volumeStepEstimate = rs.targetError > 0.0 || rs.timeBudget > 0.0 || a.has("volume-step-estimate");
  return rs;
}

void setObjectFrom(Scene& scene, uint32_t object, const Scene& source) {
  switch (source.objectType(object)) {
    case GeometryType::Triangles:
      scene.setMesh(object, TriangleMesh(source.mesh(object)));
      break;
    case GeometryType::Spheres:
      scene.setSpheres(object, SphereSet(source.spheres(object)));
      break;
    case GeometryType::Tubes:
      scene.setTubes(object, TubeSet(source.tubes(object)));
      break;
  }
}

TimedFrames timeFrames(const Scene& scene, const Camera& cam, const RenderSettings& rs, int w, int h, int warmup,
                       int reps, FrameBuffer& fb) {
  TimedFrames out;
  std::vector<double> cpu;
  out.wall = timeRepeated(warmup, reps, [&] {
    const double c0 = processCpuNow();
    out.stats = render(scene, cam, rs, w, h, fb);
    cpu.push_back(processCpuNow() - c0);
    return out.stats.secondsTrace;
  });
  cpu.erase(cpu.begin(), cpu.begin() + std::min<std::ptrdiff_t>(warmup, std::ptrdiff_t(cpu.size()) - 1));
  out.cpu = summarize(cpu);
  return out;
}

void savePng(const std::string& path, const FrameBuffer& fb) {
  if (!path.empty() && !writePng(path, fb.width, fb.height, toRgba8(fb)))
    std::fprintf(stderr, "cannot write %s\n", path.c_str());
}

}  // namespace whitted::bench
