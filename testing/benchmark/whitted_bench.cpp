// whitted_bench: the measuring half of the benchmark (run_benchmark.py drives it and writes the report). One
// sub-command per experiment, each in its own file cmd_<name>.cpp:
//
//   whitted_bench info   --scene NAME                        camera, lights, material as JSON (for the VTK script)
//   whitted_bench rays   --scene NAME --size WxH             Mrays/s of primary / primary4 / shadow / shadow4
//                                                            (packets of 4) / incoherent rays, ours and Embree's
//                                                            (default and robust mode); agreement
//   whitted_bench build  --scene NAME                        BVH build time and memory, ours and Embree's
//                                                            (low / medium / high quality), at equal threads
//   whitted_bench frame  --scene NAME --sizes WxH,...        whole frames; --threads-list 1,2 for scaling
//   whitted_bench update --scene NAME                        re-render cost after camera / transform / mesh edits
//   whitted_bench error  --scene NAME --size WxH             error against a high-quality reference vs run time
//                                                            (--budget S: slow settings get fewer timed runs)
//   whitted_bench mesh   --scene NAME --out file.whtmesh     writes a scene's first mesh (tests, debugging)
//   whitted_bench pov    --scene NAME --out file.pov         the scene in POV-Ray 3.7's language (the anchor)
//   whitted_bench diff   --image A.png --reference B.png     RMSE, PSNR, SSIM, largest 8-bit difference (JSON)
//
// Common options: --data DIR1,DIR2 (where wavelet_*.whtmesh live), --csv FILE (rows are appended), --reps N
// (timed runs, median reported), --warmup N (untimed runs first), --threads-list 1,0 (0 = all usable cores).
#include "bench_commands.h"

#include <cstdio>
#include <cstring>

using namespace whitted::bench;

namespace {

struct Command {
  const char* name;
  int (*run)(const Args&);
};

constexpr Command kCommands[] = {{"info", cmdInfo},   {"rays", cmdRays},     {"build", cmdBuild},
                                 {"frame", cmdFrame}, {"update", cmdUpdate}, {"error", cmdError},
                                 {"mesh", cmdMesh},   {"pov", cmdPov},       {"diff", cmdDiff},
                                 {"steps", cmdSteps}, {"target", cmdTarget}};

int usage() {
  std::fprintf(stderr, "usage: whitted_bench");
  for (const Command& c : kCommands) std::fprintf(stderr, "%s%s", &c == kCommands ? " " : "|", c.name);
  std::fprintf(stderr, " --scene NAME [options]\nscenes:");
  for (const std::string& n : benchSceneNames()) std::fprintf(stderr, " %s", n.c_str());
  std::fprintf(stderr, "\nEmbree anchor: %s\n", kHaveEmbree ? "compiled in" : "not available");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) return usage();
  for (const Command& c : kCommands)
    if (std::strcmp(argv[1], c.name) == 0) return c.run(Args(argc, argv, 2));
  return usage();
}
