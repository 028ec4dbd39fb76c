// Error of an image against a reference, on linear RGB clamped to [0,1] (what an 8-bit framebuffer can show).
// The benchmark's one image-difference helper: the error sweep compares frame buffers in memory, the POV-Ray
// comparison compares PNG files through `whitted_bench diff`.
#pragma once

#include "image/renderer.h"

#include <string>

namespace whitted::bench {

struct ImageError {
  double rmse = 0.0;  ///< Root mean square over pixels and the three channels.
  double psnr = 0.0;  ///< 20 log10(1 / rmse) in dB (capped at 100 for identical images).
  double ssim = 1.0;  ///< Mean SSIM over RGB channels (Gaussian window sigma 1.5, 11 x 11; Wang et al. 2004).
  /// The quantity FrameStats::truncation bounds: per pixel the largest channel difference, then RMS (and
  /// max) over pixels. Compared against a reference traced with the same samples, it isolates the radiance left
  /// out by the depth cap and the contribution threshold.
  double maxChannelRms = 0.0;
  double maxChannelMax = 0.0;
  int maxLevels = 0;  ///< Largest channel difference in 8-bit levels (round(255 x maxChannelMax)).
};

/// Largest channel difference of two pixels' colours clamped to [0, 1] (the unit of the error estimates).
float maxChannelDifference(const Color4& a, const Color4& b);

/// Errors of img against ref (same size).
ImageError compareImages(const FrameBuffer& img, const FrameBuffer& ref);

/// Reads an 8-bit PNG (any colour type libpng converts to RGBA) into fb.color as values / 255, rows bottom to
/// top like a rendered frame. Returns false with a message on failure.
bool readPng(const std::string& path, FrameBuffer& fb, std::string& error);

/// A reference image's colours cached as raw floats (references take minutes to render): readColorCache resizes fb
/// to w x h and returns true if path holds a whole image of that size (the caller keeps a file to one scene and set
/// of settings); writeColorCache writes fb's colours there. An empty path reads nothing and writes nothing.
bool readColorCache(const std::string& path, int w, int h, FrameBuffer& fb);
void writeColorCache(const std::string& path, const FrameBuffer& fb);

}  // namespace whitted::bench
