#include "scenes/stiff_scenes.h"

namespace whitted {

namespace {

Material diffuseMaterial(Color c, float kr = 0.0f) {
  Material m;
  m.ambient = 0.05f;
  m.diffuse = 0.9f;
  m.diffuseColor = c;
  m.specular = 0.3f;
  m.specularPower = 20.0f;
  m.reflectance = Color(kr);
  return m;
}

Material glass(float kt, float kr, float ior, float opacity) {
  Material m = diffuseMaterial(Color(0.9f, 0.95f, 1.0f));
  m.opacity = opacity;
  m.transmittance = Color(kt);
  m.reflectance = Color(kr);
  m.ior = ior;
  return m;
}

void addMesh(Scene& s, TriangleMesh mesh, const Material& m) {
  s.addInstance(s.addMesh(std::move(mesh)), Mat4(1.0), s.addMaterial(m));
}

void addSphere(Scene& s, const Vec3& c, double r, const Material& m) {
  SphereSet set;
  set.centers = {c};
  set.radii = {r};
  s.addInstance(s.addSpheres(std::move(set)), Mat4(1.0), s.addMaterial(m));
}

}  // namespace

TriangleMesh makeBoxMesh(const Vec3& lo, const Vec3& hi) {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i)
    m.positions.push_back(Vec3((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z));
  const uint32_t f[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (auto& q : f) {
    m.triangles.push_back({q[0], q[1], q[2]});
    m.triangles.push_back({q[0], q[2], q[3]});
  }
  return m;
}

Light makePointLight(const Vec3& p) {
  Light l;
  l.positional = true;
  l.position = p;
  l.focalPoint = Vec3(0.0);
  l.coneAngle = 180.0;
  return l;
}

void buildFacingMirrorsScene(Scene& s, CameraSpec& cam) {
  Material mirror = diffuseMaterial(Color(0.6f), 0.9f);
  mirror.diffuse = 0.1f;
  addMesh(s, makeGrid(Vec3(-0.5, -1, 4), Vec3(0, 0, -40), Vec3(0, 2, 0), 1, 1), mirror);
  addMesh(s, makeGrid(Vec3(0.5, -1, 4), Vec3(0, 2, 0), Vec3(0, 0, -40), 1, 1), mirror);
  addMesh(s, makeGrid(Vec3(-0.5, -1, -36), Vec3(1, 0, 0), Vec3(0, 2, 0), 1, 1), diffuseMaterial(Color(0.3f, 0.8f, 0.3f)));
  addMesh(s, makeGrid(Vec3(-0.5, -1, 4), Vec3(1, 0, 0), Vec3(0, 0, -40), 1, 1), diffuseMaterial(Color(0.8f)));
  addSphere(s, Vec3(0.1, -0.6, -3), 0.3, diffuseMaterial(Color(0.9f, 0.2f, 0.1f)));
  s.lights().push_back(makePointLight(Vec3(0, 0.8, 2)));
  s.background = Color(0.2f, 0.3f, 0.5f);
  cam.eye = Vec3(0.0, 0.0, 3.5);
  cam.focal = Vec3(0.35, -0.1, 0.0);
  cam.viewAngle = 50.0;
}

void buildNestedGlassScene(Scene& s, CameraSpec& cam) {
  addSphere(s, Vec3(0, 0, 0), 1.0, glass(0.9f, 0.1f, 1.5f, 0.05f));
  addSphere(s, Vec3(0.1, 0, 0), 0.55, glass(0.8f, 0.2f, 1.33f, 0.05f));
  addSphere(s, Vec3(0.15, -0.1, 0), 0.2, diffuseMaterial(Color(1.0f, 0.5f, 0.1f)));
  addMesh(s, makeGrid(Vec3(-4, -1.05, 4), Vec3(8, 0, 0), Vec3(0, 0, -8), 1, 1), diffuseMaterial(Color(0.7f)));
  s.lights().push_back(makePointLight(Vec3(1.5, 3, 2)));
  s.background = Color(0.3f, 0.35f, 0.45f);
  cam.eye = Vec3(0.4, 0.8, 3.2);
  cam.focal = Vec3(0, -0.1, 0);
  cam.viewAngle = 40.0;
}

void buildLightInGlassScene(Scene& s, CameraSpec& cam) {
  addMesh(s, makeBoxMesh(Vec3(-0.8, -0.3, -0.8), Vec3(0.8, 1.3, 0.8)), glass(0.35f, 0.1f, 1.5f, 0.1f));
  addMesh(s, makeBoxMesh(Vec3(-0.4, 0.1, -0.4), Vec3(0.4, 0.9, 0.4)), glass(0.35f, 0.1f, 1.5f, 0.1f));
  addMesh(s, makeGrid(Vec3(-5, -0.3, 5), Vec3(10, 0, 0), Vec3(0, 0, -10), 1, 1), diffuseMaterial(Color(0.8f)));
  addSphere(s, Vec3(1.6, 0.2, 0.5), 0.5, diffuseMaterial(Color(0.2f, 0.4f, 0.9f)));
  s.lights().push_back(makePointLight(Vec3(0, 0.5, 0)));
  s.background = Color(0.05f);
  cam.eye = Vec3(1.0, 2.5, 4.5);
  cam.focal = Vec3(0.3, 0.2, 0);
  cam.viewAngle = 45.0;
}

void buildFenceScene(Scene& s, CameraSpec& cam) {
  Material floor = diffuseMaterial(Color(0.5f, 0.55f, 0.6f), 0.5f);
  addMesh(s, makeGrid(Vec3(-4, -0.5, 4), Vec3(8, 0, 0), Vec3(0, 0, -8), 1, 1), floor);
  addSphere(s, Vec3(-0.7, 0.1, 0.2), 0.6, glass(0.9f, 0.1f, 1.5f, 0.05f));
  // 24 posts 0.02 wide (about a third of a pixel at 160 x 120) on a line behind the sphere
  const Material post = diffuseMaterial(Color(0.8f, 0.6f, 0.3f));
  for (int k = 0; k < 24; ++k) {
    const double x = -2.4 + 0.2 * k;
    addMesh(s, makeBoxMesh(Vec3(x, -0.5, -1.2), Vec3(x + 0.02, 0.7, -1.18)), post);
  }
  addMesh(s, makeBoxMesh(Vec3(0.5, -0.5, -0.2), Vec3(1.2, 0.2, 0.5)), diffuseMaterial(Color(0.2f, 0.5f, 0.9f)));
  s.lights().push_back(makePointLight(Vec3(2, 3, 2)));
  Light fill = makePointLight(Vec3(-3, 2, 1));
  fill.intensity = 0.5f;
  s.lights().push_back(fill);
  s.background = Color(0.15f, 0.2f, 0.3f);
  cam.eye = Vec3(0.3, 1.2, 4.2);
  cam.focal = Vec3(0, 0, -0.3);
  cam.viewAngle = 40.0;
}

void buildTextScene(Scene& s, CameraSpec& cam) {
  // A white page with 8 rows of 16 seven-segment glyphs: strokes 0.0075 wide, about a third of a pixel at 160 x 120
  addMesh(s, makeGrid(Vec3(-1.6, -1.2, 0), Vec3(3.2, 0, 0), Vec3(0, 2.4, 0), 1, 1),
          diffuseMaterial(Color(0.95f, 0.93f, 0.88f)));
  const Material ink = diffuseMaterial(Color(0.05f, 0.05f, 0.1f));
  const double t = 0.0075, gw = 0.12, gh = 0.2, z0 = 0.0, z1 = 0.004;
  unsigned seed = 12345u;
  for (int row = 0; row < 8; ++row)
    for (int col = 0; col < 16; ++col) {
      seed = seed * 1664525u + 1013904223u;
      const unsigned segs = (seed >> 8) & 0x7fu;
      const double x = -1.45 + 0.18 * col, y = 0.85 - 0.27 * row;
      const double mid = y + 0.5 * gh;
      auto bar = [&](double x0, double y0, double x1, double y1) {
        addMesh(s, makeBoxMesh(Vec3(x0, y0, z0), Vec3(x1, y1, z1)), ink);
      };
      if (segs & 1u) bar(x, y + gh - t, x + gw, y + gh);    // top
      if (segs & 2u) bar(x + gw - t, mid, x + gw, y + gh);  // upper right
      if (segs & 4u) bar(x + gw - t, y, x + gw, mid);       // lower right
      if (segs & 8u) bar(x, y, x + gw, y + t);              // bottom
      if (segs & 16u) bar(x, y, x + t, mid);                // lower left
      if (segs & 32u) bar(x, mid, x + t, y + gh);           // upper left
      if (segs & 64u || segs == 0u) bar(x, mid - 0.5 * t, x + gw, mid + 0.5 * t);  // middle
    }
  s.lights().push_back(makePointLight(Vec3(1, 1.5, 3)));
  s.background = Color(0.15f, 0.2f, 0.3f);
  // slightly oblique, so the strokes do not line up with the pixel grid
  cam.eye = Vec3(0.5, -0.35, 3.95);
  cam.focal = Vec3(0, 0, 0);
  cam.viewAngle = 40.0;
}

}  // namespace whitted
