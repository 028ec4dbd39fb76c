// libFuzzer target: a whole scene built from arbitrary bytes (meshes with NaN/Inf/degenerate data, bad indices,
// spheres and tubes with any radius, arbitrary materials and lights, random instance transforms and camera), then
// committed and rendered at 8x8. Invariant: no crash, no sanitizer report, every pixel finite.
#include "fuzz_bytes.h"
#include "image/renderer.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

using namespace whitted;

namespace {
using Reader = whitted_fuzz::Bytes;

/// One object: a triangle mesh (optional normals, colours, texture coordinates), a sphere set or a tube set.
uint32_t randomGeometry(Reader& r, Scene& scene) {
  uint8_t kind = r.get<uint8_t>() % 3;
  int count = r.get<uint8_t>() % 16;
  if (kind == 0) {
    TriangleMesh m;
    int nv = count + 3;
    for (int i = 0; i < nv; ++i) m.positions.push_back(r.v3());
    for (int i = 0; i < count + 1; ++i)
      m.triangles.push_back({r.get<uint8_t>() % (nv + 2), r.get<uint8_t>() % (nv + 2), r.get<uint8_t>() % (nv + 2)});
    uint8_t extras = r.get<uint8_t>();
    if (extras & 1)
      for (int i = 0; i < nv; ++i) m.normals.push_back(Vec3f(r.col()));
    if (extras & 2)
      for (int i = 0; i < nv; ++i) m.vertexColors.push_back(Color4(r.col(), r.f()));
    if (extras & 4)
      for (int i = 0; i < count + 1; ++i) m.triangleColors.push_back(Color4(r.col(), r.f()));
    if (extras & 8)
      for (int i = 0; i < nv; ++i) m.texcoords.push_back(Vec2f(r.f(), r.f()));
    return scene.addMesh(std::move(m));
  } else if (kind == 1) {
    SphereSet s;
    for (int i = 0; i < count + 1; ++i) {
      s.centers.push_back(r.v3());
      s.radii.push_back(r.d());
    }
    return scene.addSpheres(std::move(s));
  } else {
    TubeSet c;
    for (int i = 0; i < count + 1; ++i) {
      c.p0.push_back(r.v3());
      c.p1.push_back(r.v3());
    }
    c.radii.push_back(r.d());
    return scene.addTubes(std::move(c));
  }
}

/// A material with any values, sanitised as the VTK adapter does, with a 2x2 texture; its id.
uint32_t randomMaterial(Reader& r, Scene& scene) {
  Material m;
  m.ambient = r.f();
  m.diffuse = r.f();
  m.specular = r.f();
  m.specularPower = r.f();
  m.opacity = r.f();
  m.reflectance = r.col();
  m.transmittance = r.col();
  m.ior = r.f();
  m.absorption = r.col();
  m.colorSource = ColorSource(r.get<uint8_t>() % 4);
  sanitizeMaterial(m);  // what the VTK adapter does before handing materials over
  Texture tex;
  tex.width = tex.height = 2;
  tex.rgba.assign(16, r.get<uint8_t>());
  m.texture = int32_t(scene.addTexture(tex));
  return scene.addMaterial(m);
}

/// Identity, or an affine transform with any values.
Mat4 randomTransform(Reader& r) {
  Mat4 xf(1.0);
  if (r.get<uint8_t>() & 1)
    for (int c = 0; c < 4; ++c)
      for (int k = 0; k < 3; ++k) xf[c][k] = r.d();
  return xf;
}

void randomLights(Reader& r, Scene& scene) {
  int lights = r.get<uint8_t>() % 3;
  for (int i = 0; i < lights; ++i) {
    Light l;
    l.positional = r.get<uint8_t>() & 1;
    l.position = r.v3();
    l.focalPoint = r.v3();
    l.color = r.col();
    l.intensity = r.f();
    l.attenuation = r.v3();
    l.coneAngle = r.d();
    l.exponent = r.d();
    scene.lights().push_back(l);
  }
}

/// Renders 8x8 with any view-projection and settings; aborts on a non-finite pixel, a depth outside [0, 1] or a
/// safety-net catch.
void renderAndCheck(Reader& r, const Scene& scene) {
  Mat4 vp(1.0);
  for (int c = 0; c < 4; ++c)
    for (int k = 0; k < 4; ++k) vp[c][k] = r.d();
  if (r.get<uint8_t>() & 1) vp = Mat4(1.0);
  RenderSettings rs;
  rs.threads = 1;
  rs.samplesPerPixel = 1 + r.get<uint8_t>() % 3;
  rs.integrator.maxDepth = r.get<uint8_t>() % 8;
  rs.integrator.fresnel = r.get<uint8_t>() & 1;
  rs.integrator.beerLambert = r.get<uint8_t>() & 1;
  FrameBuffer fb;
  const FrameStats fs = render(scene, Camera::fromViewProjection(vp), rs, 8, 8, fb);
  // The frame's safety nets zero non-finite values: the checks below could never fail on their own, so what the
  // nets caught must be zero too (the scene was sanitised at commit; nothing invalid may remain for them)
  if (fs.rays.nonFiniteSamples + fs.rays.nonFinitePixels != 0) {
    std::fprintf(stderr, "safety nets caught %llu non-finite samples, %llu non-finite pixels\n",
                 (unsigned long long)fs.rays.nonFiniteSamples, (unsigned long long)fs.rays.nonFinitePixels);
    std::abort();
  }
  for (const Color4& c : fb.color)
    for (int k = 0; k < 4; ++k)
      if (!std::isfinite(c[k])) {
        std::fprintf(stderr, "non-finite pixel %g %g %g %g\n", c.x, c.y, c.z, c.w);
        std::abort();
      }
  for (float dpt : fb.depth)
    if (!(dpt >= 0.0f && dpt <= 1.0f)) {
      std::fprintf(stderr, "depth out of range %g\n", dpt);
      std::abort();
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  Reader r{data, size};
  Scene scene;
  int objects = r.get<uint8_t>() % 4 + 1;
  for (int o = 0; o < objects; ++o) {
    const uint32_t obj = randomGeometry(r, scene);
    const uint32_t material = randomMaterial(r, scene);
    scene.addInstance(obj, randomTransform(r), material);
  }
  randomLights(r, scene);
  scene.background = r.col();
  scene.commit();
  renderAndCheck(r, scene);
  return 0;
}
