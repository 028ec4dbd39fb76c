// The sub-commands of whitted_bench (one file each, cmd_<name>.cpp) and what they share: scene loading, thread
// lists, render settings from options, PNG output.
#pragma once

#include "bench_common.h"
#include "bench_scenes.h"
#include "image/renderer.h"

#include <string>
#include <vector>

namespace whitted::bench {

#ifdef WHITTED_HAVE_EMBREE
constexpr bool kHaveEmbree = true;
#else
constexpr bool kHaveEmbree = false;
#endif

/// Sub-commands; each returns the process exit code (0 = success, 2 = bad input).
int cmdInfo(const Args& a);    ///< camera, lights, material as JSON (for the VTK script)
int cmdMesh(const Args& a);    ///< writes a scene's first triangle mesh as .whtmesh
int cmdRays(const Args& a);    ///< ray throughput, ours vs Embree default and robust, with hit agreement
int cmdBuild(const Args& a);   ///< BVH build time and memory, ours vs Embree, at equal thread counts
int cmdFrame(const Args& a);   ///< whole frames (sizes x thread counts)
int cmdUpdate(const Args& a);  ///< re-render cost after camera / material / transform / mesh edits
int cmdError(const Args& a);   ///< error against a high-quality reference vs run time
int cmdTarget(const Args& a);  ///< TargetError's calibrated estimate against an independent truth
int cmdPov(const Args& a);     ///< writes a scene as POV-Ray 3.7 scene description
int cmdDiff(const Args& a);    ///< image difference of two PNG files
int cmdSteps(const Args& a);   ///< volume step study: error against a fine step, and time, per sample distance

/// Builds the scene named by --scene (default classic) from the --data directories; prints the error and returns
/// false on failure.
bool loadScene(const Args& a, BenchScene& bs);

/// Thread counts from --threads-list (default "1,0"; 0 = all usable cores), sorted and unique.
std::vector<int> threadList(const Args& a);

/// Render settings from --spp, --adaptive, --depth, --threshold, --no-shadows, --no-packets,
/// --no-primary-packets (defaults: the renderer's).
RenderSettings settingsFrom(const Args& a);

/// Hands object `object` of `source` to `scene` again as fresh geometry (a copy, set with setMesh / setSpheres /
/// setTubes), as an adapter without caching would: its BVH is rebuilt at the next commit. source may be scene.
void setObjectFrom(Scene& scene, uint32_t object, const Scene& source);

/// Frames rendered warmup times untimed, then reps times timed (TimedFrames::wall: trace seconds; cpu: the process's
/// CPU seconds per render); fb and stats are the last frame's.
struct TimedFrames {
  Timing wall, cpu;
  FrameStats stats;
};
TimedFrames timeFrames(const Scene& scene, const Camera& cam, const RenderSettings& rs, int w, int h, int warmup,
                       int reps, FrameBuffer& fb);

/// Writes fb as an 8-bit PNG (nothing when path is empty).
void savePng(const std::string& path, const FrameBuffer& fb);

}  // namespace whitted::bench
