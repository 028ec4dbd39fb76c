// whitted_bench mesh --scene NAME --out FILE: writes the scene's first triangle mesh as .whtmesh (tests,
// debugging).
#include "bench_commands.h"

#include <cstdio>

namespace whitted::bench {

int cmdMesh(const Args& a) {
  BenchScene bs;
  if (!loadScene(a, bs)) return 2;
  for (uint32_t o = 0; o < bs.scene.objectCount(); ++o)
    if (bs.scene.objectType(o) == GeometryType::Triangles)
      return writeMeshFile(a.str("out", "mesh.whtmesh"), bs.scene.mesh(o)) ? 0 : 1;
  std::fprintf(stderr, "scene has no triangle mesh\n");
  return 1;
}

}  // namespace whitted::bench
