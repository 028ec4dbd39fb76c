// Integrator tests against analytic optics: slab refraction offset, total internal reflection, IOR 1 invisibility,
// Fresnel, Beer-Lambert; contribution cutoff and depth cap accounting, feature-driven kernels, the error estimate
// against a deep reference, alpha and what escaped rays see.
// The local shading of one hit (VTK's lighting, shadow rays, the energy rule) is tested in local_shading_test.cpp.
#include "shading/integrator.h"
#include "image/renderer.h"
#include "scenes/scenes.h"
#include "scenes/stiff_scenes.h"
#include "shading/integrator_test_util.h"

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

using namespace whitted;
using namespace whitted::integrator_test;

// A ray through a glass slab exits parallel to itself, shifted sideways by d sin(t) (1 - cos(t) / sqrt(n^2 -
// sin^2(t))) (perpendicular to the ray). We find where a sharp white/black edge behind the slab appears along a
// family of parallel rays starting on a horizontal line, with and without the slab, by bisection on the
// integrator's output; their difference is the lateral offset divided by cos(t).
TEST(Integrator, SlabLateralOffsetMatchesSnell) {
  const double thickness = 1.0, n = 1.5, theta = 0.5;  // radians
  auto edgePosition = [&](bool withSlab) {
    Scene s;
    if (withSlab) addObject(s, makeBoxMesh(Vec3(-50, -1.0 - thickness, -50), Vec3(50, -1.0, 50)), glassMaterial(float(n)));
    // Screen at y = -10: white for x > 0, black for x < 0 (unlit, so the colour is exact)
    addObject(s, makeGrid(Vec3(0, -10, 50), Vec3(100, 0, 0), Vec3(0, 0, -100), 1, 1), unlit(Color(1.0f)));
    addObject(s, makeGrid(Vec3(-100, -10, 50), Vec3(100, 0, 0), Vec3(0, 0, -100), 1, 1), unlit(Color(0.0f)));
    s.background = Color(0.5f);
    s.commit();
    IntegratorSettings is;
    is.contributionThreshold = 0.0f;
    Integrator integ(s, is, Vec3(0, 1, 0));
    Vec3 dir(std::sin(theta), -std::cos(theta), 0.0);
    // Rays start at y = 0 with x = x0; find x0 where the colour switches from black to white
    double lo = -20.0, hi = 20.0;
    for (int i = 0; i < 80; ++i) {
      double mid = 0.5 * (lo + hi);
      RayStats st;
      Sample smp = integ.trace(ray(Vec3(mid, 0, 0.25), dir), st, Color(0.0f));
      (smp.color.x > 0.5f ? hi : lo) = mid;
    }
    return 0.5 * (lo + hi);
  };
  double shift = (edgePosition(true) - edgePosition(false)) * std::cos(theta);
  double st = std::sin(theta), ct = std::cos(theta);
  double expected = thickness * st * (1.0 - ct / std::sqrt(n * n - st * st));
  EXPECT_NEAR(shift, expected, 1e-9);
  EXPECT_GT(shift, 0.1);  // the effect is real, not a degenerate zero
}

// Inside glass (n = 1.5, critical angle 41.81 degrees) a ray meeting the top face just below the critical angle
// leaves through it to a red plane above; just above, it is totally reflected down onto a green plane inside.
TEST(Integrator, TotalInternalReflectionPastCriticalAngle) {
  const double n = 1.5, critical = std::asin(1.0 / n);
  Scene s;
  addObject(s, makeBoxMesh(Vec3(-50, -1, -50), Vec3(50, 1, 50)), glassMaterial(float(n)));
  addObject(s, makeGrid(Vec3(-100, 5, 100), Vec3(200, 0, 0), Vec3(0, 0, -100 * 2), 1, 1), unlit(Color(1, 0, 0)));
  addObject(s, makeGrid(Vec3(-40, -0.5, -40), Vec3(80, 0, 0), Vec3(0, 0, 80), 1, 1), unlit(Color(0, 1, 0)));
  s.commit();
  IntegratorSettings is;
  is.maxDepth = 3;
  is.contributionThreshold = 0.0f;
  Integrator integ(s, is, Vec3(0, 1, 0));
  for (double delta : {-1e-3, 1e-3}) {
    double a = critical + delta;  // angle from the face normal
    RayStats st;
    Sample smp = integ.trace(ray(Vec3(0, 0, 0), Vec3(std::sin(a), std::cos(a), 0)), st, Color(0.0f));
    if (delta < 0) {
      EXPECT_GT(smp.color.x, 0.99f) << "below critical: refracted out to the red plane";
      EXPECT_LT(smp.color.y, 0.01f);
    } else {
      EXPECT_GT(smp.color.y, 0.99f) << "past critical: totally reflected down to the green plane";
      EXPECT_LT(smp.color.x, 0.01f);
      EXPECT_GE(st.reflection, 1u);
    }
  }
}

// A slab that is both a perfect mirror and clear glass (kr = kt = 1, no local colour) in front of a uniform
// background of colour c, no lights: every path ends in the background, so no ray may return more than c (kr + kt
// is scaled to 1 at commit). Rays at several angles, with and without Fresnel, deep recursion, no cutoff.
TEST(Integrator, MirrorGlassSlabNeverBrighterThanBackground) {
  const Color c(0.2f, 0.5f, 0.8f);
  Scene s;
  addObject(s, makeBoxMesh(Vec3(-50, -0.5, -50), Vec3(50, 0.5, 50)), glassMaterial(1.5f, Color(1.0f), Color(1.0f)));
  s.background = c;
  s.commit();
  for (bool fresnel : {false, true}) {
    IntegratorSettings is;
    is.maxDepth = 10;
    is.contributionThreshold = 0.0f;
    is.fresnel = fresnel;
    Integrator integ(s, is, Vec3(0, 1, 0));
    float brightest = 0.0f;
    for (double angle : {0.0, 0.3, 0.7, 1.2, 1.5}) {
      RayStats st;
      Sample smp = integ.trace(ray(Vec3(0.1, 3.0, 0.2), Vec3(std::sin(angle), -std::cos(angle), 0.05)), st, c);
      ASSERT_TRUE(smp.hit);
      for (int k = 0; k < 3; ++k)
        EXPECT_LE(smp.color[k], c[k] * (1.0f + 1e-5f)) << "angle " << angle << " fresnel " << fresnel;
      brightest = std::max(brightest, smp.color.z / c.z);
    }
    std::printf("[integrator] kr = kt = 1 slab, fresnel %d: brightest sample %.4f x background\n", int(fresnel),
                brightest);
  }
}

// With IOR 1 and kt = 1, a transmissive sphere leaves the image unchanged; with kt = 0.5 what is behind is seen
// through two crossings (in and out), so it is scaled by 0.25.
TEST(Integrator, IorOneIsInvisibleApartFromKt) {
  auto renderWith = [](int mode) {
    Scene s;
    Color4 c0(1, 1, 1, 1), c1(0.2f, 0.3f, 0.9f, 1);
    Material floor = unlit(Color(1.0f));
    floor.colorSource = ColorSource::ScalarsAmbientAndDiffuse;
    addObject(s, makeGrid(Vec3(-4, -4, -2), Vec3(8, 0, 0), Vec3(0, 8, 0), 8, 8, &c0, &c1), floor);
    if (mode > 0) {
      SphereSet sp;
      sp.centers = {Vec3(0.3, 0.1, 0.0)};
      sp.radii = {1.2};
      s.addInstance(s.addSpheres(sp), Mat4(1.0), s.addMaterial(glassMaterial(1.0f, Color(mode == 1 ? 1.0f : 0.5f))));
    }
    s.commit();
    Camera cam = Camera::perspective(Vec3(0, 0, 6), Vec3(0), Vec3(0, 1, 0), 40.0, 1.0, 0.1, 100.0);
    RenderSettings rs;
    rs.integrator.contributionThreshold = 0.0f;
    FrameBuffer fb;
    render(s, cam, rs, 64, 64, fb);
    return fb;
  };
  FrameBuffer none = renderWith(0), clear = renderWith(1), half = renderWith(2);
  int covered = 0;
  for (std::size_t i = 0; i < none.color.size(); ++i) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(clear.color[i][c], none.color[i][c], 1e-6f) << i;
    bool insideSphere = std::abs(half.color[i].x - none.color[i].x) > 1e-4f;
    if (insideSphere) {
      ++covered;
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(half.color[i][c], 0.25f * none.color[i][c], 1e-6f) << i;
    }
  }
  EXPECT_GT(covered, 300);
}

// Two facing mirrors with kr = 0.5: path weights 0.5^k. With threshold 0.1 the 4th bounce (0.0625) is not traced
// and is counted as saved; with kr = 1 the depth cap ends the recursion and is counted.
TEST(Integrator, ContributionCutoffAndDepthCapCountSavedRays) {
  for (float kr : {0.5f, 1.0f}) {
    Scene s;
    Material mirror;
    mirror.reflectance = Color(kr);
    addObject(s, makeGrid(Vec3(-5, -5, -1), Vec3(10, 0, 0), Vec3(0, 10, 0), 1, 1), mirror);
    addObject(s, makeGrid(Vec3(-5, -5, 1), Vec3(0, 10, 0), Vec3(10, 0, 0), 1, 1), mirror);
    s.background = Color(0.2f);  // something the left-out rays could have seen
    s.commit();
    IntegratorSettings is;
    is.maxDepth = 6;
    is.contributionThreshold = 0.1f;
    Integrator integ(s, is, Vec3(0, 1, 0));
    RayStats st;
    Sample smp = integ.trace(ray(Vec3(0, 0, 0), Vec3(0, 0.01, -1)), st, Color(0.0f));
    if (kr == 0.5f) {
      EXPECT_EQ(st.reflection, 3u);
      EXPECT_EQ(st.savedByThreshold, 1u);
      EXPECT_EQ(st.savedByDepth, 0u);
    } else {
      EXPECT_EQ(st.reflection, 6u);
      EXPECT_EQ(st.savedByDepth, 1u);
      EXPECT_GT(smp.truncationBound, 0.0f);
    }
  }
}

// An opaque scene runs a kernel without reflection/refraction machinery and traces no secondary rays.
TEST(Integrator, OpaqueSceneLeavesOutSecondaryMachinery) {
  Scene s;
  CameraSpec cs;
  buildClassicScene(s, cs);
  s.material(1).reflectance = Color(0.0f);
  s.material(2).transmittance = Color(0.0f);
  s.material(2).reflectance = Color(0.0f);
  s.commit();
  EXPECT_FALSE(s.features().reflective);
  EXPECT_FALSE(s.features().transmissive);
  RenderSettings rs;
  FrameBuffer fb;
  FrameStats fs = render(s, cs.make(1.0, s.bounds()), rs, 48, 48, fb);
  EXPECT_FALSE(fs.kernelReflection);
  EXPECT_FALSE(fs.kernelRefraction);
  EXPECT_TRUE(fs.kernelShadows);
  EXPECT_EQ(fs.rays.reflection + fs.rays.refraction, 0u);
  EXPECT_GT(fs.rays.shadow, 0u);
}

// The per-frame error estimate bounds the real difference to a deep, cutoff-free reference at every pixel: the
// truncation bound >= the largest channel difference of the clamped colours (the estimate's units), pixel by pixel.
// Negative control: the same check on a copy of the bound lowered at one pixel only (the pixel of the largest
// error, to 0) reports exactly that pixel, while an image-wide RMS comparison still passes on that copy.
TEST(Integrator, ErrorEstimateBoundsTrueError) {
  Scene s;
  CameraSpec cs;
  buildClassicScene(s, cs);
  s.commit();
  Camera cam = cs.make(4.0 / 3.0, s.bounds());
  RenderSettings ref, cheap;
  ref.integrator.maxDepth = 24;
  ref.integrator.contributionThreshold = 0.0f;
  cheap.integrator.maxDepth = 2;
  cheap.integrator.contributionThreshold = 0.05f;
  FrameBuffer a, b;
  render(s, cam, ref, 80, 60, a);
  FrameStats fs = render(s, cam, cheap, 80, 60, b);
  std::vector<float> diff(a.color.size());
  double err2 = 0.0;
  std::size_t worst = 0;
  for (std::size_t i = 0; i < a.color.size(); ++i) {
    for (int c = 0; c < 3; ++c)
      diff[i] = std::max(diff[i], std::abs(std::clamp(a.color[i][c], 0.0f, 1.0f) - std::clamp(b.color[i][c], 0.0f, 1.0f)));
    err2 += double(diff[i]) * diff[i];
    if (diff[i] > diff[worst]) worst = i;
  }
  const double rms = std::sqrt(err2 / double(a.color.size()));
  EXPECT_GT(rms, 1e-3);  // the cheap settings really do lose something
  // Pixels whose bound is under the measured error (1e-5: float rounding of the two renders)
  auto under = [&](const std::vector<float>& bound) {
    std::vector<std::size_t> out;
    for (std::size_t i = 0; i < diff.size(); ++i)
      if (bound[i] + 1e-5f < diff[i]) out.push_back(i);
    return out;
  };
  const std::vector<std::size_t> missed = under(b.truncation);
  EXPECT_TRUE(missed.empty()) << missed.size() << " pixels under, first " << missed.front() << ": bound "
                              << b.truncation[missed.front()] << " < measured " << diff[missed.front()];
  EXPECT_GE(fs.truncation.rms, rms);
  // Negative control
  ASSERT_GT(diff[worst], 0.05f);
  std::vector<float> lowered = b.truncation;
  lowered[worst] = 0.0f;
  const std::vector<std::size_t> caught = under(lowered);
  ASSERT_EQ(caught.size(), 1u);
  EXPECT_EQ(caught[0], worst);
  double lowered2 = 0.0;
  for (float t : lowered) lowered2 += double(t) * t;
  EXPECT_GE(std::sqrt(lowered2 / double(lowered.size())), rms);  // the RMS comparison alone misses it
}

// Over a transparent background (alpha 0, as in VTK's layered renderers) a translucent quad with kt = 0.75 gets
// alpha 0.25 and premultiplied colour 0.25 * local; what is behind is left to the compositor.
TEST(Integrator, TranslucentHitOverTransparentBackgroundHasPartialAlpha) {
  Scene s;
  Material m = unlit(Color(0.8f, 0.4f, 0.2f));
  m.opacity = 0.25f;
  m.transmittance = Color(0.75f);
  addObject(s, makeGrid(Vec3(-1, -1, 0), Vec3(2, 0, 0), Vec3(0, 2, 0), 1, 1), m);
  s.background = Color(0.0f, 0.0f, 1.0f);
  s.backgroundAlpha = 0.0f;
  s.commit();
  Integrator integ(s, IntegratorSettings{}, Vec3(0, 1, 0));
  RayStats st;
  Sample smp = integ.trace(ray(Vec3(0, 0, 5), Vec3(0, 0, -1)), st, Color(0.0f));
  EXPECT_NEAR(smp.alpha, 0.25f, 1e-6f);
  EXPECT_NEAR(smp.color.x, 0.25f * 0.8f, 1e-6f);
  EXPECT_NEAR(smp.color.z, 0.25f * 0.2f, 1e-6f);  // no background colour mixed in
  s.backgroundAlpha = 1.0f;                       // opaque background: traced through, alpha 1
  s.commit();
  Integrator opaque(s, IntegratorSettings{}, Vec3(0, 1, 0));
  smp = opaque.trace(ray(Vec3(0, 0, 5), Vec3(0, 0, -1)), st, s.background);
  EXPECT_NEAR(smp.alpha, 1.0f, 1e-6f);
  EXPECT_NEAR(smp.color.z, 0.25f * 0.2f + 0.75f * 1.0f, 1e-6f);
}

// Exact Fresnel against the analytic values: ((n-1)/(n+1))^2 at normal incidence, 1 at grazing, 0 without an
// interface (IOR 1) at every angle, symmetric inside/outside at corresponding angles.
TEST(Integrator, FresnelMatchesAnalyticValues) {
  for (double n : {1.33, 1.5, 2.4}) {
    const double r0 = (n - 1) / (n + 1) * (n - 1) / (n + 1);
    EXPECT_NEAR(fresnelDielectric(1.0, 1.0, 1.0 / n), r0, 1e-12);
    EXPECT_NEAR(fresnelDielectric(1.0, 1.0, n), r0, 1e-12);
    const double cosi = 1e-9, sint = std::sqrt(1.0 - cosi * cosi) / n;
    EXPECT_GT(fresnelDielectric(cosi, std::sqrt(1.0 - sint * sint), 1.0 / n), 0.999999);
    // Entering at theta_i and leaving at the corresponding inner angle reflect the same share
    const double ci = std::cos(0.7), ct = std::sqrt(1.0 - std::sin(0.7) * std::sin(0.7) / (n * n));
    EXPECT_NEAR(fresnelDielectric(ci, ct, 1.0 / n), fresnelDielectric(ct, ci, n), 1e-12);
  }
  for (double c : {1.0, 0.5, 0.1, 1e-6}) EXPECT_EQ(fresnelDielectric(c, c, 1.0), 0.0);
}

// Fresnel in the integrator: a glass half-space (n = 1.5, kt = 1) over a black floor seen at normal incidence
// against a white background reflects exactly r0 of the background; at IOR 1 nothing at any angle; with
// reflections off the Fresnel share is not moved to a ray that is not traced, so nothing is lost.
TEST(Integrator, FresnelShareInTheImage) {
  auto traceAt = [](float ior, double angle, bool reflections) {
    Scene s;
    addObject(s, makeBoxMesh(Vec3(-1e3, -1e3, -1e3), Vec3(1e3, 1e3, 0)), glassMaterial(ior));
    s.background = Color(1.0f);
    s.commit();
    IntegratorSettings is;
    is.fresnel = true;
    is.reflections = reflections;
    is.contributionThreshold = 0.0f;
    Integrator integ(s, is, Vec3(0, 1, 0));
    RayStats st;
      Sample smp = integ.trace(ray(Vec3(0, 0, 1), Vec3(std::sin(angle), 0, -std::cos(angle))), st, Color(1.0f));
    return std::make_pair(smp, st);
  };
  auto [normal, st] = traceAt(1.5f, 0.0, true);
  EXPECT_GE(st.reflection, 1u);
  // Everything (reflected + transmitted) ends at the white background: energy is conserved exactly
  EXPECT_NEAR(normal.color.x, 1.0f, 1e-5f);
  auto [iorOne, st1] = traceAt(1.0f, 1.4, true);
  EXPECT_EQ(st1.reflection, 0u) << "IOR 1: no interface, no reflected ray";
  EXPECT_NEAR(iorOne.color.x, 1.0f, 1e-6f);
  auto [noRefl, st2] = traceAt(1.5f, 0.0, false);
  EXPECT_EQ(st2.reflection, 0u);
  EXPECT_NEAR(noRefl.color.x, 1.0f, 1e-5f) << "reflections off: the Fresnel share must not be lost";
}

// What escaped rays see: a straight escape (miss, or through an IOR-1 surface) sees the screen background
// behind its pixel, through alpha when backgroundAlpha is 0; a mirrored ray sees the environment in its
// direction (gradient by elevation along the view-up) as an opaque colour.
TEST(Integrator, EscapedRaysSeeScreenBackgroundOrEnvironment) {
  Scene s;
  Material mirror;
  mirror.diffuse = 0.0f;
  mirror.reflectance = Color(1.0f);
  // A mirror facing +z, tilted so that rays from +z reflect straight up (+y)
  Mat4 tilt = glm::rotate(Mat4(1.0), glm::radians(-45.0), Vec3(1, 0, 0));
  addObject(s, makeGrid(Vec3(-1, -1, 0), Vec3(2, 0, 0), Vec3(0, 2, 0), 1, 1), mirror, tilt);
  s.background = Color(0.1f, 0.2f, 0.3f);
  s.background2 = Color(0.9f, 0.8f, 0.7f);
  s.gradientBackground = true;
  s.backgroundAlpha = 0.0f;
  s.commit();
  Integrator integ(s, IntegratorSettings{}, Vec3(0, 1, 0));
  RayStats st;
  Sample up = integ.trace(ray(Vec3(0, 0, 5), Vec3(0, 0, -1)), st, Color(0.5f));
  EXPECT_NEAR(up.alpha, 1.0f, 1e-6f);
  EXPECT_NEAR(up.color.x, 0.9f, 1e-5f) << "reflected straight up: the top colour";
  Sample miss = integ.trace(ray(Vec3(0, 0, 5), Vec3(1, 0, 0)), st, Color(0.5f));
  EXPECT_EQ(miss.alpha, 0.0f);
  EXPECT_EQ(miss.color, Color(0.0f)) << "a miss leaves the screen background to what is drawn behind";
  EXPECT_EQ(st.safetyNetCatches(), 0u);
}

// Beer-Lambert: exp(-absorption x distance) through a 10-unit glass block, and exactly 1 without absorption.
// (A path longer than float's range used to give 0 x inf = NaN with no absorption, zeroed by the safety net and
// found by the fuzzer once the net's count was asserted: testing/fuzz/corpus/scene/beer-lambert-inf-times-zero.)
TEST(Integrator, BeerLambertAbsorption) {
  for (float absorption : {0.0f, 1e-3f, 0.1f}) {
    Scene s;
    Material glass = glassMaterial(1.0f);
    glass.absorption = Color(absorption);
    addObject(s, makeBoxMesh(Vec3(-1, -1, -10), Vec3(1, 1, 0)), glass);
    s.background = Color(1.0f);
    s.commit();
    IntegratorSettings is;
    is.beerLambert = true;
    Integrator integ(s, is, Vec3(0, 1, 0));
    RayStats st;
    Sample smp = integ.trace(ray(Vec3(0, 0, 1), Vec3(0, 0, -1)), st, Color(1.0f));
    EXPECT_EQ(st.safetyNetCatches(), 0u);
    EXPECT_EQ(st.refraction, 2u);
    EXPECT_NEAR(smp.color.x, std::exp(-10.0 * absorption), 1e-6);
  }
}
