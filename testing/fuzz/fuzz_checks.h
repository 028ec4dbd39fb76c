// The frame checks every fuzz target applies to what it rendered, and what "valid input" means for each.
//
// The renderer has four safety nets (RayStats): non-finite sample colours zeroed (nonFiniteSamples), coverage
// outside [0, 1] clamped (clampedAlpha), first-hit depth outside [0, 1] clamped (clampedDepth), non-finite pixels
// zeroed (nonFinitePixels). What they catch is hidden from the image, so checking the image alone proves nothing:
// a net must catch nothing for valid input, and the image must satisfy checks the nets do not enforce.
//
// Valid input:
// - For nonFiniteSamples, nonFinitePixels and clampedAlpha: any scene after Scene::commit() (which sanitises
//   materials, lights and background and leaves out non-finite or degenerate primitives; the fuzz targets
//   sanitise nothing themselves beyond what the VTK adapter does) seen by ANY camera matrix, even a singular or
//   non-finite one (its rays then miss and see the background).
// - For clampedDepth, in addition a camera as vtkCamera makes one (Camera::perspective / parallel: finite eye,
//   focal point and view-up, eye != focal point, view-up not along the view direction, 0 < near < far) in a
//   domain where double rounding cannot move a hit across a clip plane: eye, focal point, geometry and the
//   instance transforms' translations within 1e3 in magnitude, instance transforms rotation x scale with scales in
//   [1e-3, 1e3], near >= 1e-3 and far <= 1e4 x near (see TameCamera). Outside it (e.g. a triangle with vertices at
//   1e150 whose hit point is rounded by 1e134, or a "camera" with its near plane behind the eye) the net may catch
//   depths, as it is there to. The net counts a depth outside [0, 1] (by 1e-6) only when no point within the
//   sample's firstHitSlack (the hit point's error bound plus its distance from the camera ray: a surface point
//   projected onto a tube that crosses the near plane can lie 1e-9 in front of it, depth -4.5e-6 with near 1e-3,
//   fuzz_scene from seed 1 at input 21969) along the view direction is inside. Asserted zero on valid cameras;
//   Renderer.SafetyNetClampedDepthTripsOnNearPlaneBehindTheEye and the clampedDepth control show it can fire.
//
// The image checks (each can fail; WHITTED_FUZZ_CORRUPT shows it):
// - every colour and alpha component finite, colour >= 0 (sanitised input has no negative colour or weight);
// - every depth finite and in [0, 1];
// - with one sample per pixel (the pixel centre), against an independent Scene::intersect of the pixel's camera
//   ray: depth exactly 1 where that ray hits nothing; with a valid camera, where it hits, depth within 1e-4 of the
//   GL depth (0.5 z/w + 0.5) of that hit's surface point.
//
// Negative controls: with WHITTED_FUZZ_CORRUPT set, corruptFrame() breaks one thing after the render and before
// the checks (a net's count + 1, or one pixel's colour or depth) and the target aborts with the check's report;
// testing/fuzz/CMakeLists.txt runs each mode as a test that passes only if that report appears.
#pragma once

#include "image/renderer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace whitted_fuzz {

/// WHITTED_FUZZ_CORRUPT, read once: "" (normal), or one of kCorruptions.
inline const std::string& corruption() {
  static const std::string mode = [] {
    const char* e = std::getenv("WHITTED_FUZZ_CORRUPT");
    return std::string(e ? e : "");
  }();
  return mode;
}

constexpr const char* kCorruptions[] = {"nonFiniteSamples", "clampedAlpha", "clampedDepth", "nonFinitePixels",
                                        "color-nan",        "color-negative", "depth-nan",  "depth-range",
                                        "depth-miss",       "depth-hit"};

[[noreturn]] inline void fail(const std::string& what) {
  std::fprintf(stderr, "fuzz check failed: %s\n", what.c_str());
  std::abort();
}

/// A camera from fuzz values mapped into the valid domain above (any doubles give a valid camera): eye and focal
/// point within 1e3, view-up made non-parallel to the view direction, view angle in [1, 179] degrees or a
/// parallel scale in [1e-3, 1e3], near in [1e-3, 10], far / near in [1.5, 1e4].
inline whitted::Camera tameCamera(const double v[13], bool parallel) {
  using whitted::Vec3;
  auto tame = [](double x, double range) { return std::isfinite(x) ? std::fmod(x, range) : 0.0; };
  auto positive = [&](double x, double lo, double range) { return lo + std::abs(tame(x, range)); };
  const Vec3 eye(tame(v[0], 1e3), tame(v[1], 1e3), tame(v[2], 1e3));
  Vec3 focal(tame(v[3], 1e3), tame(v[4], 1e3), tame(v[5], 1e3));
  Vec3 up(tame(v[6], 1e3), tame(v[7], 1e3), tame(v[8], 1e3));
  if (!(glm::length(focal - eye) >= 1e-3)) focal = eye + Vec3(0.0, 0.0, -1.0);
  const Vec3 dir = glm::normalize(focal - eye);
  if (!(glm::length(glm::cross(up, dir)) >= 1e-3 * glm::length(up))) {  // also catches up = 0
    up = std::abs(dir.y) < 0.9 ? Vec3(0.0, 1.0, 0.0) : Vec3(1.0, 0.0, 0.0);
  }
  const double nearDist = positive(v[10], 1e-3, 10.0);
  const double farDist = nearDist * positive(v[11], 1.5, 1e4 - 1.5);
  if (parallel) {
    return whitted::Camera::parallel(eye, focal, up, positive(v[12], 1e-3, 1e3), 1.0, nearDist, farDist);
  }
  return whitted::Camera::perspective(eye, focal, up, positive(v[9], 1.0, 178.0), 1.0, nearDist, farDist);
}

/// The test-only corruption of a rendered frame (see above); says what it did, or "" when off or when the mode
/// needs a pixel this frame does not have (depth-miss / depth-hit: one sample per pixel and a pixel whose
/// reference ray misses / hits). endOfInput() then fails, so a control test cannot pass undetected.
inline std::string corruptFrame(const whitted::Scene& scene, const whitted::Camera& camera, int spp,
                                whitted::FrameStats& fs, whitted::FrameBuffer& fb) {
  const std::string& mode = corruption();
  if (mode.empty()) return "";
  if (mode == "nonFiniteSamples") ++fs.rays.nonFiniteSamples;
  else if (mode == "clampedAlpha") ++fs.rays.clampedAlpha;
  else if (mode == "clampedDepth") ++fs.rays.clampedDepth;
  else if (mode == "nonFinitePixels") ++fs.rays.nonFinitePixels;
  else if (mode == "color-nan") fb.color[0].x = std::nanf("");
  else if (mode == "color-negative") fb.color[0].y = -0.25f;
  else if (mode == "depth-nan") fb.depth[0] = std::nanf("");
  else if (mode == "depth-range") fb.depth[0] = 1.5f;
  else if (mode == "depth-miss" || mode == "depth-hit") {
    const bool wantHit = mode == "depth-hit";
    for (int y = 0; y < fb.height && spp == 1; ++y)
      for (int x = 0; x < fb.width; ++x) {
        whitted::Hit hit;
        if (scene.intersect(camera.rayPixel(x + 0.5, y + 0.5, fb.width, fb.height), hit) == wantHit) {
          float& d = fb.depth[std::size_t(y) * fb.width + x];
          d = wantHit ? (d < 0.5f ? 1.0f : 0.0f) : 0.5f;
          return mode + " at pixel " + std::to_string(x) + "," + std::to_string(y);
        }
      }
    return "";
  } else {
    fail("unknown WHITTED_FUZZ_CORRUPT mode " + mode);
  }
  return mode;
}

/// Checks a rendered frame (see above) and aborts with a report on the first failure. validCamera: camera and
/// scene are in the domain where clampedDepth must be 0 and a hit's depth is checked.
inline void checkFrame(const whitted::Scene& scene, const whitted::Camera& camera, int spp, bool validCamera,
                       whitted::FrameStats fs, whitted::FrameBuffer fb) {
  const std::string corrupted = corruptFrame(scene, camera, spp, fs, fb);
  if (!corrupted.empty()) std::fprintf(stderr, "WHITTED_FUZZ_CORRUPT: %s\n", corrupted.c_str());
  // The safety nets
  const whitted::RayStats& r = fs.rays;
  const std::pair<const char*, uint64_t> nets[] = {{"nonFiniteSamples", r.nonFiniteSamples},
                                                   {"clampedAlpha", r.clampedAlpha},
                                                   {"nonFinitePixels", r.nonFinitePixels},
                                                   {"clampedDepth", validCamera ? r.clampedDepth : 0}};
  for (const auto& net : nets)
    if (net.second != 0)
      fail(std::string("safety net ") + net.first + " caught " + std::to_string(net.second) + " on valid input");
  // Colour and depth of every pixel
  for (std::size_t i = 0; i < fb.color.size(); ++i) {
    const whitted::Color4& c = fb.color[i];
    char buf[160];
    std::snprintf(buf, sizeof buf, "pixel %zu: colour %g %g %g %g, depth %g", i, c.x, c.y, c.z, c.w, fb.depth[i]);
    for (int k = 0; k < 4; ++k)
      if (!std::isfinite(c[k])) fail(std::string("non-finite colour at ") + buf);
    if (!(c.x >= 0.0f && c.y >= 0.0f && c.z >= 0.0f)) fail(std::string("negative colour at ") + buf);
    if (!std::isfinite(fb.depth[i])) fail(std::string("non-finite depth at ") + buf);
    if (!(fb.depth[i] >= 0.0f && fb.depth[i] <= 1.0f)) fail(std::string("depth outside [0, 1] at ") + buf);
  }
  // Depth against an independent intersection of each pixel's one camera ray
  if (spp != 1) return;
  for (int y = 0; y < fb.height; ++y)
    for (int x = 0; x < fb.width; ++x) {
      const whitted::Ray ray = camera.rayPixel(x + 0.5, y + 0.5, fb.width, fb.height);
      whitted::Hit hit;
      const float d = fb.depth[std::size_t(y) * fb.width + x];
      char buf[160];
      if (!scene.intersect(ray, hit)) {
        if (d != 1.0f) {
          std::snprintf(buf, sizeof buf, "pixel %d,%d: depth %.9g where its camera ray hits nothing", x, y, d);
          fail(buf);
        }
      } else if (validCamera) {
        // The depth of the hit's surface point, as the tracer writes it: the surface point is the ray point
        // re-projected onto the surface (within the hit's rounding), and next to the near plane a depth changes
        // by 1e-4 for 1e-7 of distance (seen: a tube 1.2e-7 off the ray point gave 1.5e-4)
        const double z = camera.glDepth(scene.surface(ray, hit).p);
        const double expected = std::clamp(std::isfinite(z) ? z : 1.0, 0.0, 1.0);
        if (!(std::abs(d - expected) <= 1e-4)) {
          std::snprintf(buf, sizeof buf, "pixel %d,%d: depth %.9g, but its camera ray hits at depth %.9g", x, y, d,
                        expected);
          fail(buf);
        }
      }
    }
}

/// Called at the end of every input: with WHITTED_FUZZ_CORRUPT set, reaching it means no check caught the
/// corruption (or no frame could be corrupted), which fails the control.
inline void endOfInput() {
  if (!corruption().empty()) fail("corruption " + corruption() + " was not detected by any check");
}

}  // namespace whitted_fuzz
