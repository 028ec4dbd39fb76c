// Adaptive sampling (RenderSettings::adaptive): after a pass of centre samples, the full sample count only for the
// pixels whose neighbours do not predict them. The neighbour rule here is also the one-sample part of the
// sampling estimate (error_estimate.cpp).
#include "image/frame_job.h"

#include <algorithm>
#include <cmath>

namespace whitted {

void FrameJob::supersampleDisagreements(int n) {
  marks_.assign(std::size_t(w_) * h_, 0);
  markDisagreements();
  runPass([&](int tile) { tracePixels(tile, n, true); });
}

void FrameJob::markDisagreements() {
  for (int y = 0; y < h_; ++y)
    for (int x = 0; x < w_; ++x) {
      const std::size_t i = index(x, y);
      if (!fb_.traced[i]) continue;
      const auto [hitDiffers, diff] = unpredicted(x, y);
      marks_[i] = hitDiffers || diff > s_.adaptiveThreshold ? 1 : 0;
    }
}

// The second difference is the pixel against the mean of its two neighbours on an axis; at the image border,
// against the line through the two pixels on the inner side. A linear ramp (smooth shading) has none; edges,
// silhouettes, highlights and texture detail do.
std::pair<bool, float> FrameJob::unpredicted(int x, int y) const {
  auto clampC = [](const Color4& c) { return glm::clamp(c, Color4(0.0f), Color4(1.0f)); };
  auto maxAbs = [](const Color4& d) {
    return std::max(std::max(std::abs(d.x), std::abs(d.y)), std::max(std::abs(d.z), std::abs(d.w)));
  };
  auto traced = [&](int u, int v) { return u >= 0 && v >= 0 && u < w_ && v < h_ && fb_.traced[index(u, v)]; };
  const std::size_t i = index(x, y);
  const Color4 c = clampC(fb_.color[i]);
  bool hitDiffers = false;
  float diff = 0.0f;
  for (int axis = 0; axis < 2; ++axis) {
    const int dx = axis == 0 ? 1 : 0, dy = 1 - dx;
    const bool lo = traced(x - dx, y - dy), hi = traced(x + dx, y + dy);
    if ((lo && hitMask_[index(x - dx, y - dy)] != hitMask_[i]) ||
        (hi && hitMask_[index(x + dx, y + dy)] != hitMask_[i]))
      hitDiffers = true;
    if (lo && hi) {
      const Color4 mean =
          0.5f * (clampC(fb_.color[index(x - dx, y - dy)]) + clampC(fb_.color[index(x + dx, y + dy)]));
      diff = std::max(diff, maxAbs(c - mean));
    } else if (lo || hi) {
      const int s = hi ? 1 : -1;
      const Color4 n1 = clampC(fb_.color[index(x + s * dx, y + s * dy)]);
      const Color4 predicted = traced(x + 2 * s * dx, y + 2 * s * dy)
                                   ? 2.0f * n1 - clampC(fb_.color[index(x + 2 * s * dx, y + 2 * s * dy)])
                                   : n1;
      diff = std::max(diff, 0.5f * maxAbs(c - predicted));
    }
  }
  return {hitDiffers, diff};
}

}  // namespace whitted
