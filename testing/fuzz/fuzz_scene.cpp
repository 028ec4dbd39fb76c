// libFuzzer target: a whole scene built from arbitrary bytes (meshes with NaN/Inf/degenerate data, bad indices,
// spheres and tubes with any radius, arbitrary materials and lights, random instance transforms and camera), then
// committed and rendered at 8x8. Each input is built and rendered twice:
// - as given (any doubles, any camera matrix): no crash, no sanitizer report, and the checks of fuzz_checks.h
//   for any camera (three safety nets catch nothing, colours finite and >= 0, depths finite in [0, 1] and exactly
//   1 where the pixel's camera ray hits nothing);
// - tamed into the valid domain of fuzz_checks.h (the same bytes, doubles mapped to within 1e3, transforms
//   rotation x scale x translation, a vtkCamera-like camera): all four safety nets catch nothing and depth agrees
//   with an independent intersection where the ray hits too.
#include "fuzz_bytes.h"
#include "fuzz_checks.h"
#include "image/renderer.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

using namespace whitted;

namespace {
/// The input's values; tame: doubles mapped into the valid domain (fuzz_checks.h), non-finite ones to 0.
struct Reader : whitted_fuzz::Bytes {
  bool tame = false;
  Reader(const uint8_t* data, size_t size, bool t) : Bytes(data, size), tame(t) {}
  double d() {
    const double x = Bytes::d();
    return !tame ? x : std::isfinite(x) ? std::fmod(x, 1e3) : 0.0;
  }
  /// A radius: tamed, a positive radius is at least 1e-9 (0 and negative ones stay invalid input): 1e-12 of the
  /// coordinates (1e3 here), where the tube test still finds every hit exactly (Tube.ThinLongTubeExactNearItsEnds;
  /// thinner tubes approach the coordinates' rounding and may miss rays, never hit off their surface).
  double radius() {
    const double x = d();
    return tame && x > 0.0 ? std::max(x, 1e-9) : x;
  }
  Vec3 v3() {  // named locals: the three reads happen in this order
    double a = d(), b = d(), c = d();
    return Vec3(a, b, c);
  }
};

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
      s.radii.push_back(r.radius());
    }
    return scene.addSpheres(std::move(s));
  } else {
    TubeSet c;
    for (int i = 0; i < count + 1; ++i) {
      c.p0.push_back(r.v3());
      c.p1.push_back(r.v3());
    }
    c.radii.push_back(r.radius());
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

/// Identity, or an affine transform with any values (tame: a translation within 1e3 times a rotation times
/// scales in [1e-3, 1e3], from the same 12 values).
Mat4 randomTransform(Reader& r) {
  Mat4 xf(1.0);
  if (r.get<uint8_t>() & 1)
    for (int c = 0; c < 4; ++c)
      for (int k = 0; k < 3; ++k) xf[c][k] = r.d();
  if (!r.tame || xf == Mat4(1.0)) return xf;
  const Vec3 axis(xf[0]), scale(xf[1]), move(xf[3]);
  Mat4 t = glm::translate(Mat4(1.0), move);
  if (glm::length(axis) > 0.0) t = glm::rotate(t, xf[2][0], glm::normalize(axis));
  return glm::scale(t, Vec3(std::pow(10.0, scale.x / 1e3 * 3.0), std::pow(10.0, scale.y / 1e3 * 3.0),
                            std::pow(10.0, scale.z / 1e3 * 3.0)));
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

/// Renders 8x8 with the input's camera and settings and checks the frame (fuzz_checks.h). As given: any
/// view-projection matrix; tamed: a vtkCamera-like camera from the same values.
void renderAndCheck(Reader& r, const Scene& scene) {
  Mat4 vp(1.0);
  double v[16];
  for (int c = 0; c < 4; ++c)
    for (int k = 0; k < 4; ++k) vp[c][k] = v[c * 4 + k] = r.Bytes::d();
  const uint8_t cameraBits = r.get<uint8_t>();
  if (cameraBits & 1) vp = Mat4(1.0);
  const Camera camera = r.tame ? whitted_fuzz::tameCamera(v, cameraBits & 2) : Camera::fromViewProjection(vp);
  RenderSettings rs;
  rs.threads = 1;
  rs.samplesPerPixel = 1 + r.get<uint8_t>() % 3;
  rs.integrator.maxDepth = r.get<uint8_t>() % 8;
  rs.integrator.fresnel = r.get<uint8_t>() & 1;
  rs.integrator.beerLambert = r.get<uint8_t>() & 1;
  FrameBuffer fb;
  const FrameStats fs = render(scene, camera, rs, 8, 8, fb);
  whitted_fuzz::checkFrame(scene, camera, rs.samplesPerPixel, r.tame, fs, fb);
}

void buildRenderAndCheck(const uint8_t* data, size_t size, bool tame) {
  Reader r{data, size, tame};
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
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  buildRenderAndCheck(data, size, false);
  buildRenderAndCheck(data, size, true);
  whitted_fuzz::endOfInput();
  return 0;
}
