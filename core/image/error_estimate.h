// The per-pixel error estimate: what it states, the rules every user of it shares (the sampling estimate of a
// pixel's samples, the total of its two parts) and its summary over an image. The neighbour part and the
// summaries of a frame are computed in error_estimate.cpp.
#pragma once

#include "util/math.h"  // Color, maxComponent

#include <algorithm>
#include <cmath>

namespace whitted {

/// What the sampling estimate states. A pixel with n >= 2 samples: twice the standard error of its mean
/// (sample variance of the n samples / n, largest channel), which covers the pixel's true error with about 95%
/// probability if the mean were normally distributed (stratified samples make the true spread smaller), but at
/// least the neighbour term below / sqrt(n) (samples that all fell on one side of an edge show no spread). A
/// pixel with one sample: half the second difference of its colour against its neighbours (the rule adaptive
/// sampling refines by), a heuristic with no probability attached; the benchmark reports the coverage measured.
constexpr double kSamplingConfidence = 0.95;
constexpr float kSamplingStandardErrors = 2.0f;

/// Summary over the traced pixels of one per-pixel error image.
struct ErrorSummary {
  double rms = 0.0, p95 = 0.0, max = 0.0;  ///< Root mean square, 95th percentile (to 1/4096) and largest value.
};

/// A pixel's total error estimate from its two parts (FrameBuffer::truncation and sampling), in the units of
/// the clamped colour: their sum, at most 1. Every user of the total (summaries, refinement, error images) takes
/// it from here.
inline float totalEstimate(float truncation, float sampling) {
  return std::min(1.0f, truncation + sampling);
}

/// The spread part of the sampling estimate of n >= 2 samples with these sums of colours and of their squares:
/// kSamplingStandardErrors standard errors of their mean, largest channel, at most 1.
inline float samplingEstimate(const Color& sum, const Color& sum2, int n) {
  const Color var = glm::max(Color(0.0f), (sum2 - sum * sum / float(n)) / float(n - 1));
  return std::min(1.0f, kSamplingStandardErrors * std::sqrt(maxComponent(var) / float(n)));
}

}  // namespace whitted
