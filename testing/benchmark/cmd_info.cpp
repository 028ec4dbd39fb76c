// whitted_bench info --scene NAME: the scene's camera, lights, material and bounds as JSON, so VTK's rendering
// (vtk_gl_bench.py) sets up exactly the scene whitted_bench traces; also the versions the report quotes.
#include "bench_commands.h"
#include "bench_embree.h"

#include <cstdio>

namespace whitted::bench {

namespace {

std::string jsonVec(const Vec3& v) {
  char b[128];
  std::snprintf(b, sizeof b, "[%.9g, %.9g, %.9g]", v.x, v.y, v.z);
  return b;
}

std::string jsonColor(const Color& c) {
  return jsonVec(Vec3(c));
}

}  // namespace

int cmdInfo(const Args& a) {
  BenchScene bs;
  if (!loadScene(a, bs)) return 2;
  bs.scene.commit();
  SceneStats st = bs.scene.stats();
  const Material& m = bs.mainMaterial;
  std::printf("{\n  \"scene\": \"%s\",\n  \"description\": \"%s\",\n", bs.name.c_str(), bs.description.c_str());
  std::printf("  \"triangles\": %zu, \"spheres\": %zu, \"tubes\": %zu,\n", st.triangles, st.spheres, st.tubes);
  std::printf("  \"camera\": {\"eye\": %s, \"focal\": %s, \"up\": %s, \"viewAngle\": %.9g},\n",
              jsonVec(bs.camera.eye).c_str(), jsonVec(bs.camera.focal).c_str(), jsonVec(bs.camera.up).c_str(),
              bs.camera.viewAngle);
  std::printf("  \"background\": %s,\n  \"lights\": [", jsonColor(bs.scene.background).c_str());
  for (std::size_t i = 0; i < bs.scene.lights().size(); ++i) {
    const Light& l = bs.scene.lights()[i];
    std::printf(
        "%s{\"positional\": %s, \"position\": %s, \"focalPoint\": %s, \"color\": %s, \"intensity\": %g, "
        "\"coneAngle\": %g, \"castShadows\": %s, \"headlight\": %s}",
        i ? ", " : "", l.positional ? "true" : "false", jsonVec(l.position).c_str(), jsonVec(l.focalPoint).c_str(),
        jsonColor(l.color).c_str(), l.intensity, l.coneAngle, l.castShadows ? "true" : "false",
        int(i) == bs.headlight ? "true" : "false");
  }
  std::printf(
      "],\n  \"material\": {\"diffuseColor\": %s, \"ambient\": %g, \"diffuse\": %g, \"specular\": %g, "
      "\"specularPower\": %g},\n",
      jsonColor(m.diffuseColor).c_str(), m.ambient, m.diffuse, m.specular, m.specularPower);
  Bounds3 b = bs.scene.bounds();
#ifdef WHITTED_HAVE_EMBREE
  const char* embreeVersion = RTC_VERSION_STRING;
#else
  const char* embreeVersion = "";
#endif
  std::printf(
      "  \"bounds\": [%s, %s],\n  \"hardwareThreads\": %d,\n  \"embree\": %s,\n  \"embreeVersion\": \"%s\",\n"
      "  \"compiler\": \"%s\"\n}\n",
      jsonVec(b.lo).c_str(), jsonVec(b.hi).c_str(), hardwareThreads(), kHaveEmbree ? "true" : "false",
      embreeVersion,
#if defined(__clang__)
      "clang " __clang_version__
#elif defined(__GNUC__)
      "gcc " __VERSION__
#else
      "unknown"
#endif
  );
  return 0;
}

}  // namespace whitted::bench
