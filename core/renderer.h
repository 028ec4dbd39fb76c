// Renderer: splits the image into tiles handed to all cores from a work queue, runs the integrator for each
// sample, and fills linear RGBA and OpenGL-depth buffers. Output is bit-identical for any thread count: sample
// positions are a deterministic function of (pixel, sample index) and statistics are summed per pixel/tile.
#pragma once

#include "camera.h"
#include "integrator.h"

#include <functional>
#include <vector>

namespace whitted {

/// Linear float buffers, rows bottom to top (OpenGL / VTK order).
struct FrameBuffer {
  int width = 0, height = 0;
  std::vector<Color4> color;    ///< Linear RGBA, premultiplied by alpha (not clamped).
  std::vector<float> depth;     ///< OpenGL window depth in [0,1]; 1 where nothing was hit.
  std::vector<uint8_t> traced;  ///< 1 where this process traced the pixel (see RenderSettings::tileStride).
  void resize(int w, int h);
};

struct RenderSettings {
  IntegratorSettings integrator;
  int samplesPerPixel = 1;  ///< Stratified samples per pixel; 1 = the pixel centre. Default 1.
  bool adaptive = false;    ///< Centre sample first, full samples only where neighbours differ. Default off.
  /// Supersampling trigger (adaptive): a pixel's centre sample differs from the mean of its two neighbours on an
  /// axis by more than this (max channel), or a neighbour hits where it misses.
  float adaptiveThreshold = 2.0f / 255.0f;
  int threads = 0;    ///< Worker threads; 0 = hardwareThreads() (all usable cores). Default 0.
  int tileSize = 16;  ///< Tile edge in pixels. Default 16.
  /// Pixel split between processes: this process traces tiles with index % tileStride == tileOffset, and writes
  /// depth 1 / alpha 0 elsewhere (for sort-last compositing). Default 1/0 = everything.
  int tileStride = 1;
  int tileOffset = 0;
  /// Called on the calling thread between tiles; return true to abort the frame. May be empty.
  std::function<bool()> abortCheck;
  /// Called on the calling thread with the fraction done. May be empty.
  std::function<void(double)> progress;
};

struct FrameStats {
  double secondsTrace = 0.0;  ///< Wall time of tracing (all passes).
  RayStats rays;
  uint64_t samples = 0;             ///< Camera samples taken.
  uint64_t pixelsSupersampled = 0;  ///< Adaptive mode: pixels that got the full sample count.
  double errorEstimateRms = 0.0;    ///< RMS over pixels of the per-pixel bound on radiance left out (clamped to 1).
  double errorEstimateMax = 0.0;    ///< Largest per-pixel bound.
  bool aborted = false;
  int threads = 1;
  bool kernelReflection = false, kernelRefraction = false, kernelShadows = false;
};

/// Renders scene (committed) through camera into fb (resized to width x height).
FrameStats render(const Scene& scene, const Camera& camera, const RenderSettings& settings, int width, int height,
                  FrameBuffer& fb);

/// Number of cores this process may run on (its CPU affinity on Linux, else the hardware threads; at least 1):
/// what RenderSettings::threads = 0 uses.
int hardwareThreads();

}  // namespace whitted
