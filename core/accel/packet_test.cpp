// Shadow packets (Scene::occludedPacket, Integrator::traceBlock) and closest-hit packets of camera rays
// (Scene::intersectPacket): the same hits, image, ray counts and error bounds as single rays. Shadow packets: for
// opaque and translucent occluders, instances (transformed, several levels of the top tree), spheres and tubes,
// point, spot and directional lights, one and several samples per pixel. (Frames of scenes with translucent
// surfaces trace single shadow rays, see traceBlock: their frames check that gate; the packet answers and
// hand-overs there are checked ray by ray.)
#include "image/renderer.h"
#include "scenes/scenes.h"

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <string>

using namespace whitted;

namespace {

/// Opaque and (optionally) translucent occluders over a floor: a mesh sphere instanced three times (one rotated
/// and scaled), spheres, tubes; a point light, a spot light and a directional one.
void buildShadowScene(Scene& s, bool translucent) {
  Material floor;
  floor.diffuseColor = Color(0.8f, 0.8f, 0.7f);
  floor.specular = 0.3f;
  floor.specularPower = 20.0f;
  const uint32_t floorMat = s.addMaterial(floor);
  Material red;
  red.diffuseColor = Color(0.9f, 0.2f, 0.1f);
  const uint32_t redMat = s.addMaterial(red);
  Material glass;
  glass.opacity = 0.3f;
  glass.transmittance = Color(0.6f, 0.8f, 0.7f);
  const uint32_t glassMat = s.addMaterial(glass);

  s.addInstance(s.addMesh(makeGrid(Vec3(-4, -4, 0), Vec3(8, 0, 0), Vec3(0, 8, 0), 16, 16)), Mat4(1.0), floorMat);
  const uint32_t ball = s.addMesh(makeSphereMesh(Vec3(0.0), 0.6, 24, 12));
  s.addInstance(ball, glm::translate(Mat4(1.0), Vec3(-1.2, 0.3, 0.8)), redMat);
  s.addInstance(ball,
                glm::scale(glm::rotate(glm::translate(Mat4(1.0), Vec3(1.1, -0.6, 0.9)), 0.7, Vec3(1, 1, 0)),
                           Vec3(1.0, 0.5, 1.5)),
                translucent ? glassMat : redMat);
  s.addInstance(ball, glm::translate(Mat4(1.0), Vec3(0.2, 1.5, 1.4)), translucent ? glassMat : redMat);
  SphereSet spheres;
  for (int i = 0; i < 6; ++i) spheres.centers.push_back(Vec3(-2.5 + i, -2.0, 0.4 + 0.1 * i));
  spheres.radii = {0.3};
  s.addInstance(s.addSpheres(spheres), Mat4(1.0), redMat);
  TubeSet tubes;
  tubes.p0 = {Vec3(-2, 2.5, 0.5), Vec3(0, 2.5, 1.0)};
  tubes.p1 = {Vec3(0, 2.5, 1.0), Vec3(2, 2.2, 0.3)};
  tubes.radii = {0.15};
  s.addInstance(s.addTubes(tubes), Mat4(1.0), translucent ? glassMat : redMat);

  Light point;
  point.positional = true;
  point.coneAngle = 90.0;
  point.position = Vec3(2.0, -1.0, 5.0);
  point.intensity = 0.6f;
  Light spot;
  spot.positional = true;
  spot.position = Vec3(-3.0, 2.0, 4.0);
  spot.focalPoint = Vec3(0.0);
  spot.coneAngle = 35.0;
  spot.intensity = 0.5f;
  Light sun;
  sun.position = Vec3(1.0, 2.0, 3.0);
  sun.intensity = 0.4f;
  s.lights() = {point, spot, sun};
}

/// The frames with the packets of `which` (shadow or camera rays) off and on are the same.
void expectSameFrames(const Scene& scene, const Camera& cam, RenderSettings rs, const std::string& what,
                      bool IntegratorSettings::*which = &IntegratorSettings::packets) {
  FrameBuffer single, packets;
  rs.integrator.*which = false;
  const FrameStats a = render(scene, cam, rs, 61, 47, single);
  rs.integrator.*which = true;
  const FrameStats b = render(scene, cam, rs, 61, 47, packets);
  if (rs.integrator.shadows) ASSERT_GT(a.rays.shadow, 0u) << what;
  ASSERT_GT(a.rays.primary, 0u) << what;
  EXPECT_EQ(0, std::memcmp(single.color.data(), packets.color.data(), single.color.size() * sizeof(Color4))) << what;
  EXPECT_EQ(0, std::memcmp(single.depth.data(), packets.depth.data(), single.depth.size() * sizeof(float))) << what;
  EXPECT_EQ(0, std::memcmp(single.truncation.data(), packets.truncation.data(),
                           single.truncation.size() * sizeof(single.truncation[0])))
      << what;
  EXPECT_EQ(a.rays.primary, b.rays.primary) << what;
  EXPECT_EQ(a.rays.shadow, b.rays.shadow) << what;
  EXPECT_EQ(a.rays.reflection, b.rays.reflection) << what;
  EXPECT_EQ(a.rays.refraction, b.rays.refraction) << what;
  EXPECT_EQ(a.rays.savedByThreshold, b.rays.savedByThreshold) << what;
  EXPECT_EQ(a.truncation.rms, b.truncation.rms) << what;
  EXPECT_EQ(a.sampling.rms, b.sampling.rms) << what;
}

}  // namespace

TEST(ShadowPackets, SameFramesAsSingleRays) {
  for (bool translucent : {false, true}) {
    Scene s;
    buildShadowScene(s, translucent);
    s.commit();
    CameraSpec cs;
    cs.eye = Vec3(0.5, -7.0, 5.0);
    cs.focal = Vec3(0.0, 0.0, 0.5);
    cs.up = Vec3(0, 0, 1);
    const Camera cam = cs.make(61.0 / 47.0, s.bounds());
    const std::string name = translucent ? "translucent occluders" : "opaque occluders";
    RenderSettings rs;
    rs.threads = 2;
    expectSameFrames(s, cam, rs, name + ", 1 spp");
    rs.samplesPerPixel = 4;
    rs.adaptive = true;
    expectSameFrames(s, cam, rs, name + ", 4 spp adaptive");
    rs.samplesPerPixel = 5;  // a pixel's last block holds one sample
    rs.adaptive = false;
    expectSameFrames(s, cam, rs, name + ", 5 spp");
  }
  // The classic scene: glass and mirror spheres (reflections, refractions) over a floor, one point light
  Scene c;
  CameraSpec cs;
  buildClassicScene(c, cs);
  c.commit();
  RenderSettings rs;
  rs.threads = 2;
  expectSameFrames(c, cs.make(61.0 / 47.0, c.bounds()), rs, "classic");
}

// Each packet answer is transmittance()'s, and opaque scenes answer every ray in the packet (nothing falls back).
TEST(ShadowPackets, PacketAnswersAreTransmittance) {
  for (bool translucent : {false, true}) {
    Scene s;
    buildShadowScene(s, translucent);
    s.commit();
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int blockedRays = 0, freeRays = 0, fallbacks = 0;
    for (int packet = 0; packet < 2000; ++packet) {
      // Four rays from nearby floor points toward one light position (coherent, like a pixel block's)
      const Vec3 base(3.0 * u(rng), 3.0 * u(rng), 0.0), light(2.0 * u(rng), 2.0 * u(rng), 4.0 + u(rng));
      Ray rays[4];
      for (int i = 0; i < 4; ++i) {
        rays[i].origin = base + Vec3(0.05 * u(rng), 0.05 * u(rng), 1e-9);
        rays[i].dir = light - rays[i].origin;
        rays[i].tMin = 0.0;
        rays[i].tMax = packet % 2 ? 1.0 - 1e-9 : kInfinity;
      }
      const unsigned active = 1u + unsigned(packet % 15);
      unsigned blocked = 0;
      const unsigned fallback = s.occludedPacket(rays, active, blocked);
      EXPECT_EQ(0u, fallback & ~active);
      EXPECT_EQ(0u, blocked & ~active);
      for (int i = 0; i < 4; ++i) {
        if (!(active >> i & 1) || (fallback >> i & 1)) {
          fallbacks += (fallback >> i) & 1;
          continue;
        }
        const Color t = s.transmittance(rays[i], 1.0f / 255.0f);
        const Color expected((blocked >> i & 1) ? 0.0f : 1.0f);
        ASSERT_EQ(0, std::memcmp(&t, &expected, sizeof t)) << packet << " " << i;
        ((blocked >> i & 1) ? blockedRays : freeRays)++;
      }
    }
    if (!translucent) {
      EXPECT_EQ(0, fallbacks);
      EXPECT_GT(blockedRays, 100);
    }
    EXPECT_GT(freeRays, 100) << translucent;
  }
}

namespace {

/// A point cloud (many small spheres) and a second, coplanar copy of the floor grid (instances that tie at every
/// floor hit: the lower instance id must win in any visiting order), on top of the shadow scene.
void addPointsAndDuplicateFloor(Scene& s) {
  SphereSet points;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 400; ++i)
    points.centers.push_back(Vec3(2.5 + 0.6 * u(rng), 1.5 + 0.6 * u(rng), 0.6 + 0.4 * u(rng)));
  points.radii = {0.03};
  s.addInstance(s.addSpheres(points), Mat4(1.0), 0);
  s.addInstance(s.addMesh(makeGrid(Vec3(-4, -4, 0), Vec3(8, 0, 0), Vec3(0, 8, 0), 16, 16)), Mat4(1.0), 1);
}

void expectSameHit(bool found, const Hit& h, bool foundSingle, const Hit& single, const std::string& what) {
  ASSERT_EQ(foundSingle, found) << what;
  if (!found) return;
  EXPECT_EQ(0, std::memcmp(&single.t, &h.t, sizeof h.t)) << what << " t " << single.t << " " << h.t;
  EXPECT_EQ(single.instance, h.instance) << what;
  EXPECT_EQ(single.prim, h.prim) << what;
  EXPECT_EQ(single.slot, h.slot) << what;
  EXPECT_EQ(0, std::memcmp(&single.u, &h.u, sizeof h.u)) << what;
  EXPECT_EQ(0, std::memcmp(&single.v, &h.v, sizeof h.v)) << what;
}

}  // namespace

TEST(PrimaryPackets, SameFramesAsSingleRays) {
  const auto camera = [](const Scene& s) {
    CameraSpec cs;
    cs.eye = Vec3(0.5, -7.0, 5.0);
    cs.focal = Vec3(0.0, 0.0, 0.5);
    cs.up = Vec3(0, 0, 1);
    return cs.make(61.0 / 47.0, s.bounds());
  };
  for (bool translucent : {false, true}) {
    Scene s;
    buildShadowScene(s, translucent);
    addPointsAndDuplicateFloor(s);
    s.commit();
    const Camera cam = camera(s);
    const std::string name = translucent ? "translucent occluders" : "opaque occluders";
    for (bool shadowPackets : {false, true}) {
      RenderSettings rs;
      rs.threads = 2;
      rs.integrator.packets = shadowPackets;
      const std::string what = name + (shadowPackets ? ", shadow packets" : ", single shadow rays");
      expectSameFrames(s, cam, rs, what + ", 1 spp", &IntegratorSettings::primaryPackets);
      rs.samplesPerPixel = 4;
      expectSameFrames(s, cam, rs, what + ", 4 spp", &IntegratorSettings::primaryPackets);
      rs.adaptive = true;
      expectSameFrames(s, cam, rs, what + ", 4 spp adaptive", &IntegratorSettings::primaryPackets);
    }
    RenderSettings rs;
    rs.threads = 2;
    rs.integrator.shadows = false;
    expectSameFrames(s, cam, rs, name + ", no shadows", &IntegratorSettings::primaryPackets);
  }
  // The classic scene: glass and mirror spheres (reflections, refractions) over a floor; and its mesh version.
  // Scenes with transmissive surfaces (these, and the translucent occluders above) find their first hits one by
  // one (traceBlock): their frames check that gate
  for (int subdivisions : {0, 24}) {
    Scene c;
    CameraSpec cs;
    buildClassicScene(c, cs, subdivisions);
    c.commit();
    RenderSettings rs;
    rs.threads = 2;
    const Camera cam = cs.make(61.0 / 47.0, c.bounds());
    expectSameFrames(c, cam, rs, "classic 1 spp", &IntegratorSettings::primaryPackets);
    rs.samplesPerPixel = 4;
    rs.adaptive = true;
    expectSameFrames(c, cam, rs, "classic 4 spp adaptive", &IntegratorSettings::primaryPackets);
  }
}

// Each packet hit is intersect()'s, bit for bit: random coherent packets, packets whose rays share an origin, and
// rays aimed exactly at the floor grid's vertices and edges (ties between triangles) and at its coplanar copy (ties
// between instances), in a scene with a top level and in a single-instance one.
TEST(PrimaryPackets, HitsAreSingleRayHits) {
  Scene s;
  buildShadowScene(s, false);
  addPointsAndDuplicateFloor(s);
  s.commit();
  Scene one;  // a single identity instance: no top level
  one.addInstance(one.addMesh(makeGrid(Vec3(-4, -4, 0), Vec3(8, 0, 0), Vec3(0, 8, 0), 16, 16)), Mat4(1.0), 0);
  one.commit();
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> grid(-8, 8);
  int hits = 0, ties = 0;
  for (int packet = 0; packet < 2000; ++packet) {
    const Scene& scene = packet % 4 == 3 ? one : s;
    const int kind = packet % 3;  // 0: nearby origins, 1: one shared origin, 2: aimed at grid vertices and edges
    const Vec3 eye(6.0 * u(rng), -7.0 + u(rng), 3.0 + 3.0 * u(rng)), target(3.0 * u(rng), 3.0 * u(rng), u(rng));
    Ray rays[4];
    for (int i = 0; i < 4; ++i) {
      rays[i].origin = kind == 0 ? eye + Vec3(0.01 * u(rng), 0.01 * u(rng), 0.01 * u(rng)) : eye;
      Vec3 to = target + Vec3(0.05 * u(rng), 0.05 * u(rng), 0.05 * u(rng));
      if (kind == 2) {
        // A grid vertex (multiples of 0.5) or the middle of an edge: hit by several triangles at the same t
        to = Vec3(0.5 * grid(rng), 0.5 * grid(rng), 0.0);
        if (i & 1) to.x += 0.25;
      }
      rays[i].dir = to - rays[i].origin;
      rays[i].tMin = 0.0;
      rays[i].tMax = packet % 5 == 4 ? 0.999 : kInfinity;
    }
    const unsigned active = packet % 7 == 6 ? 1u + unsigned(packet % 15) : 0xfu;
    Hit h[4];
    const unsigned found = scene.intersectPacket(rays, active, h);
    EXPECT_EQ(0u, found & ~active);
    for (int i = 0; i < 4; ++i) {
      if (!(active >> i & 1)) continue;
      Hit single;
      const bool foundSingle = scene.intersect(rays[i], single);
      expectSameHit(found >> i & 1, h[i], foundSingle, single, std::to_string(packet) + " " + std::to_string(i));
      hits += foundSingle;
      ties += foundSingle && kind == 2 && (single.u == 0.0 || single.v == 0.0 || single.u + single.v == 1.0);
    }
  }
  EXPECT_GT(hits, 4000);
  EXPECT_GT(ties, 500);  // hits on an edge or vertex (a barycentric coordinate exactly 0)
}
