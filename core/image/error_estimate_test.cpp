// The frame's error estimate: the truncation bound is never under the measured truncation error at any pixel
// (stiff scenes: facing mirrors, nested glass, a light inside glass; and the classic scene), over depth caps and
// thresholds; the sampling estimate's coverage against a many-sample reference. Progressive refinement by the
// estimate is tested in refinement_test.cpp.
#include "image/renderer.h"
#include "scenes/stiff_scenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>

using namespace whitted;

namespace {

struct NamedScene {
  const char* name;
  std::function<void(Scene&, CameraSpec&)> build;
};

const NamedScene kScenes[] = {{"mirrors", buildFacingMirrorsScene},
                              {"nested-glass", buildNestedGlassScene},
                              {"light-in-glass", buildLightInGlassScene},
                              {"classic", [](Scene& s, CameraSpec& c) { buildClassicScene(s, c); }}};

// Largest channel difference of the clamped colours (what the estimates are stated in)
float pixelDifference(const Color4& a, const Color4& b) {
  float d = 0.0f;
  for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(std::clamp(a[c], 0.0f, 1.0f) - std::clamp(b[c], 0.0f, 1.0f)));
  return d;
}

// A stiff scene at w x h with its truncation reference: same samples, depth 16 (the truncation reference depth),
// threshold 0
struct Truncated {
  Scene scene;
  Camera cam;
  FrameBuffer ref;
  Truncated(const std::function<void(Scene&, CameraSpec&)>& build, int w, int h) {
    CameraSpec cs;
    build(scene, cs);
    scene.commit();
    cam = cs.make(double(w) / h, scene.bounds());
    RenderSettings rs;
    rs.integrator.maxDepth = 16;
    rs.integrator.contributionThreshold = 0.0f;
    render(scene, cam, rs, w, h, ref);
  }
  // A truncated render against the reference: RMS of the measured error, pixels whose bound is under it by > slack
  struct Check {
    double measuredRms = 0.0;
    int under = 0;
  };
  Check check(const FrameBuffer& fb, float slack) const {
    Check c;
    double measured2 = 0.0;
    for (std::size_t i = 0; i < ref.color.size(); ++i) {
      const float d = pixelDifference(ref.color[i], fb.color[i]);
      measured2 += double(d) * d;
      if (fb.truncation[i] + slack < d) ++c.under;
    }
    c.measuredRms = std::sqrt(measured2 / double(ref.color.size()));
    return c;
  }
};

}  // namespace

// At every pixel, for every depth cap and threshold: the bound >= |render - reference|, where the reference has the
// same samples, threshold 0 and depth 16 (the truncation reference depth: in the nested-glass scene kr + kt = 1 and
// the series does not converge). The largest measured error is asserted to be large, so replacing the bound by any
// constant below it fails; the RMS ratio bound / measured is printed (tightness). Every lookahead is checked: 0
// (every cut ray charged the scene-wide bound), 1 (the default) and 2 levels of bound rays, and the adaptive one
// (1 level, more up to 16 while a charge is above 1/255); each level is never above the one before (a hit's charge
// is at most the scene-wide bound in every channel), the adaptive one never above 1 level, and none changes the
// image.
TEST(ErrorEstimate, TruncationBoundNeverUnderMeasuredOnStiffScenes) {
  const int w = 64, h = 48;
  for (const NamedScene& ns : kScenes) {
    Truncated t(ns.build, w, h);
    const Scene& s = t.scene;
    const Camera& cam = t.cam;
    const FrameBuffer& refFb = t.ref;
    float largest = 0.0f;
    int checked = 0;
    for (int depth : {0, 1, 2, 3, 5, 8})
      for (float thr : {0.0f, 1.0f / 255, 0.05f, 0.2f}) {
        RenderSettings rs;
        rs.integrator.maxDepth = depth;
        rs.integrator.contributionThreshold = thr;
        FrameBuffer fb[4];
        FrameStats fs[4];
        for (int look = 0; look < 4; ++look) {
          rs.integrator.truncationLookahead = look < 3 ? look : 1;
          rs.integrator.truncationTolerance = look < 3 ? 0.0f : 1.0f / 255;
          rs.integrator.truncationLookaheadMax = look < 3 ? 0 : 16;
          fs[look] = render(s, cam, rs, w, h, fb[look]);
        }
        EXPECT_EQ(fs[0].rays.boundRays, 0u);
        if (fs[1].rays.savedByDepth + fs[1].rays.savedByThreshold > 0) EXPECT_GT(fs[1].rays.boundRays, 0u);
        double measured2 = 0.0;
        int under[4] = {0, 0, 0, 0}, aboveLooser = 0;
        for (std::size_t i = 0; i < fb[1].color.size(); ++i) {
          const float d = pixelDifference(refFb.color[i], fb[1].color[i]);
          measured2 += double(d) * d;
          largest = std::max(largest, d);
          for (int look = 0; look < 4; ++look) {
            if (fb[look].truncation[i] + 1e-5f < d) ++under[look];
            ASSERT_EQ(fb[look].color[i], fb[1].color[i]) << i;
          }
          if (fb[1].truncation[i] > fb[0].truncation[i] + 1e-5f || fb[2].truncation[i] > fb[1].truncation[i] + 1e-5f ||
              fb[3].truncation[i] > fb[1].truncation[i] + 1e-5f)
            ++aboveLooser;
        }
        for (int look = 0; look < 4; ++look)
          EXPECT_EQ(under[look], 0) << ns.name << " depth " << depth << " threshold " << thr << " lookahead " << look;
        EXPECT_EQ(aboveLooser, 0) << ns.name << " depth " << depth << " threshold " << thr;
        const double measuredRms = std::sqrt(measured2 / double(fb[1].color.size()));
        if (measuredRms > 1e-4) {
          ++checked;
          std::printf(
              "%-15s depth %d thr %.4f: measured RMS %.4f, bound RMS %.4f (x%.1f; lookahead 0 x%.1f, 2 x%.1f, "
              "adaptive x%.1f), bound p95 %.4f, max %.4f\n",
              ns.name, depth, thr, measuredRms, fs[1].truncation.rms, fs[1].truncation.rms / measuredRms,
              fs[0].truncation.rms / measuredRms, fs[2].truncation.rms / measuredRms,
              fs[3].truncation.rms / measuredRms, fs[1].truncation.p95, fs[1].truncation.max);
        }
      }
    EXPECT_GT(largest, 0.05f) << ns.name << ": the settings must lose something for the check to mean anything";
    EXPECT_GT(checked, 4) << ns.name;
  }
}

// The tight bound (bound rays, lookahead 1) is really tighter than the scene-wide one (lookahead 0) where cut rays
// end on dim surfaces: in the classic scene at depth 5 the cut rays bounce between the spheres and mostly land on
// the floor or the background, and in the light-in-glass scene at depth 2 they land on the floor, while the
// scene-wide bound charges each the brightest surface's fixed point. Measured at 64x48: RMS ratio tight / loose
// 0.18 (classic) and 0.41 (light in glass); replacing the tight bound by the loose one gives 1 and fails.
TEST(ErrorEstimate, TightTruncationBoundIsTighterThanTheSceneWideOne) {
  struct Case {
    const NamedScene* scene;
    int depth;
    double most;
  };
  const Case cases[] = {{&kScenes[3], 5, 0.3}, {&kScenes[2], 2, 0.6}};
  for (const Case& c : cases) {
    Scene s;
    CameraSpec cs;
    c.scene->build(s, cs);
    s.commit();
    const Camera cam = cs.make(4.0 / 3.0, s.bounds());
    RenderSettings rs;
    rs.integrator.maxDepth = c.depth;
    rs.integrator.contributionThreshold = 0.0f;
    FrameBuffer fb;
    const FrameStats tight = render(s, cam, rs, 64, 48, fb);
    rs.integrator.truncationLookahead = 0;
    const FrameStats loose = render(s, cam, rs, 64, 48, fb);
    ASSERT_GT(loose.truncation.rms, 1e-4) << c.scene->name;
    std::printf("%s depth %d: truncation bound RMS tight %.5f, loose %.5f (x%.2f), %llu bound rays\n", c.scene->name,
                c.depth, tight.truncation.rms, loose.truncation.rms, tight.truncation.rms / loose.truncation.rms,
                (unsigned long long)tight.rays.boundRays);
    EXPECT_LT(tight.truncation.rms, c.most * loose.truncation.rms) << c.scene->name;
    EXPECT_GT(tight.rays.boundRays, 0u) << c.scene->name;
  }
}

// The adaptive lookahead follows a bound ray's secondary rays while their charge (path weight x kr + kt x the
// scene-wide remaining bound) is above the tolerance, so chains of mirrors and glass no longer end on that
// scene-wide figure. Facing mirrors (kr 0.9) at depth 8: every level lands on another mirror, and a fixed lookahead
// of 1 or 2 gives 5.6x / 5.4x the measured RMS; classic at depth 5 threshold 0.05: cut rays land on the glass ball
// (kr + kt = 1: the remaining bound grows to the reference depth), 13.7x at 1. Measured at 64x48 with the adaptive
// lookahead (1/255, up to 16 levels): 1.2x and 1.1x. Light in glass at depth 1: cut rays land on the floor, lit
// through the glass (transmittance 0.12), 6.4x at 1; the adaptive lookahead's exact shadow rays at hits with a large
// charge give 1.5x (2.4x with the unshadowed local term). Asserted: within the 2x of the measured RMS and
// below 0.4x the fixed lookahead's bound; the fixed lookahead (tolerance 0) fails both.
TEST(ErrorEstimate, AdaptiveLookaheadBoundWithinTwiceTheMeasured) {
  struct Case {
    const NamedScene* scene;
    int depth;
    float threshold;
  };
  const Case cases[] = {{&kScenes[0], 8, 0.0f}, {&kScenes[3], 5, 0.05f}, {&kScenes[2], 1, 0.0f}};
  const int w = 64, h = 48;
  for (const Case& c : cases) {
    Truncated t(c.scene->build, w, h);
    const Scene& s = t.scene;
    const Camera& cam = t.cam;
    FrameBuffer fixedFb, adaptiveFb;
    RenderSettings rs;
    rs.integrator.maxDepth = c.depth;
    rs.integrator.contributionThreshold = c.threshold;
    rs.integrator.truncationLookahead = 1;
    rs.integrator.truncationTolerance = 0.0f;
    const FrameStats fixed = render(s, cam, rs, w, h, fixedFb);
    rs.integrator.truncationTolerance = 1.0f / 255;
    rs.integrator.truncationLookaheadMax = 16;
    const FrameStats adaptive = render(s, cam, rs, w, h, adaptiveFb);
    const auto [measuredRms, under] = t.check(adaptiveFb, 1e-5f);
    ASSERT_GT(measuredRms, 1e-3) << c.scene->name;
    std::printf(
        "%s depth %d thr %.3f: measured RMS %.5f, bound RMS fixed lookahead x%.2f, adaptive x%.2f (%llu / %llu "
        "bound rays)\n",
        c.scene->name, c.depth, c.threshold, measuredRms, fixed.truncation.rms / measuredRms,
        adaptive.truncation.rms / measuredRms, (unsigned long long)fixed.rays.boundRays,
        (unsigned long long)adaptive.rays.boundRays);
    EXPECT_EQ(under, 0) << c.scene->name;
    EXPECT_LT(adaptive.truncation.rms, 2.0 * measuredRms) << c.scene->name;
    EXPECT_LT(adaptive.truncation.rms, 0.4 * fixed.truncation.rms) << c.scene->name;
  }
}

// Many small charges: light in glass at depth 5, threshold 1/255. Every cut ray is charged under the absolute
// tolerance (1/255), so with it alone each keeps its scene-wide charge (unshadowed light, the remaining bound),
// while the light reaches the floor through the glass at 0.12: the bound is several times the measured error. The
// relative tolerance (1/8 of each cut ray's own first charge) follows those rays further where a level halves the
// charge (the glass: kr + kt = 0.45). Asserted: never under at any pixel, within 2x of the measured RMS with the
// relative tolerance, and over 2.5x without it (so the first assertion fails when the relative rule is dropped).
TEST(ErrorEstimate, RelativeToleranceBoundsManySmallCharges) {
  const int w = 64, h = 48;
  Truncated t(buildLightInGlassScene, w, h);
  const Scene& s = t.scene;
  const Camera& cam = t.cam;
  FrameBuffer absFb, relFb;
  RenderSettings rs;
  rs.integrator.maxDepth = 5;
  rs.integrator.contributionThreshold = 1.0f / 255;
  ASSERT_GT(rs.integrator.truncationRelativeTolerance, 0.0f);  // on by default
  const FrameStats rel = render(s, cam, rs, w, h, relFb);
  rs.integrator.truncationRelativeTolerance = 0.0f;
  const FrameStats abs = render(s, cam, rs, w, h, absFb);
  for (std::size_t i = 0; i < relFb.color.size(); ++i)
    EXPECT_EQ(relFb.color[i], absFb.color[i]) << i;  // colours do not depend on it
  const auto [measuredRms, under] = t.check(relFb, 1e-6f);
  ASSERT_GT(measuredRms, 5e-5);
  std::printf(
      "light in glass depth 5 thr 1/255: measured RMS %.6f, bound RMS absolute tolerance x%.2f, relative "
      "x%.2f (%llu / %llu bound rays)\n",
      measuredRms, abs.truncation.rms / measuredRms, rel.truncation.rms / measuredRms,
      (unsigned long long)abs.rays.boundRays, (unsigned long long)rel.rays.boundRays);
  EXPECT_EQ(under, 0);
  EXPECT_LT(rel.truncation.rms, 2.0 * measuredRms);
  EXPECT_GT(abs.truncation.rms, 2.5 * measuredRms);
}

// The adaptive lookahead's bound rays per cut ray are capped (truncationBoundRays): a cut ray whose levels branch
// at every hit (nested glass: each surface reflects and refracts) would otherwise trace up to 2^16 of them. Nested
// glass at depth 1 with a tolerance of 1e-6 (so every branch is followed to 16 levels while its charge is above it):
// without the cap, 192 bound rays per cut ray on average (up to thousands); with a cap of 64, 48.7 on average (a cut
// ray stops adding levels at 64; the branches under way finish, plus their hits' shadow rays: the frame's total is
// asserted, not each cut ray's count), the capped cut rays are counted, the bound is still never under the measured
// error at any pixel, never below the uncapped one, and the image is the same.
TEST(ErrorEstimate, BoundRaysPerCutRayAreCapped) {
  const int w = 32, h = 24;
  Truncated t(buildNestedGlassScene, w, h);
  RenderSettings rs;
  rs.integrator.maxDepth = 1;
  rs.integrator.contributionThreshold = 0.0f;
  rs.integrator.truncationTolerance = 1e-6f;
  rs.integrator.truncationBoundRays = 1 << 30;
  FrameBuffer freeFb, cappedFb;
  const FrameStats uncapped = render(t.scene, t.cam, rs, w, h, freeFb);
  const int cap = 64;
  rs.integrator.truncationBoundRays = cap;
  const FrameStats capped = render(t.scene, t.cam, rs, w, h, cappedFb);
  const uint64_t cut = capped.rays.savedByDepth + capped.rays.savedByThreshold;
  ASSERT_EQ(cut, uncapped.rays.savedByDepth + uncapped.rays.savedByThreshold);
  ASSERT_GT(cut, 0u);
  std::printf("nested glass depth 1, tolerance 1e-6: %llu cut rays; bound rays %llu uncapped (%.0f per cut ray), "
              "%llu with a cap of %d (%.1f per cut ray, %llu cut rays capped)\n",
              (unsigned long long)cut, (unsigned long long)uncapped.rays.boundRays,
              double(uncapped.rays.boundRays) / double(cut), (unsigned long long)capped.rays.boundRays, cap,
              double(capped.rays.boundRays) / double(cut), (unsigned long long)capped.rays.boundRaysCapped);
  EXPECT_EQ(uncapped.rays.boundRaysCapped, 0u);
  EXPECT_GT(uncapped.rays.boundRays, 2 * cap * cut);  // the scene branches past the cap (on average)
  EXPECT_GT(capped.rays.boundRaysCapped, 0u);
  const uint64_t lights = t.scene.lights().size();
  // per cut ray: the cap, the branches under way (up to truncationLookaheadMax), each with its shadow rays
  EXPECT_LE(capped.rays.boundRays,
            cut * uint64_t(cap + rs.integrator.truncationLookaheadMax) * (1 + lights));
  EXPECT_EQ(t.check(cappedFb, 1e-6f).under, 0);
  for (std::size_t i = 0; i < cappedFb.color.size(); ++i) {
    ASSERT_EQ(cappedFb.color[i], freeFb.color[i]) << i;
    ASSERT_GE(cappedFb.truncation[i], freeFb.truncation[i]) << i;
  }
}

// Light cut from shadow rays: with depth 16 no ray is cut by depth in the light-in-glass scene, and with
// reflections and refractions off no secondary ray exists, so only the shadow rays' cut (transmittance 0.1225
// below the threshold 0.2) is left out, and the bound must cover it.
TEST(ErrorEstimate, ShadowRaysCutByTheThresholdAreBounded) {
  Scene s;
  CameraSpec cs;
  buildLightInGlassScene(s, cs);
  for (uint32_t m = 0; m < s.materialCount(); ++m) s.material(m).reflectance = Color(0.0f);
  s.commit();
  const Camera cam = cs.make(4.0 / 3.0, s.bounds());
  RenderSettings rs;
  rs.integrator.refractions = false;
  rs.integrator.maxDepth = 0;
  rs.integrator.contributionThreshold = 0.0f;
  FrameBuffer ref, cut;
  render(s, cam, rs, 48, 36, ref);
  rs.integrator.contributionThreshold = 0.2f;
  render(s, cam, rs, 48, 36, cut);
  float largest = 0.0f;
  std::size_t at = 0;
  for (std::size_t i = 0; i < ref.color.size(); ++i) {
    const float d = pixelDifference(ref.color[i], cut.color[i]);
    if (d > largest) largest = d, at = i;
    EXPECT_GE(cut.truncation[i] + 1e-5f, d) << i;
  }
  // maxDepth 0 also cuts the straight-through transmitted rays (bounded in both renders): where the threshold
  // lost most, that part alone would not cover the loss, so the shadow part of the bound is what holds the check
  EXPECT_GT(largest, ref.truncation[at]);
  EXPECT_GT(largest, 0.02f);  // the floor lit through both boxes really loses light
}

// Images do not depend on the estimates, which are the same for any thread count.
TEST(ErrorEstimate, EstimatesAreSideDataAndDeterministic) {
  Scene s;
  CameraSpec cs;
  buildNestedGlassScene(s, cs);
  s.commit();
  const Camera cam = cs.make(4.0 / 3.0, s.bounds());
  RenderSettings rs;
  rs.samplesPerPixel = 4;
  rs.threads = 1;
  FrameBuffer a, b, c;
  const FrameStats fa = render(s, cam, rs, 40, 30, a);
  rs.errorEstimates = false;
  render(s, cam, rs, 40, 30, b);
  rs.errorEstimates = true;
  rs.threads = 3;
  const FrameStats fc = render(s, cam, rs, 40, 30, c);
  EXPECT_EQ(0, std::memcmp(a.color.data(), b.color.data(), a.color.size() * sizeof(Color4)));
  EXPECT_EQ(a.truncation, c.truncation);
  EXPECT_EQ(a.sampling, c.sampling);
  EXPECT_EQ(fa.sampling.rms, fc.sampling.rms);
  EXPECT_GT(fa.sampling.max, 0.0);
  EXPECT_GE(fa.sampling.max, fa.sampling.p95);
  EXPECT_GE(fa.sampling.p95, 0.0);
  EXPECT_EQ(fa.truncation.rms > 0.0, true);
}

// The sampling estimate against the truth, a 256-sample render with the same depth and threshold: the share of
// pixels whose true error is within the estimate, at 4 and 16 samples (2 standard errors, stated ~95%) and at 1
// sample (the neighbour heuristic), over all pixels and over the pixels with an error of at least 1/255.
TEST(ErrorEstimate, SamplingEstimateCoverage) {
  for (const NamedScene& ns : kScenes) {
    Scene s;
    CameraSpec cs;
    ns.build(s, cs);
    s.commit();
    const Camera cam = cs.make(4.0 / 3.0, s.bounds());
    RenderSettings rs;
    rs.samplesPerPixel = 256;
    FrameBuffer truth;
    render(s, cam, rs, 48, 36, truth);
    for (int spp : {1, 4, 16}) {
      rs.samplesPerPixel = spp;
      FrameBuffer fb;
      render(s, cam, rs, 48, 36, fb);
      int covered = 0, nonzero = 0, nonzeroCovered = 0;
      for (std::size_t i = 0; i < fb.color.size(); ++i) {
        const float d = pixelDifference(truth.color[i], fb.color[i]);
        const bool ok = d <= fb.sampling[i] + 1.0f / 512;  // half an 8-bit step: the truth is 256 samples
        covered += ok;
        if (d >= 1.0f / 255) ++nonzero, nonzeroCovered += ok;
      }
      const double coverage = double(covered) / double(fb.color.size());
      std::printf("%-15s %3d spp: coverage %.3f, over the %d of %zu pixels with an error >= 1/255: %.3f\n", ns.name,
                  spp, coverage, nonzero, fb.color.size(), nonzero ? double(nonzeroCovered) / nonzero : 1.0);
      EXPECT_GT(coverage, 0.95) << ns.name << " " << spp;
      if (nonzero >= 50) EXPECT_GT(double(nonzeroCovered) / nonzero, 0.9) << ns.name << " " << spp;
    }
  }
}
