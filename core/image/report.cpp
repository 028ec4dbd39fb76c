#include "image/report.h"

#include <cstdio>
#include <thread>

namespace whitted {

std::string frameReport(const FrameStats& f, const SceneStats& s, const CommitStats& c, int w, int h,
                        double secondsOther, const char* otherLabel) {
  char buf[2048];
  // Say when the process may use fewer cores than the machine has (mpirun binds ranks to single cores by default)
  char affinity[64] = "";
  const int usable = hardwareThreads(), machine = int(std::thread::hardware_concurrency());
  if (machine > usable)
    std::snprintf(affinity, sizeof affinity, " [CPU affinity: %d of %d cores usable]", usable, machine);
  double traced = double(f.rays.traced());
  double mrays = f.secondsTrace > 0.0 ? traced / f.secondsTrace * 1e-6 : 0.0;
  int n = std::snprintf(buf, sizeof buf,
                        "Whitted frame report\n"
                        "  image            %d x %d, %llu samples, %d threads%s%s\n"
                        "  time             build %.2f ms (%d object BVHs rebuilt, top level %s), trace %.2f ms",
                        w, h, (unsigned long long)f.samples, f.threads, affinity, f.aborted ? " (ABORTED)" : "",
                        c.secondsBuild * 1e3, c.objectsRebuilt, c.topLevelRebuilt ? "rebuilt" : "kept",
                        f.secondsTrace * 1e3);
  std::string out(buf, std::size_t(n));
  if (otherLabel) {
    n = std::snprintf(buf, sizeof buf, ", %s %.2f ms", otherLabel, secondsOther * 1e3);
    out.append(buf, std::size_t(n));
  }
  n = std::snprintf(
      buf, sizeof buf,
      "\n"
      "  rays             primary %llu, shadow %llu, reflection %llu, refraction %llu (%.2f Mrays/s)\n"
      "  rays saved       %llu below contribution threshold, %llu at depth cap; %llu bound rays (first hit of "
      "cut rays, for the truncation bound); %llu camera rays in 8x8 blocks whose frustum meets nothing (misses, not traced)\n"
      "  kernel           reflection %s, refraction %s, shadows %s\n"
      "  scene            %zu triangles, %zu spheres, %zu tubes, %zu objects, %zu instances, %zu invalid skipped\n"
      "  memory           BVH %zu nodes, %.2f MiB; geometry %.2f MiB\n"
      "  error estimate   truncation RMS %.3g, p95 %.3g, max %.3g (upper bound: what depth cap and threshold "
      "left out)\n"
      "                   sampling RMS %.3g, p95 %.3g, max %.3g (95%% per pixel); total RMS %.3g (bound)\n"
      "                   calibrated RMS %.3g (sampling %.3g; a 1-sigma estimate of the RMS error, what "
      "TargetError compares)\n",
      (unsigned long long)f.rays.primary, (unsigned long long)f.rays.shadow, (unsigned long long)f.rays.reflection,
      (unsigned long long)f.rays.refraction, mrays, (unsigned long long)f.rays.savedByThreshold,
      (unsigned long long)f.rays.savedByDepth, (unsigned long long)f.rays.boundRays, (unsigned long long)f.pixelsCulled, f.kernelReflection ? "on" : "off", f.kernelRefraction ? "on" : "off",
      f.kernelShadows ? "on" : "off", s.triangles, s.spheres, s.tubes, s.objects, s.instances, c.invalidPrimitives,
      s.bvhNodes, s.bvhBytes / 1048576.0, s.geometryBytes / 1048576.0, f.truncation.rms, f.truncation.p95,
      f.truncation.max, f.sampling.rms, f.sampling.p95, f.sampling.max, f.total.rms, f.calibrated.rms,
      f.calibratedSampling.rms);
  out.append(buf, std::size_t(n));
  if (f.rays.boundRaysCapped > 0) {
    n = std::snprintf(buf, sizeof buf,
                      "                   %llu cut rays reached the cap of bound rays per cut ray (charged the "
                      "scene-wide bound for the levels left)\n",
                      (unsigned long long)f.rays.boundRaysCapped);
    out.append(buf, std::size_t(n));
  }
  // Safety nets: what they caught is counted, never silently hidden (all zero for valid input)
  n = std::snprintf(buf, sizeof buf,
                    "  safety nets      %llu non-finite samples, %llu non-finite pixels, %llu alpha and %llu depth "
                    "values clamped; scene input fixed: %zu materials, %zu lights\n",
                    (unsigned long long)f.rays.nonFiniteSamples, (unsigned long long)f.rays.nonFinitePixels,
                    (unsigned long long)f.rays.clampedAlpha, (unsigned long long)f.rays.clampedDepth,
                    c.invalidMaterials, c.invalidLights);
  out.append(buf, std::size_t(n));
  if (s.volumes > 0 || c.invalidVolumes > 0 || c.invalidVoxels > 0) {
    n = std::snprintf(buf, sizeof buf,
                      "  volumes          %zu traced (%.2f MiB), %zu skipped as invalid; %llu samples (+%llu for the "
                      "step's error estimate), %llu rays terminated early; %zu non-finite scalars, %llu samples of "
                      "them (transparent)\n",
                      s.volumes, s.volumeBytes / 1048576.0, c.invalidVolumes, (unsigned long long)f.rays.volumeSamples,
                      (unsigned long long)f.rays.volumeEstimateSamples, (unsigned long long)f.rays.volumeTerminated,
                      c.invalidVoxels,
                      (unsigned long long)f.rays.volumeInvalidSamples);
    out.append(buf, std::size_t(n));
  }
  return out;
}

}  // namespace whitted
