// Progressive refinement (RenderSettings::targetError, timeBudget): its tuning numbers and what it measures to
// steer by. The rounds themselves (FrameJob::refine and its helpers) are in refinement.cpp.
#pragma once

#include "image/renderer.h"  // kMaxLoosening

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace whitted {

// How a round picks its pixels
/// Samples of the jittered grid that replaces a refined one-sample pixel's centre sample (as adaptive sampling's
/// second pass does); later rounds continue with the sequence.
constexpr int kFirstStrata = 4;
/// A round's rays, as a share of the rays of the image so far: rounds grow geometrically, so their re-estimates
/// cost little.
constexpr double kRoundShare = 0.5;
/// With a time budget, a round takes all the time left when a round of the usual size would leave less than this
/// many rounds' worth of it (what is left after it would be too little for another round).
constexpr double kBudgetRoundsLeft = 1.5;
/// A pixel is refined only if its total estimate is at least this share of the target error (refining pixels
/// already well below the target does little for the RMS).
constexpr double kLeastEstimateShare = 0.5;
/// A round near the target is cut to the pixels whose expected drop of the image's squared error is this many
/// times what the target still needs (rms^2 - target^2 summed over the pixels)
constexpr double kNeedMargin = 1.5;
/// The least squared sampling estimate a one-sample pixel is ranked by, as a share of the squared target: its
/// neighbour rule may miss a thin feature, so it stays a candidate even where its neighbours predict it.
constexpr double kMinimumVariance = 4.0;
/// With a TargetError, the first round gives every one-sample pixel on a fixed pattern (one in kProbeStride, see
/// probePixel) its grid, whatever its estimate: a sample of the one-sample pixels chosen independently of the image,
/// whose measured change (centre sample against its grid's mean) calibrates the neighbour rule of the pixels still
/// at one sample (RefineMeasures::probeMean): the target can count as met with such pixels left once every probe
/// is recorded. A bucket with fewer than kProbeMinimum probes keeps the neighbour rule.
constexpr int kProbeStride = 16;
/// Whether pixel (x, y) is on the probe pattern: one pixel in 16 per row, each row's shifted by 4 (spread over the
/// image like a rotated grid).
inline bool probePixel(int x, int y) { return (x + 4 * y) % kProbeStride == 0; }
/// Probes per estimate bucket before its mean replaces the neighbour rule.
constexpr int kProbeMinimum = 4;
/// Priority buckets of a round's selection (pixels ranked by gain per ray), each 1 / kBucketsPerOctave of an
/// octave of gain per ray, centred on a gain per ray of 1.
constexpr int kBuckets = 512;
constexpr float kBucketsPerOctave = 4.0f;

// The coarse level -1 of extra samples (see FrameJob::makeCoarse)
/// Contribution threshold of the coarse level: the frame's times kCoarseFactor, at most kCoarseThreshold (and never
/// below the frame's).
constexpr float kCoarseFactor = 16.0f;
constexpr float kCoarseThreshold = 64.0f / 255.0f;
/// A one-sample pixel's grid is traced coarse when its sampling estimate exceeds kCoarseMargin times its (scaled)
/// truncation bound: the coarse level's larger truncation hardly adds to such a pixel's error.
constexpr float kCoarseMargin = 4.0f;

// The loosening levels 1.. (see levelSettings in refinement.cpp)
/// Per level, maxDepth is multiplied by kLoosenDepthFactor, but grows by at least kLoosenDepthStep and up to
/// kLoosenMaxDepth, and the contribution threshold is divided by kLoosenThresholdDivisor.
constexpr int kLoosenDepthFactor = 2;
constexpr int kLoosenDepthStep = 2;
constexpr int kLoosenMaxDepth = 64;
constexpr float kLoosenThresholdDivisor = 16.0f;
/// Share of a pixel's truncation part a looser level is taken to leave (when choosing how to refine a pixel):
/// that of the threshold.
constexpr float kLoosenLeaves = 1.0f / kLoosenThresholdDivisor;
/// A contribution threshold below this is taken as 0: a level looser than one at kLoosenMaxDepth with such a
/// threshold changes nothing.
constexpr float kNegligibleThreshold = 1e-6f;

/// What refinement measured on the pixels refined so far in this frame, to steer the next rounds by: how many
/// more rays a pixel's samples take when traced again one loosening level looser, and a centre sample's 2x2
/// grid per sample (at the frame's or the coarse level); and how much of its truncation bound a loosened pixel
/// actually changed by (the same samples traced again: the difference is truncation alone). Integer sums (the
/// bounds in fixed point), so the same for any thread count and call split; each ratio starts from a prior worth
/// a few pixels.
class RefineMeasures {
 public:
  void addLoosen(int level, uint64_t raysBefore, uint64_t raysAfter, float bound, float change) {
    const std::size_t k = std::size_t(level + 1);
    add(kRays + k, raysBefore, raysAfter);
    add(kTruncation + k, fixed(bound), fixed(std::min(bound, change)));
  }
  void addGrid(bool coarse, uint64_t raysBefore, uint64_t raysAfter) {
    add(kRays + kGrid + coarse, raysBefore, raysAfter);
  }
  /// Rays of a pixel loosened from level over its rays before
  float loosenGrowth(int level) const { return ratio(kRays + std::size_t(level + 1), kLoosenPrior, kPriorRays); }
  /// Rays per sample of a 2x2 grid over the centre sample's rays
  float gridGrowth(bool coarse) const { return ratio(kRays + kGrid + coarse, 1.0, kPriorRays); }
  /// Share of the truncation bound of pixels at this level that loosening them changed
  float truncationShare(int level) const { return ratio(kTruncation + std::size_t(level + 1), 1.0, kPriorBound); }
  /// A probe pixel (kProbeStride) got its grid: its neighbour-rule estimate e0 before, and change, the largest
  /// channel's difference between its centre sample and its grid's mean (whose square estimates the centre
  /// sample's squared error, plus the grid's own variance: a little over).
  void addProbe(float e0, float change) {
    add(kProbe + probeBucket(e0), 1, fixed(change * change));
    add(kProbesMarked, 0, 1);
  }
  /// Pixels marked as probes (the first round's selection)
  void addProbesMarked(uint64_t n) { add(kProbesMarked, n, 0); }
  /// Every probe marked has been recorded (its round was not cut short by a deadline)
  bool probesComplete() const { return before_[kProbesMarked].load() == after_[kProbesMarked].load(); }
  /// The mean squared change of the probes whose estimate was in e0's bucket (an octave of e0; one bucket below
  /// 2^-12), or -1 when fewer than kProbeMinimum were.
  float probeMean(float e0) const {
    const std::size_t k = kProbe + probeBucket(e0);
    const uint64_t n = before_[k].load();
    return n >= uint64_t(kProbeMinimum) ? float(double(after_[k].load()) / kFixed / double(n)) : -1.0f;
  }
  void save(std::vector<uint64_t>& out) const {
    out.resize(2 * kSlots);
    for (std::size_t k = 0; k < kSlots; ++k) {
      out[2 * k] = before_[k].load();
      out[2 * k + 1] = after_[k].load();
    }
  }
  void restore(const std::vector<uint64_t>& in) {
    if (in.size() != 2 * kSlots) return;
    for (std::size_t k = 0; k < kSlots; ++k) {
      before_[k] = in[2 * k];
      after_[k] = in[2 * k + 1];
    }
  }

 private:
  static constexpr std::size_t kLevels = kMaxLoosening + 2, kGrid = kLevels, kRays = 0, kTruncation = kLevels + 2;
  static constexpr std::size_t kProbe = kTruncation + kLevels, kProbeBuckets = 13;
  static constexpr std::size_t kProbesMarked = kProbe + kProbeBuckets;  // marked (before_), recorded (after_)
  static constexpr std::size_t kSlots = kProbesMarked + 1;
  static std::size_t probeBucket(float e0) {
    if (!(e0 > 0x1p-12f)) return 0;
    return std::size_t(std::clamp(std::floor(std::log2(e0)) + 13.0f, 1.0f, float(kProbeBuckets - 1)));
  }
  /// Priors: a loosened pixel's rays grow 4x, a grid's rays per sample and the truncation share start at 1, each
  /// as if measured on a few pixels (64 rays; 4 pixels with a bound of 1); the bounds in fixed point.
  static constexpr double kLoosenPrior = 4.0, kPriorRays = 64.0, kFixed = double(1 << 24);
  static constexpr double kPriorBound = 4.0 * kFixed;  // four pixels with a bound of 1
  static uint64_t fixed(float v) { return uint64_t(double(std::clamp(v, 0.0f, 1.0f)) * kFixed); }
  void add(std::size_t k, uint64_t before, uint64_t after) {
    before_[k].fetch_add(before, std::memory_order_relaxed);
    after_[k].fetch_add(after, std::memory_order_relaxed);
  }
  float ratio(std::size_t k, double prior, double weight) const {
    return float((double(after_[k].load()) + prior * weight) / (double(before_[k].load()) + weight));
  }
  std::atomic<uint64_t> before_[kSlots] = {}, after_[kSlots] = {};
};

}  // namespace whitted
