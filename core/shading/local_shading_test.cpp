// Local shading of one hit (local_shading.cpp) against VTK's: coloured shadows through transmissive occluders,
// VTK's specular view vector, colour-map lookup before lighting, the ambient term of opaque back faces, no shadow ray
// whose light cannot be seen, and the energy rule (body colour, highlight and opacity as VTK blends them).
#include "scenes/scenes.h"
#include "scenes/stiff_scenes.h"
#include "shading/integrator.h"
#include "shading/integrator_test_util.h"

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <vector>

using namespace whitted;
using namespace whitted::integrator_test;

// A point on the floor lit through two transmissive plates receives the light times kt1 * kt2 (coloured shadow).
TEST(Integrator, ShadowThroughTwoTransmissiveOccluders) {
  auto floorColor = [](bool plates) {
    Scene s;
    Material floor;
    floor.ambient = 0.0f;
    floor.diffuse = 1.0f;
    addObject(s, makeGrid(Vec3(-10, 0, 10), Vec3(20, 0, 0), Vec3(0, 0, -20), 1, 1), floor);
    if (plates) {
      Material p1 = glassMaterial(1.0f, Color(0.5f, 1.0f, 0.8f)), p2 = glassMaterial(1.0f, Color(1.0f, 0.5f, 0.8f));
      addObject(s, makeGrid(Vec3(-1, 2, 1), Vec3(2, 0, 0), Vec3(0, 0, -2), 1, 1), p1);
      addObject(s, makeGrid(Vec3(-1, 3, 1), Vec3(2, 0, 0), Vec3(0, 0, -2), 1, 1), p2);
    }
    Light l;
    l.positional = true;
    l.position = Vec3(0, 10, 0);
    l.coneAngle = 180.0;
    s.lights().push_back(l);
    s.commit();
    Integrator integ(s, IntegratorSettings{}, Vec3(0, 1, 0));
    RayStats st;
    // Look straight down at the floor point under the plates, from between plate 1 and the floor
    return integ.trace(ray(Vec3(0.01, 1.0, 0.01), Vec3(0, -1, 0)), st, Color(0.0f)).color;
  };
  Color open = floorColor(false), shadowed = floorColor(true);
  ASSERT_GT(open.x, 0.5f);
  EXPECT_NEAR(shadowed.x / open.x, 0.5f, 1e-5f);
  EXPECT_NEAR(shadowed.y / open.y, 0.5f, 1e-5f);
  EXPECT_NEAR(shadowed.z / open.z, 0.64f, 1e-5f);
}

// VTK's specular uses V = normalize(eye - P) even for parallel projection; with viewFromEye the tracer does too.
TEST(Integrator, ViewFromEyeMatchesVtkParallelSpecular) {
  Scene s;
  Material m;
  m.diffuse = 0.0f;
  m.specular = 1.0f;
  m.specularPower = 10.0f;
  addObject(s, makeGrid(Vec3(-5, -5, 0), Vec3(10, 0, 0), Vec3(0, 10, 0), 1, 1), m);
  Light l;
  l.position = Vec3(0, 0, 1);  // directional, straight down -z
  s.lights().push_back(l);
  s.commit();
  IntegratorSettings is;
  is.viewFromEye = true;
  is.eye = Vec3(0, 0, 3);
  Integrator integ(s, is, Vec3(0, 1, 0));
  RayStats st;
  // A parallel camera ray at x = 1 hits P = (1, 0, 0): R = (0,0,1), V = normalize((0,0,3) - P)
  Sample smp = integ.trace(ray(Vec3(1, 0, 3), Vec3(0, 0, -1)), st, Color(0.0f));
  float expected = float(std::pow(3.0 / std::sqrt(10.0), 10.0));
  EXPECT_NEAR(smp.color.x, expected, 1e-5f);
  is.viewFromEye = false;  // V = -d = (0,0,1): full highlight
  Integrator plain(s, is, Vec3(0, 1, 0));
  EXPECT_NEAR(plain.trace(ray(Vec3(1, 0, 3), Vec3(0, 0, -1)), st, Color(0.0f)).color.x, 1.0f, 1e-5f);
}

// InterpolateScalarsBeforeMapping: the interpolated coordinate is looked up (nearest) in the colour map before
// lighting, so the specular highlight keeps the specular colour instead of being tinted.
TEST(Integrator, ColorMapLookupBeforeLighting) {
  Scene s;
  TriangleMesh quad = makeGrid(Vec3(-1, -1, 0), Vec3(2, 0, 0), Vec3(0, 2, 0), 1, 1);
  quad.colorCoords = {0.0f, 1.0f, 0.0f, 1.0f};  // varies along x
  Texture lut;
  lut.width = 4;
  lut.height = 1;
  lut.rgba = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 255};
  quad.colorMap = int32_t(s.addTexture(lut));
  Material m = unlit(Color(1.0f));
  m.colorSource = ColorSource::ScalarsAmbientAndDiffuse;
  addObject(s, quad, m);
  s.commit();
  Integrator integ(s, IntegratorSettings{}, Vec3(0, 1, 0));
  RayStats st;
  // x = -0.9 -> coordinate 0.05 -> texel 0 (red); x = 0.3 -> 0.65 -> texel 2 (blue)
  Color a = integ.trace(ray(Vec3(-0.9, 0, 1), Vec3(0, 0, -1)), st, Color(0.0f)).color;
  Color b = integ.trace(ray(Vec3(0.3, 0, 1), Vec3(0, 0, -1)), st, Color(0.0f)).color;
  EXPECT_EQ(a, Color(1, 0, 0));
  EXPECT_EQ(b, Color(0, 0, 1));
}

// Back faces of an opaque actor keep their ambient term whether or not an unrelated transmissive actor exists
// (it used to depend on the kernel: with any kt > 0 in the scene, opaque back faces lost their ambient light).
TEST(Integrator, OpaqueSceneUnchangedByUnrelatedTransmissiveActor) {
  auto image = [](bool withGlass) {
    Scene s;
    Material m;
    m.ambient = 0.3f;
    m.diffuseColor = Color(0.8f, 0.6f, 0.4f);
    // A quad seen from its back, and a box seen from outside
    addObject(s, makeGrid(Vec3(-2, -2, 0), Vec3(0, 4, 0), Vec3(4, 0, 0), 1, 1), m);
    addObject(s, makeBoxMesh(Vec3(-0.5, -0.5, 0.5), Vec3(0.5, 0.5, 1.0)), m);
    if (withGlass)  // far behind the camera, out of every ray's and light's way
      addObject(s, makeBoxMesh(Vec3(-1, -1, 100), Vec3(1, 1, 102)), glassMaterial(1.5f, Color(0.9f)));
    Light l;
    l.position = Vec3(0.3, 0.2, 1.0);
    s.lights().push_back(l);
    s.commit();
    Integrator integ(s, IntegratorSettings{}, Vec3(0, 1, 0));
    std::vector<Color> out;
    RayStats st;
    for (int y = 0; y < 16; ++y)
      for (int x = 0; x < 16; ++x)
        out.push_back(integ.trace(ray(Vec3(0, 0, 5), Vec3((x - 7.5) / 20.0, (y - 7.5) / 20.0, -1)), st,
                                  Color(0.0f))
                          .color);
    EXPECT_EQ(st.safetyNetCatches(), 0u);
    return out;
  };
  const std::vector<Color> without = image(false), with = image(true);
  ASSERT_EQ(without.size(), with.size());
  for (std::size_t i = 0; i < with.size(); ++i) EXPECT_EQ(with[i], without[i]) << "pixel " << i;
  EXPECT_GT(without[0].x, 0.3f * 0.8f * 0.99f);  // the back face has its ambient term (0.3 x 0.8) at least
}

// Leave out what cannot be seen: a pure mirror (no diffuse, no specular) traces no shadow ray, nor does a light of
// zero intensity; a diffuse surface under a real light does. The image is the same as with every ray traced.
TEST(Integrator, NoShadowRayWhoseContributionCannotBeSeen) {
  Scene s;
  Material mirror;
  mirror.diffuse = 0.0f;
  mirror.specular = 0.0f;
  mirror.reflectance = Color(0.9f);
  Material matte = unlit(Color(0.7f));
  matte.lighting = true;
  addObject(s, makeGrid(Vec3(-5, -5, 0), Vec3(10, 0, 0), Vec3(0, 10, 0), 1, 1), mirror);
  addObject(s, makeGrid(Vec3(-5, -5, 3), Vec3(0, 10, 0), Vec3(10, 0, 0), 1, 1), matte);  // faces down, seen in it
  Light on, off;
  on.positional = true;
  on.position = Vec3(0.5, 0.5, 1.5);
  on.coneAngle = 180.0;
  off = on;
  off.intensity = 0.0f;
  s.lights() = {on, off};
  s.commit();
  Integrator integ(s, IntegratorSettings{}, Vec3(0, 1, 0));
  RayStats st;
  Sample smp = integ.trace(ray(Vec3(0.2, 0.1, 1.0), Vec3(0, 0, -1)), st, Color(0.0f));
  EXPECT_EQ(st.reflection, 1u);
  EXPECT_EQ(st.shadow, 1u) << "one shadow ray: from the matte ceiling seen in the mirror, to the lit light only";
  EXPECT_GT(smp.color.x, 0.0f);
  EXPECT_EQ(st.safetyNetCatches(), 0u);
}

// The energy rule (bodyWeight). An opaque (Opacity 1), lit, white surface with only Transmittance set is clear
// glass: kt = 1 at IOR 1 shows exactly what is behind; kt = 0.9 shows 0.9 x behind + 0.1 x its own colour, never
// more than 1 (it used to be 1 x colour + 0.9 x behind). Reflectance alone makes a mirror: kr = 1 in front of a
// known wall shows exactly the wall. A translucent actor with VTK's defaults (kt = 1 - Opacity, kr = 0) keeps
// VTK's blend bit for bit, and the specular highlight keeps the opacity weight.
TEST(Integrator, EnergyRuleTransmittanceAloneIsGlassReflectanceAloneIsMirror) {
  const Color behind(0.2f, 0.6f, 0.9f);
  auto trace = [&](const Material& front, Vec3 origin, Vec3 dir) {
    Scene s;
    addObject(s, makeGrid(Vec3(-1, -1, 0), Vec3(2, 0, 0), Vec3(0, 2, 0), 1, 1), front);
    addObject(s, makeGrid(Vec3(-50, -50, -5), Vec3(100, 0, 0), Vec3(0, 100, 0), 1, 1), unlit(behind));
    Light l;
    l.position = Vec3(0, 0, 1);  // directional along -z: the front quad's diffuse term is its full colour
    s.lights().push_back(l);
    s.commit();
    Integrator integ(s, IntegratorSettings{}, Vec3(0, 1, 0));
    RayStats st;
    Sample smp = integ.trace(ray(origin, dir), st, Color(0.0f));
    EXPECT_EQ(st.safetyNetCatches(), 0u);
    return smp.color;
  };
  Material white;  // lit, diffuse 1, white, Opacity 1
  for (float kt : {1.0f, 0.9f, 0.5f}) {
    Material glass = white;
    glass.transmittance = Color(kt);
    Color c = trace(glass, Vec3(0, 0, 5), Vec3(0, 0, -1));
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(c[i], kt * behind[i] + (1.0f - kt) * 1.0f, 1e-6f) << kt;
  }
  // A mirror turned 45 degrees about y sends the camera ray along +x, head on into an unlit wall at x = 5
  Material mirror = white;
  mirror.reflectance = Color(1.0f);
  Scene s;
  addObject(s, makeGrid(Vec3(-1, -1, 0), Vec3(2, 0, 0), Vec3(0, 2, 0), 1, 1), mirror,
            glm::rotate(Mat4(1.0), glm::radians(45.0), Vec3(0, 1, 0)));
  addObject(s, makeGrid(Vec3(5, -50, -50), Vec3(0, 0, 100), Vec3(0, 100, 0), 1, 1), unlit(behind));
  Light l;
  l.position = Vec3(0, 0, 1);
  s.lights().push_back(l);
  s.commit();
  Integrator integ(s, IntegratorSettings{}, Vec3(0, 1, 0));
  RayStats st;
  Sample smp = integ.trace(ray(Vec3(0, 0, 5), Vec3(0, 0, -1)), st, Color(0.0f));
  EXPECT_EQ(st.reflection, 1u);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(smp.color[i], behind[i], 1e-6f);

  // VTK's translucency: Opacity 0.3, kt = 1 - 0.3 computed as the VTK adapter computes it
  Material translucent = white;
  translucent.opacity = 0.3f;
  translucent.transmittance = Color(1.0f - translucent.opacity);
  Color c = trace(translucent, Vec3(0, 0, 5), Vec3(0, 0, -1));
  for (int i = 0; i < 3; ++i) EXPECT_EQ(c[i], translucent.opacity * 1.0f + translucent.transmittance[i] * behind[i]);
  EXPECT_EQ(bodyWeight(translucent, 0.3f), 0.3f);
  EXPECT_EQ(bodyWeight(translucent, 0.1f), 0.1f);  // vertex or texel alpha below the Opacity

  // The highlight keeps the opacity weight: clear glass with a specular term shows behind + the highlight
  Material shiny = white;
  shiny.diffuse = 0.0f;
  shiny.specular = 0.5f;
  shiny.transmittance = Color(1.0f);
  c = trace(shiny, Vec3(0, 0, 5), Vec3(0, 0, -1));
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(c[i], behind[i] + 0.5f, 1e-6f);
}
