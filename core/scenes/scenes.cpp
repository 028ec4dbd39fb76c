#include "scenes/scenes.h"

#include <algorithm>

namespace whitted {

Camera CameraSpec::make(double aspect, const Bounds3& b) const {
  double n = nearDist, f = farDist;
  if (!(n > 0.0) || !(f > n)) {
    // Like vtkRenderer::ResetCameraClippingRange: distances of the bounds' corners along the view direction
    Vec3 dir = glm::normalize(focal - eye);
    double lo = kInfinity, hi = -kInfinity;
    for (int i = 0; i < 8 && b.valid(); ++i) {
      Vec3 c((i & 1) ? b.hi.x : b.lo.x, (i & 2) ? b.hi.y : b.lo.y, (i & 4) ? b.hi.z : b.lo.z);
      double d = glm::dot(c - eye, dir);
      lo = std::min(lo, d);
      hi = std::max(hi, d);
    }
    if (!b.valid()) lo = 0.1, hi = 1000.0;
    hi = hi * 1.01 + 1e-12;
    lo = std::max(lo * 0.99, hi * 1e-4);
    n = lo;
    f = hi;
  }
  return Camera::perspective(eye, focal, up, viewAngle, aspect, n, f);
}

TriangleMesh makeSphereMesh(const Vec3& center, double radius, int thetaRes, int phiRes) {
  TriangleMesh m;
  thetaRes = std::max(3, thetaRes);
  phiRes = std::max(3, phiRes);
  // Single pole vertices (as vtkSphereSource) so the mesh is closed: 0 = north (+y), 1 = south (-y)
  m.positions = {center + Vec3(0, radius, 0), center - Vec3(0, radius, 0)};
  m.normals = {Vec3f(0, 1, 0), Vec3f(0, -1, 0)};
  for (int j = 1; j < phiRes; ++j) {
    double phi = kPi * j / phiRes;
    for (int i = 0; i < thetaRes; ++i) {
      double th = 2.0 * kPi * i / thetaRes;
      Vec3 n(std::sin(phi) * std::cos(th), std::cos(phi), std::sin(phi) * std::sin(th));
      m.positions.push_back(center + radius * n);
      m.normals.push_back(Vec3f(n));
    }
  }
  auto ring = [&](int j, int i) { return uint32_t(2 + (j - 1) * thetaRes + (i % thetaRes)); };
  for (int i = 0; i < thetaRes; ++i) {
    // Counter-clockwise seen from outside
    m.triangles.push_back({0u, ring(1, i + 1), ring(1, i)});
    for (int j = 1; j < phiRes - 1; ++j) {
      m.triangles.push_back({ring(j, i), ring(j, i + 1), ring(j + 1, i)});
      m.triangles.push_back({ring(j, i + 1), ring(j + 1, i + 1), ring(j + 1, i)});
    }
    m.triangles.push_back({ring(phiRes - 1, i), ring(phiRes - 1, i + 1), 1u});
  }
  return m;
}

TriangleMesh makeGrid(const Vec3& origin, const Vec3& u, const Vec3& v, int nu, int nv, const Color4* c0,
                      const Color4* c1) {
  TriangleMesh m;
  for (int j = 0; j <= nv; ++j)
    for (int i = 0; i <= nu; ++i) {
      m.positions.push_back(origin + u * (double(i) / nu) + v * (double(j) / nv));
      m.texcoords.push_back(Vec2f(float(i) / nu, float(j) / nv));
    }
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      uint32_t a = uint32_t(j * (nu + 1) + i), b = a + 1, c = a + uint32_t(nu + 1), d = c + 1;
      m.triangles.push_back({a, b, d});
      m.triangles.push_back({a, d, c});
      if (c0 && c1) {
        const Color4& col = ((i + j) % 2 == 0) ? *c0 : *c1;
        m.triangleColors.push_back(col);
        m.triangleColors.push_back(col);
      }
    }
  return m;
}

const ClassicSceneDescription& classicSceneDescription() {
  static const ClassicSceneDescription d = [] {
    ClassicSceneDescription c;
    // Checkerboard floor (red / yellow as in Whitted 1980) in the plane y = 0, normal +y
    c.floor.origin = Vec3(-5.0, 0.0, 3.0);
    c.floor.point1 = Vec3(5.0, 0.0, 3.0);
    c.floor.point2 = Vec3(-5.0, 0.0, -11.0);
    c.floor.cellsX = 10;
    c.floor.cellsY = 14;
    c.floor.color0 = Vec3(0.85, 0.1, 0.1);
    c.floor.color1 = Vec3(0.95, 0.85, 0.1);
    c.floor.ambient = 0.15;
    c.floor.diffuse = 0.85;
    // Mirror sphere (back right) and glass sphere (front left)
    c.mirror = {Vec3(0.9, 1.1, -3.6), 1.1, Vec3(0.7), 0.05, 0.15, 0.6, 60.0, 0.8, 0.0, 1.0};
    c.glass = {Vec3(-0.7, 0.8, -1.4), 0.8, Vec3(0.9), 0.0, 0.0, 0.8, 100.0, 0.1, 0.9, 1.5};
    c.lightPosition = Vec3(4.0, 7.0, 3.0);
    c.background = Vec3(0.3, 0.5, 0.85);
    c.camera.eye = Vec3(0.0, 1.8, 4.0);
    c.camera.focal = Vec3(0.0, 0.9, -2.5);
    c.camera.up = Vec3(0.0, 1.0, 0.0);
    c.camera.viewAngle = 40.0;
    return c;
  }();
  return d;
}

void buildClassicScene(Scene& scene, CameraSpec& cam, int sphereSubdivisions) {
  const ClassicSceneDescription& d = classicSceneDescription();

  // Floor: per-triangle checker colours
  Color4 c0(Color(d.floor.color0), 1.0f), c1(Color(d.floor.color1), 1.0f);
  TriangleMesh floor = makeGrid(d.floor.origin, d.floor.point1 - d.floor.origin, d.floor.point2 - d.floor.origin,
                                d.floor.cellsX, d.floor.cellsY, &c0, &c1);
  Material floorMat;
  floorMat.ambient = float(d.floor.ambient);
  floorMat.diffuse = float(d.floor.diffuse);
  floorMat.colorSource = ColorSource::ScalarsAmbientAndDiffuse;
  uint32_t floorObj = scene.addMesh(std::move(floor));
  scene.addInstance(floorObj, Mat4(1.0), scene.addMaterial(floorMat));

  // Spheres: analytic, or UV-sphere meshes
  for (const ClassicSceneDescription::Ball* b : {&d.mirror, &d.glass}) {
    Material m;
    m.diffuseColor = m.ambientColor = Color(b->color);
    m.ambient = float(b->ambient);
    m.diffuse = float(b->diffuse);
    m.specular = float(b->specular);
    m.specularPower = float(b->specularPower);
    m.reflectance = Color(float(b->reflectance));
    m.transmittance = Color(float(b->transmittance));
    m.ior = float(b->ior);
    uint32_t obj;
    if (sphereSubdivisions > 0) {
      obj = scene.addMesh(makeSphereMesh(b->center, b->radius, 2 * sphereSubdivisions, sphereSubdivisions));
    } else {
      SphereSet s;
      s.centers = {b->center};
      s.radii = {b->radius};
      obj = scene.addSpheres(std::move(s));
    }
    scene.addInstance(obj, Mat4(1.0), scene.addMaterial(m));
  }

  // Light, background, camera
  Light l;
  l.positional = true;
  l.position = d.lightPosition;
  l.focalPoint = Vec3(0.0);
  l.coneAngle = 180.0;
  scene.lights().push_back(l);
  scene.background = Color(d.background);
  cam.eye = d.camera.eye;
  cam.focal = d.camera.focal;
  cam.up = d.camera.up;
  cam.viewAngle = d.camera.viewAngle;
}

std::vector<std::string> builtinSceneNames() {
  return {"classic", "classic-mesh", "classic-fog"};
}

void addFogVolume(Scene& scene, int n) {
  // A smooth blob with ripples (like vtkRTAnalyticSource's wavelet) over the middle of the scene's box: seen
  // directly, through the glass sphere, in the mirror sphere, and casting a shadow on the floor
  scene.commit();
  const Bounds3 b = scene.bounds();
  const Vec3 c = b.center(), e = b.hi - b.lo;
  const Vec3 lo = c - 0.3 * e, hi = c + 0.3 * e;
  std::vector<float> s(std::size_t(n) * std::size_t(n) * std::size_t(n));
  std::size_t k = 0;
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const Vec3 u = Vec3(x, y, z) / double(n - 1) * 2.0 - 1.0;
        s[k++] = float(std::exp(-2.0 * glm::dot(u, u)) * (0.8 + 0.2 * std::sin(9.0 * u.x) * std::cos(7.0 * u.y)));
      }
  Volume v;
  const int dims[3] = {n, n, n};
  v.grid = VolumeGrid::fromScalars(dims, s.data());
  v.grid.origin = lo;
  v.grid.spacing = (hi - lo) / double(n - 1);
  v.transfer.colorX = {0.0f, 0.5f, 1.0f};
  v.transfer.colorY = {Color(0.1f, 0.2f, 0.9f), Color(0.9f, 0.9f, 0.9f), Color(1.0f, 0.5f, 0.1f)};
  v.transfer.opacityX = {0.1f, 0.9f};
  v.transfer.opacityY = {0.0f, 0.8f};
  v.transfer.unitDistance = glm::length(hi - lo) / 30.0;
  scene.addVolume(std::move(v));
}

bool buildBuiltinScene(const std::string& name, Scene& scene, CameraSpec& cam) {
  if (name == "classic") {
    buildClassicScene(scene, cam, 0);
    return true;
  }
  if (name == "classic-mesh") {
    buildClassicScene(scene, cam, 48);
    return true;
  }
  if (name == "classic-fog") {
    buildClassicScene(scene, cam, 0);
    addFogVolume(scene, 64);
    return true;
  }
  return false;
}

}  // namespace whitted
