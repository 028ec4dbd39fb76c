// whitted_bench update --scene NAME: the main scene plus a ring of small glyph actors; re-render cost (commit +
// trace) after no change, a camera move, a material change, one actor moved, a small and the main mesh replaced,
// and a full rebuild (what an adapter without caching would pay).
#include "bench_commands.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cstdio>

namespace whitted::bench {

int cmdUpdate(const Args& a) {
  // The main scene plus a ring of small glyph actors (UV-sphere meshes), as a ParaView pipeline with several
  // representations would give
  BenchScene bs;
  if (!loadScene(a, bs)) return 2;
  int w = 800, h = 600;
  a.size("size", w, h);
  int reps = a.integer("reps", 5), warmup = a.integer("warmup", 1);
  int glyphs = a.integer("actors", 8);
  bs.scene.commit();
  Bounds3 b0 = bs.scene.bounds();
  double rad = 0.06 * b0.diagonal();
  Material gm;
  gm.diffuseColor = gm.ambientColor = Color(0.3f, 0.6f, 0.9f);
  gm.ambient = 0.1f;
  gm.diffuse = 0.8f;
  gm.specular = 0.3f;
  gm.specularPower = 20.0f;
  uint32_t gmat = bs.scene.addMaterial(gm);
  std::vector<uint32_t> glyphInstances, glyphObjects;
  for (int i = 0; i < glyphs; ++i) {
    double ang = 2.0 * kPi * i / glyphs;
    Vec3 c = b0.center() + 0.45 * b0.diagonal() * Vec3(std::cos(ang), 0.0, std::sin(ang));
    TriangleMesh m = makeSphereMesh(Vec3(0.0), rad, 128, 64);  // ~16k triangles each
    roundToFloat(m);
    uint32_t o = bs.scene.addMesh(std::move(m));
    glyphObjects.push_back(o);
    glyphInstances.push_back(bs.scene.addInstance(o, glm::translate(Mat4(1.0), c), gmat));
  }
  // What the adapter would hand over again without caching: the object's own geometry, given anew (as
  // cmd_build does; Scene::mesh etc. return it in the order given)
  auto resetObject = [&](uint32_t o) { setObjectFrom(bs.scene, o, bs.scene); };

  double tc0 = now();
  bs.scene.commit();
  double firstCommit = now() - tc0;
  SceneStats st = bs.scene.stats();
  RenderSettings rs;
  CameraSpec spec = bs.camera;
  Camera cam = spec.make(double(w) / h, bs.scene.bounds());
  FrameBuffer fb;

  CsvWriter csv(a.str("csv"), {"scene", "case", "triangles", "instances", "width", "height", "commit_seconds",
                               "trace_seconds", "total_seconds", "prepare_seconds", "objects_rebuilt",
                               "top_level_rebuilt", "runs", "commit_cpu_seconds", "trace_cpu_seconds"});
  auto measure = [&](const char* name, auto&& edit) {
    std::vector<double> commitT, traceT, prepT, commitC, traceC;
    CommitStats last;
    for (int r = 0; r < warmup + reps; ++r) {
      double p0 = now();
      edit(r);  // change the scene (untimed part: what the adapter hands over)
      double p1 = now(), cpu1 = processCpuNow();
      last = bs.scene.commit();
      double c1 = now(), cpu2 = processCpuNow();
      FrameStats fs = render(bs.scene, cam, rs, w, h, fb);
      double cpu3 = processCpuNow();
      if (r >= warmup) {
        prepT.push_back(p1 - p0);
        commitT.push_back(c1 - p1);
        traceT.push_back(fs.secondsTrace);
        commitC.push_back(cpu2 - cpu1);
        traceC.push_back(cpu3 - cpu2);
      }
    }
    Timing tc = summarize(commitT), tt = summarize(traceT), tp = summarize(prepT);
    csv.row({bs.name, name, fmt(st.triangles), fmt(bs.scene.instanceCount()), fmt(w), fmt(h), fmt(tc.median),
             fmt(tt.median), fmt(tc.median + tt.median), fmt(tp.median), fmt(last.objectsRebuilt),
             fmt(int(last.topLevelRebuilt)), fmt(tc.runs), fmt(summarize(commitC).median),
             fmt(summarize(traceC).median)});
    std::printf("%-26s commit %9.2f ms  trace %8.2f ms  total %9.2f ms  (%d objects rebuilt, top level %s)\n", name,
                tc.median * 1e3, tt.median * 1e3, (tc.median + tt.median) * 1e3, last.objectsRebuilt,
                last.topLevelRebuilt ? "rebuilt" : "kept");
    std::fflush(stdout);
  };

  std::printf("%s + %d glyph actors: %zu triangles, %zu instances, first commit %.1f ms\n", bs.name.c_str(), glyphs,
              st.triangles, bs.scene.instanceCount(), firstCommit * 1e3);
  measure("no change (re-render)", [&](int) {});
  measure("camera move", [&](int r) {
    CameraSpec s = spec;
    double ang = 0.02 * (r + 1);
    Vec3 off = s.eye - s.focal;
    s.eye = s.focal +
            Vec3(std::cos(ang) * off.x - std::sin(ang) * off.z, off.y, std::sin(ang) * off.x + std::cos(ang) * off.z);
    cam = s.make(double(w) / h, bs.scene.bounds());
  });
  cam = spec.make(double(w) / h, bs.scene.bounds());
  measure("material change",
          [&](int r) { bs.scene.material(gmat).diffuseColor = Color(0.3f + 0.01f * r, 0.6f, 0.9f); });
  measure("move one actor", [&](int r) {
    double ang = 2.0 * kPi * 0 / glyphs;
    Vec3 c = b0.center() + 0.45 * b0.diagonal() * Vec3(std::cos(ang), 0.0, std::sin(ang));
    bs.scene.setInstanceTransform(glyphInstances[0], glm::translate(Mat4(1.0), c + Vec3(0.0, 0.01 * rad * r, 0.0)));
  });
  measure("setMesh small actor (16k)", [&](int) { resetObject(glyphObjects[0]); });
  measure("setMesh main actor", [&](int) { resetObject(0); });
  measure("full rebuild (no caching)", [&](int) {
    for (uint32_t o = 0; o < bs.scene.objectCount(); ++o) resetObject(o);
  });
  return 0;
}

}  // namespace whitted::bench
