#include "bench_scenes.h"

#include "scenes/stiff_scenes.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>

namespace whitted::bench {

namespace {

double toFloat(double x) {
  return whitted::roundToFloat(x);  // not double(float(x)): GCC 12 folds that to x here (core/util/math.h)
}
Vec3 toFloat(const Vec3& v) {
  return Vec3(toFloat(v.x), toFloat(v.y), toFloat(v.z));
}

/// Deterministic uniform number in [0,1) from an index and a stream.
double uniform(uint32_t i, uint32_t stream) {
  return double(hashU32(i, stream, 7u, 11u)) * (1.0 / 4294967296.0);
}

/// Gaussian from two uniforms (Box-Muller).
double gaussian(uint32_t i, uint32_t stream) {
  double u1 = std::max(1e-12, uniform(i, stream)), u2 = uniform(i, stream + 1000u);
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);
}

/// A cool-to-warm colour map (ParaView's default, approximated piecewise linearly) for s in [0,1].
Color4 coolWarm(double s) {
  s = std::clamp(s, 0.0, 1.0);
  const Color c0(0.23f, 0.30f, 0.75f), c1(0.87f, 0.87f, 0.87f), c2(0.71f, 0.02f, 0.15f);
  Color c = s < 0.5 ? glm::mix(c0, c1, float(2.0 * s)) : glm::mix(c1, c2, float(2.0 * s - 1.0));
  return Color4(c, 1.0f);
}

/// A flat rectangle (two triangles) at height y spanning [x0,x1] x [z0,z1], normal +y.
TriangleMesh floorQuad(double y, double x0, double x1, double z0, double z1) {
  return makeGrid(Vec3(x0, y, z1), Vec3(x1 - x0, 0.0, 0.0), Vec3(0.0, 0.0, z0 - z1), 1, 1);
}

void buildIsosurface(const TriangleMesh& meshIn, BenchScene& out) {
  TriangleMesh mesh = meshIn;
  Bounds3 b;
  for (const Vec3& p : mesh.positions) b.extend(p);
  Material m;  // VTK defaults (ambient 0, diffuse 1) plus a little specular, as a ParaView user would set
  m.diffuseColor = m.ambientColor = Color(0.9f, 0.75f, 0.55f);
  m.ambient = 0.1f;
  m.diffuse = 0.9f;
  m.specular = 0.2f;
  m.specularPower = 30.0f;
  out.mainMaterial = m;
  uint32_t obj = out.scene.addMesh(std::move(mesh));
  out.scene.addInstance(obj, Mat4(1.0), out.scene.addMaterial(m));
  out.camera = frameBounds(b, glm::normalize(Vec3(1.0, 0.6, 1.4)), Vec3(0.0, 1.0, 0.0), 30.0, 1.15);
  // Key light above and to the left of the camera (a headlight would cast no visible shadow)
  Light key;
  key.positional = false;
  key.position = b.center() + b.diagonal() * glm::normalize(Vec3(-0.3, 1.0, 0.9));
  key.focalPoint = b.center();
  key.coneAngle = 180.0;
  out.scene.lights().push_back(key);
  // Fill light from the camera (VTK's headlight, dimmer), casting no shadows
  out.headlight = int(out.scene.lights().size());
  Light fill;
  fill.positional = false;
  fill.position = out.camera.eye;
  fill.focalPoint = out.camera.focal;
  fill.intensity = 0.35f;
  fill.coneAngle = 180.0;
  fill.castShadows = false;
  out.scene.lights().push_back(fill);
  out.scene.background = Color(0.32f, 0.34f, 0.43f);  // ParaView's default background
}

void buildPoints(BenchScene& out, int count) {
  // A three-armed spiral "galaxy" of points, drawn as spheres, floating over a slightly reflective floor
  SphereSet s;
  s.radii = {0.008};
  for (int i = 0; i < count; ++i) {
    uint32_t u = uint32_t(i);
    double arm = std::floor(uniform(u, 1) * 3.0);
    double r = std::pow(uniform(u, 2), 0.6);
    double a = arm * 2.0 * kPi / 3.0 + 4.0 * r + 0.25 * gaussian(u, 3);
    double spread = 0.06 * (1.0 - 0.5 * r);
    Vec3 p(r * std::cos(a) + spread * gaussian(u, 4), 0.05 * (1.0 - r) * gaussian(u, 5) + 0.04 * gaussian(u, 6),
           r * std::sin(a) + spread * gaussian(u, 7));
    s.centers.push_back(toFloat(p));
    s.colors.push_back(coolWarm(r));
  }
  Material pm;
  pm.ambient = 0.1f;
  pm.diffuse = 0.9f;
  pm.specular = 0.3f;
  pm.specularPower = 40.0f;
  pm.colorSource = ColorSource::ScalarsAmbientAndDiffuse;
  out.mainMaterial = pm;
  out.scene.addInstance(out.scene.addSpheres(std::move(s)), Mat4(1.0), out.scene.addMaterial(pm));

  Material fm;
  fm.diffuseColor = fm.ambientColor = Color(0.6f);
  fm.ambient = 0.1f;
  fm.diffuse = 0.8f;
  fm.reflectance = Color(0.3f);
  out.scene.addInstance(out.scene.addMesh(floorQuad(-0.3, -1.6, 1.6, -1.6, 1.6)), Mat4(1.0), out.scene.addMaterial(fm));
  out.scene.lights().push_back(makePointLight(Vec3(0.8, 3.0, 1.2)));
  out.scene.background = Color(0.1f, 0.1f, 0.15f);
  out.camera.eye = Vec3(0.0, 1.5, 2.4);
  out.camera.focal = Vec3(0.0, -0.1, 0.0);
  out.camera.up = Vec3(0.0, 1.0, 0.0);
  out.camera.viewAngle = 35.0;
}

void buildTubes(BenchScene& out, int lines, int steps) {
  // Streamlines of the ABC (Arnold-Beltrami-Childress) flow, integrated with RK4, drawn as tubes
  const double A = std::sqrt(3.0), B = std::sqrt(2.0), C = 1.0;
  auto vel = [&](const Vec3& p) {
    return Vec3(A * std::sin(p.z) + C * std::cos(p.y), B * std::sin(p.x) + A * std::cos(p.z),
                C * std::sin(p.y) + B * std::cos(p.x));
  };
  TubeSet c;
  c.radii = {0.025};
  const double dt = 0.02, twoPi = 2.0 * kPi;
  // The flow is periodic: fold every point into the [0, 2 pi)^3 cell and break the tube where it wraps
  auto fold = [&](const Vec3& p, glm::dvec3& cell) {
    cell = glm::floor(p / twoPi);
    return toFloat(p - cell * twoPi);
  };
  for (int l = 0; l < lines; ++l) {
    Vec3 p(twoPi * uniform(uint32_t(l), 21), twoPi * uniform(uint32_t(l), 22), twoPi * uniform(uint32_t(l), 23));
    glm::dvec3 cellP, cellQ;
    for (int s = 0; s < steps; ++s) {
      Vec3 k1 = vel(p), k2 = vel(p + 0.5 * dt * k1), k3 = vel(p + 0.5 * dt * k2), k4 = vel(p + dt * k3);
      Vec3 q = p + dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
      Vec3 fp = fold(p, cellP), fq = fold(q, cellQ);
      if (cellP == cellQ) {
        c.p0.push_back(fp);
        c.p1.push_back(fq);
        c.colors0.push_back(coolWarm(glm::length(vel(p)) / 4.0));
        c.colors1.push_back(coolWarm(glm::length(vel(q)) / 4.0));
      }
      p = q;
    }
  }
  Material tm;
  tm.ambient = 0.1f;
  tm.diffuse = 0.8f;
  tm.specular = 0.4f;
  tm.specularPower = 50.0f;
  tm.reflectance = Color(0.15f);
  tm.colorSource = ColorSource::ScalarsAmbientAndDiffuse;
  out.mainMaterial = tm;
  out.scene.addInstance(out.scene.addTubes(std::move(c)), Mat4(1.0), out.scene.addMaterial(tm));
  out.scene.lights().push_back(makePointLight(Vec3(-4.0, 14.0, 12.0)));
  out.scene.background = Color(0.32f, 0.34f, 0.43f);
  Bounds3 b{Vec3(0.0), Vec3(twoPi)};
  out.camera = frameBounds(b, glm::normalize(Vec3(1.0, 0.7, 1.5)), Vec3(0.0, 1.0, 0.0), 30.0, 1.2);
}

void buildGlassMirror(BenchScene& out) {
  // Checkerboard floor between two facing mirrors, with a 3 x 3 grid of alternating glass and mirror balls:
  // every primary ray that hits a ball or a wall spawns a long chain of reflections and refractions
  Color4 c0(0.9f, 0.9f, 0.9f, 1.0f), c1(0.15f, 0.15f, 0.2f, 1.0f);
  Material floorMat;
  floorMat.ambient = 0.15f;
  floorMat.diffuse = 0.85f;
  floorMat.colorSource = ColorSource::ScalarsAmbientAndDiffuse;
  floorMat.reflectance = Color(0.2f);
  out.scene.addInstance(
      out.scene.addMesh(makeGrid(Vec3(-4.0, 0.0, 4.0), Vec3(8.0, 0.0, 0.0), Vec3(0.0, 0.0, -8.0), 16, 16, &c0, &c1)),
      Mat4(1.0), out.scene.addMaterial(floorMat));

  Material wall;
  wall.diffuseColor = wall.ambientColor = Color(0.7f, 0.8f, 0.9f);
  wall.ambient = 0.02f;
  wall.diffuse = 0.08f;
  wall.reflectance = Color(0.88f, 0.9f, 0.92f);
  uint32_t wallMat = out.scene.addMaterial(wall);
  // Left wall x = -4 facing +x, right wall x = +4 facing -x (both 8 x 4)
  out.scene.addInstance(
      out.scene.addMesh(makeGrid(Vec3(-4.0, 0.0, 4.0), Vec3(0.0, 0.0, -8.0), Vec3(0.0, 4.0, 0.0), 1, 1)), Mat4(1.0),
      wallMat);
  out.scene.addInstance(
      out.scene.addMesh(makeGrid(Vec3(4.0, 0.0, -4.0), Vec3(0.0, 0.0, 8.0), Vec3(0.0, 4.0, 0.0), 1, 1)), Mat4(1.0),
      wallMat);

  Material glass;
  glass.diffuseColor = glass.ambientColor = Color(0.9f);
  glass.ambient = 0.0f;
  glass.diffuse = 0.0f;
  glass.specular = 0.8f;
  glass.specularPower = 100.0f;
  glass.reflectance = Color(0.1f);
  glass.transmittance = Color(0.88f, 0.9f, 0.92f);
  glass.ior = 1.5f;
  Material mirror;
  mirror.diffuseColor = mirror.ambientColor = Color(0.9f, 0.8f, 0.5f);
  mirror.ambient = 0.05f;
  mirror.diffuse = 0.1f;
  mirror.specular = 0.6f;
  mirror.specularPower = 60.0f;
  mirror.reflectance = Color(0.9f, 0.85f, 0.6f);
  uint32_t glassMat = out.scene.addMaterial(glass), mirrorMat = out.scene.addMaterial(mirror);
  out.mainMaterial = glass;
  SphereSet glassBalls, mirrorBalls;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      Vec3 c(-2.0 + 2.0 * i, 0.7, -2.0 + 2.0 * j);
      ((i + j) % 2 ? mirrorBalls : glassBalls).centers.push_back(c);
    }
  glassBalls.radii = {0.7};
  mirrorBalls.radii = {0.7};
  out.scene.addInstance(out.scene.addSpheres(std::move(glassBalls)), Mat4(1.0), glassMat);
  out.scene.addInstance(out.scene.addSpheres(std::move(mirrorBalls)), Mat4(1.0), mirrorMat);

  out.scene.lights().push_back(makePointLight(Vec3(1.0, 6.0, 3.0)));
  out.scene.background = Color(0.05f, 0.05f, 0.08f);
  out.camera.eye = Vec3(-1.2, 2.6, 6.5);
  out.camera.focal = Vec3(0.3, 0.6, -0.5);
  out.camera.up = Vec3(0.0, 1.0, 0.0);
  out.camera.viewAngle = 45.0;
}

void buildVolume(BenchScene& out, int n, bool skip) {
  // An n^3 grid over [-1, 1]^3: a Gaussian blob times a ripple (a wavelet-like field, 0..~280), opaque above 90 and
  // transparent below (the corners and rim: empty space), over a mirror floor that shows it from below
  const int dims[3] = {n, n, n};
  std::vector<float> s(std::size_t(n) * n * n);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double x = -1.0 + 2.0 * i / (n - 1), y = -1.0 + 2.0 * j / (n - 1), z = -1.0 + 2.0 * k / (n - 1);
        const double blob = std::exp(-(x * x + y * y + z * z) / (2.0 * 0.32 * 0.32));
        s[(std::size_t(k) * n + j) * n + i] =
            float(255.0 * blob * (1.0 + 0.1 * std::sin(17.0 * x) * std::sin(13.0 * y) * std::cos(11.0 * z)));
      }
  Volume v;
  v.grid = VolumeGrid::fromScalars(dims, s.data());
  v.grid.origin = Vec3(-1.0);
  v.grid.spacing = Vec3(2.0 / (n - 1));
  v.transfer.opacityX = {0.0f, 90.0f, 180.0f, 280.0f};
  v.transfer.opacityY = {0.0f, 0.0f, 0.05f, 0.2f};
  v.transfer.colorX = {90.0f, 180.0f, 280.0f};
  v.transfer.colorY = {Color(0.23f, 0.3f, 0.75f), Color(0.87f, 0.87f, 0.87f), Color(0.71f, 0.02f, 0.15f)};
  v.transfer.unitDistance = 0.05;
  v.skipEmptySpace = skip;
  out.scene.addVolume(std::move(v));
  Material floor;
  floor.diffuseColor = floor.ambientColor = Color(0.6f, 0.6f, 0.65f);
  floor.reflectance = Color(0.5f);
  out.scene.addInstance(out.scene.addMesh(floorQuad(-1.2, -3.0, 3.0, -3.0, 3.0)), Mat4(1.0),
                        out.scene.addMaterial(floor));
  out.mainMaterial = floor;
  out.scene.lights().push_back(makePointLight(Vec3(2.0, 4.0, 3.0)));
  out.scene.background = Color(0.32f, 0.34f, 0.43f);
  out.camera.eye = Vec3(2.2, 1.3, 3.4);
  out.camera.focal = Vec3(0.0, -0.2, 0.0);
  out.camera.up = Vec3(0.0, 1.0, 0.0);
  out.camera.viewAngle = 35.0;
}

/// The volume of testing/benchmark/vtk_volume_bench.py with its effects off, for paired runs without VTK: vtkRTAnalyticSource's
/// field with its defaults (Maximum 255, standard deviation 0.5, frequencies 60 30 40, magnitudes 10 18 5) over the
/// extent -n/2 .. n/2 - 1, spacing 1; cool-warm colour over the range, opacity 0 up to 130 and 0.2 at the top per
/// unit distance 1; sample distance 1; no surface, no light (with shade: the script's light); the script's camera.
/// shade: Shade on (VTK's defaults) under the script's scene light.
void buildWavelet(BenchScene& out, int n, bool shade) {
  const int half = n / 2, dims[3] = {n, n, n};
  std::vector<float> s(std::size_t(n) * n * n);
  const double scale = 1.0 / double(n - 1), inv2s2 = 1.0 / (2.0 * 0.5 * 0.5);
  float lo = std::numeric_limits<float>::infinity(), hi = -lo;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double x = -double(i - half) * scale, y = -double(j - half) * scale, z = -double(k - half) * scale;
        const float v = float(255.0 * std::exp(-(x * x + y * y + z * z) * inv2s2) + 10.0 * std::sin(60.0 * x) +
                              18.0 * std::sin(30.0 * y) + 5.0 * std::cos(40.0 * z));
        s[(std::size_t(k) * n + j) * n + i] = v;
        lo = std::min(lo, v);
        hi = std::max(hi, v);
      }
  Volume v;
  v.grid = VolumeGrid::fromScalars(dims, s.data());
  v.grid.origin = Vec3(-double(half));
  v.transfer.opacityX = {lo, 130.0f, hi};
  v.transfer.opacityY = {0.0f, 0.0f, 0.2f};
  v.transfer.colorX = {lo, 0.5f * (lo + hi), hi};
  v.transfer.colorY = {Color(0.23f, 0.3f, 0.75f), Color(0.87f, 0.87f, 0.87f), Color(0.71f, 0.02f, 0.15f)};
  v.transfer.unitDistance = 1.0;
  v.sampleDistance = 1.0;
  v.transfer.shade = shade;
  out.scene.addVolume(std::move(v));
  if (shade) {  // the script's scene light: directional, from (-0.6, 3, 1.5) x half toward the centre
    Light l;
    l.position = Vec3(-0.6 * half, 3.0 * half, 1.5 * half);
    out.scene.lights().push_back(l);
    out.scene.volumeAmbient = Color(0.0f);  // VTK: the sum of the lights' ambient colours (black)
  }
  out.scene.background = Color(0.32f, 0.34f, 0.43f);
  out.camera.eye = Vec3(2.4 * half, 1.8 * half, 4.8 * half);
  out.camera.focal = Vec3(0.0);
  out.camera.up = Vec3(0.0, 1.0, 0.0);
  out.camera.viewAngle = 30.0;
}

/// Rounds every coordinate and radius of every object to single precision (see the header comment).
void roundSceneToFloat(Scene& scene) {
  for (uint32_t o = 0; o < scene.objectCount(); ++o) {
    switch (scene.objectType(o)) {
      case GeometryType::Triangles: {
        TriangleMesh m = scene.mesh(o);
        roundToFloat(m);
        scene.setMesh(o, std::move(m));
        break;
      }
      case GeometryType::Spheres: {
        SphereSet s = scene.spheres(o);
        for (Vec3& c : s.centers) c = toFloat(c);
        for (double& r : s.radii) r = toFloat(r);
        scene.setSpheres(o, std::move(s));
        break;
      }
      case GeometryType::Tubes: {
        TubeSet c = scene.tubes(o);
        for (Vec3& p : c.p0) p = toFloat(p);
        for (Vec3& p : c.p1) p = toFloat(p);
        for (double& r : c.radii) r = toFloat(r);
        scene.setTubes(o, std::move(c));
        break;
      }
    }
  }
}

bool buildNamed(const std::string& name, const std::vector<std::string>& dataDirs, BenchScene& out, std::string& error);

}  // namespace

bool buildBenchScene(const std::string& name, const std::vector<std::string>& dataDirs, BenchScene& out,
                     std::string& error) {
  if (!buildNamed(name, dataDirs, out, error)) return false;
  roundSceneToFloat(out.scene);
  return true;
}

bool readMeshFile(const std::string& path, TriangleMesh& mesh, std::string& error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    error = "cannot open " + path;
    return false;
  }
  char magic[8];
  uint32_t head[4];
  in.read(magic, 8);
  in.read(reinterpret_cast<char*>(head), sizeof head);
  if (!in || std::memcmp(magic, "WHTMESH1", 8) != 0) {
    error = path + " is not a WHTMESH1 file";
    return false;
  }
  uint32_t nv = head[0], nt = head[1];
  bool normals = head[2] & 1u;
  std::vector<float> pos(std::size_t(nv) * 3), nrm(normals ? std::size_t(nv) * 3 : 0);
  std::vector<uint32_t> idx(std::size_t(nt) * 3);
  in.read(reinterpret_cast<char*>(pos.data()), std::streamsize(pos.size() * sizeof(float)));
  if (normals) in.read(reinterpret_cast<char*>(nrm.data()), std::streamsize(nrm.size() * sizeof(float)));
  in.read(reinterpret_cast<char*>(idx.data()), std::streamsize(idx.size() * sizeof(uint32_t)));
  if (!in) {
    error = path + " is truncated";
    return false;
  }
  mesh = TriangleMesh{};
  mesh.positions.resize(nv);
  for (uint32_t i = 0; i < nv; ++i) mesh.positions[i] = Vec3(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]);
  if (normals) {
    mesh.normals.resize(nv);
    for (uint32_t i = 0; i < nv; ++i) mesh.normals[i] = Vec3f(nrm[3 * i], nrm[3 * i + 1], nrm[3 * i + 2]);
  }
  mesh.triangles.resize(nt);
  for (uint32_t i = 0; i < nt; ++i) mesh.triangles[i] = glm::uvec3(idx[3 * i], idx[3 * i + 1], idx[3 * i + 2]);
  return true;
}

bool writeMeshFile(const std::string& path, const TriangleMesh& mesh) {
  std::ofstream out(path, std::ios::binary);
  if (!out) return false;
  bool normals = mesh.normals.size() == mesh.positions.size() && !mesh.normals.empty();
  uint32_t head[4] = {uint32_t(mesh.positions.size()), uint32_t(mesh.triangles.size()), normals ? 1u : 0u, 0u};
  out.write("WHTMESH1", 8);
  out.write(reinterpret_cast<const char*>(head), sizeof head);
  for (const Vec3& p : mesh.positions) {
    float f[3] = {float(p.x), float(p.y), float(p.z)};
    out.write(reinterpret_cast<const char*>(f), sizeof f);
  }
  if (normals) out.write(reinterpret_cast<const char*>(mesh.normals.data()), std::streamsize(mesh.normals.size() * 12));
  out.write(reinterpret_cast<const char*>(mesh.triangles.data()), std::streamsize(mesh.triangles.size() * 12));
  return bool(out);
}

void roundToFloat(TriangleMesh& m) {
  for (Vec3& p : m.positions) p = toFloat(p);
}

CameraSpec frameBounds(const Bounds3& b, const Vec3& dir, const Vec3& up, double viewAngle, double zoom) {
  // vtkRenderer::ResetCamera: distance so the bounding sphere fits the view angle
  CameraSpec c;
  double radius = 0.5 * b.diagonal();
  double dist = radius / std::sin(0.5 * viewAngle * kPi / 180.0) / zoom;
  c.focal = b.center();
  c.eye = c.focal + dist * dir;
  c.up = up;
  c.viewAngle = viewAngle;
  return c;
}

std::vector<std::string> benchSceneNames() {
  return {"classic", "iso60k", "iso1m", "iso4m", "points100k", "tubes", "glassmirror"};
}

std::string meshFileFor(const std::string& name) {
  if (name == "iso60k") return "wavelet_60k.whtmesh";
  if (name == "iso1m") return "wavelet_1m.whtmesh";
  if (name == "iso4m") return "wavelet_4m.whtmesh";
  return "";
}

namespace {
bool buildNamed(const std::string& name, const std::vector<std::string>& dataDirs, BenchScene& out,
                std::string& error) {
  out.name = name;
  if (name == "classic") {
    buildClassicScene(out.scene, out.camera, 0);
    out.mainMaterial = out.scene.material(1);
    out.description = "Whitted's classic scene: checkerboard floor (280 triangles), mirror and glass spheres";
    return true;
  }
  std::string file = meshFileFor(name);
  if (!file.empty()) {
    TriangleMesh mesh;
    std::string lastError = "no data directory given";
    for (const std::string& d : dataDirs) {
      if (readMeshFile(d + "/" + file, mesh, lastError)) {
        std::size_t nt = mesh.triangles.size();
        buildIsosurface(mesh, out);
        out.description = "vtkRTAnalyticSource contoured at 157: " + std::to_string(nt) + " triangles";
        return true;
      }
    }
    error = "cannot read " + file + " (" + lastError + "); generate it with gen_wavelet.py";
    return false;
  }
  if (name == "points100k" || name == "points-small") {
    int n = name == "points100k" ? 100000 : 5000;
    buildPoints(out, n);
    out.description = std::to_string(n) + " points as spheres (spiral), reflective floor";
    return true;
  }
  if (name == "tubes" || name == "tubes-small") {
    bool big = name == "tubes";
    buildTubes(out, big ? 250 : 25, big ? 400 : 100);
    out.description = std::to_string(out.scene.tubes(0).p0.size()) + " tubes along ABC-flow streamlines";
    return true;
  }
  if (name == "glassmirror") {
    buildGlassMirror(out);
    out.description = "glass and mirror balls between two facing mirrors (deep recursion)";
    return true;
  }
  if (name == "wavelet256" || name == "wavelet64" || name == "wavelet256-shade" || name == "wavelet64-shade") {
    const bool shade = name.find("-shade") != std::string::npos;
    const int n = name.compare(0, 10, "wavelet256") == 0 ? 256 : 64;
    buildWavelet(out, n, shade);
    out.description = std::to_string(n) + "^3 vtkRTAnalyticSource-like volume of vtk_volume_bench.py, effects off" +
                      (shade ? ", Shade on" : "");
    return true;
  }
  if (name == "volume256" || name == "volume64" || name == "volume256-noskip" || name == "volume64-noskip") {
    const int n = name.compare(0, 9, "volume256") == 0 ? 256 : 64;
    const bool skip = name.find("noskip") == std::string::npos;
    buildVolume(out, n, skip);
    out.description = std::to_string(n) + "^3 volume (a blob, transparent rim) over a mirror floor" +
                      (skip ? "" : ", without empty-space skipping");
    return true;
  }
  // Stiff scenes of the error estimate's calibration (core/scenes/stiff_scenes.h)
  struct Stiff {
    const char* name;
    void (*build)(Scene&, CameraSpec&);
    const char* description;
  };
  static const Stiff stiff[] = {
      {"mirrors", buildFacingMirrorsScene, "two facing mirrors (kr 0.9), up to ~20 bounces"},
      {"nestedglass", buildNestedGlassScene, "glass sphere in a glass sphere (kr + kt = 1), opaque core"},
      {"lightinglass", buildLightInGlassScene, "point light inside two glass boxes (shadow transmittance 0.12)"},
      {"fence", buildFenceScene, "mirror floor, glass sphere, a fence of thin posts, a cube, two lights"},
      {"text", buildTextScene, "a page of seven-segment glyphs with strokes a third of a pixel wide"}};
  for (const Stiff& st : stiff)
    if (name == st.name) {
      st.build(out.scene, out.camera);
      out.description = st.description;
      return true;
    }
  error = "unknown scene '" + name + "'";
  return false;
}
}  // namespace

}  // namespace whitted::bench
