// Command-line renderer of the built-in scenes (headless; no VTK). Used by the benchmark and for quick checks.
//   whitted_render [--scene classic] [--size 800x600] [--spp 1] [--adaptive] [--depth 5] [--threshold 0.0039]
//                  [--threads 0] [--no-shadows] [--no-reflections] [--no-refractions] [--fresnel]
//                  [--target-error E] [--time-budget S] (progressive refinement by the error estimate)
//                  [--repeat 1] [--out image.png] [--depth-out depth.raw]
#include "image/image.h"
#include "image/report.h"
#include "scenes/scenes.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

using namespace whitted;

namespace {

struct Options {
  std::string sceneName = "classic", out = "whitted.png", depthOut;
  int w = 800, h = 600, repeat = 1;
  RenderSettings rs;
};

/// Reads the command line into o; returns false (after a message) on a bad option or value.
bool parseOptions(int argc, char** argv, Options& o) {
  RenderSettings& rs = o.rs;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    auto next = [&]() -> const char* {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "missing value after %s\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--scene")
      o.sceneName = next();
    else if (a == "--size") {
      if (std::sscanf(next(), "%dx%d", &o.w, &o.h) != 2 || o.w <= 0 || o.h <= 0) {
        std::fprintf(stderr, "--size wants WxH\n");
        return false;
      }
    } else if (a == "--spp")
      rs.samplesPerPixel = std::atoi(next());
    else if (a == "--adaptive")
      rs.adaptive = true;
    else if (a == "--depth")
      rs.integrator.maxDepth = std::atoi(next());
    else if (a == "--threshold")
      rs.integrator.contributionThreshold = float(std::atof(next()));
    else if (a == "--threads")
      rs.threads = std::atoi(next());
    else if (a == "--no-shadows")
      rs.integrator.shadows = false;
    else if (a == "--no-reflections")
      rs.integrator.reflections = false;
    else if (a == "--no-refractions")
      rs.integrator.refractions = false;
    else if (a == "--fresnel")
      rs.integrator.fresnel = true;
    else if (a == "--target-error")
      rs.targetError = std::atof(next());
    else if (a == "--time-budget")
      rs.timeBudget = std::atof(next());
    else if (a == "--repeat")
      o.repeat = std::max(1, std::atoi(next()));
    else if (a == "--out")
      o.out = next();
    else if (a == "--depth-out")
      o.depthOut = next();
    else {
      std::fprintf(stderr, "unknown option %s\nscenes:", a.c_str());
      for (auto& n : builtinSceneNames()) std::fprintf(stderr, " %s", n.c_str());
      std::fprintf(stderr, "\n");
      return false;
    }
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (!parseOptions(argc, argv, o)) return 2;
  const int w = o.w, h = o.h;
  // The volumes' step estimate where refinement steers by it, as the VTK pass sets it
  o.rs.integrator.volumeStepEstimate = o.rs.targetError > 0.0 || o.rs.timeBudget > 0.0;

  // Scene and camera
  Scene scene;
  CameraSpec cs;
  if (!buildBuiltinScene(o.sceneName, scene, cs)) {
    std::fprintf(stderr, "unknown scene '%s'\n", o.sceneName.c_str());
    return 2;
  }
  CommitStats commit = scene.commit();
  Camera cam = cs.make(double(w) / h, scene.bounds());

  // Frames: the median trace time is reported
  FrameBuffer fb;
  FrameStats fs;
  std::vector<double> times;
  for (int r = 0; r < o.repeat; ++r) {
    fs = render(scene, cam, o.rs, w, h, fb);
    times.push_back(fs.secondsTrace);
  }
  std::sort(times.begin(), times.end());
  fs.secondsTrace = times[times.size() / 2];

  // Image, depth and report
  if (!writePng(o.out, w, h, toRgba8(fb))) {
    std::fprintf(stderr, "cannot write %s\n", o.out.c_str());
    return 1;
  }
  if (!o.depthOut.empty()) {
    FILE* f = std::fopen(o.depthOut.c_str(), "wb");
    if (f) {
      std::fwrite(fb.depth.data(), sizeof(float), fb.depth.size(), f);
      std::fclose(f);
    }
  }
  std::printf("%s", frameReport(fs, scene.stats(), commit, w, h).c_str());
  if (o.repeat > 1) std::printf("  (trace time is the median of %d runs)\n", o.repeat);
  std::printf("  wrote            %s\n", o.out.c_str());
  return 0;
}
