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

/// The calibrated RMS estimate (FrameBuffer::samplingRms, FrameStats::calibrated), beside the bound above: an
/// estimate of the pixel's root mean square error, not a bound. A pixel with n >= 2 samples sums them in two
/// interleaved halves (sampleHalf in image/sampling.h: a checkerboard of its stratified grid, then alternate samples
/// of its sequence); with half means A (nA samples) and B (nB), (A - B)^2 nA nB / n^2 is an estimate of the squared
/// error of the pixel's mean (A + B)/2 that stays unbiased for stratified samples (each half is itself spread over
/// the pixel, so their difference has the stratified mean's spread, where the sample variance above has the
/// spread of independent samples), as in Dammertz et al. 2010 and Cycles' adaptive sampling. A one-sample pixel
/// takes the neighbour rule above, or, in a frame refined to a TargetError, the mean squared change the probes
/// of its neighbour rule's bucket measured (kProbeStride in image/refinement.h: the rule cannot see a thin feature
/// no centre sample hit, and reads smooth shading's curvature as error; the probes, chosen whatever their
/// estimate, measure both). Per pixel it combines with the truncation bound in quadrature (calibratedTotal:
/// the bias and the random part of an error add as squares), and the image's RMS of that is the figure TargetError
/// is compared with. It is a 1-sigma (mean square) estimate, with no coverage probability per pixel: about a third
/// of the pixels are above it.
constexpr double kCalibratedConfidence = 0.68;

/// The calibrated sampling estimate of a pixel from the sums of its two halves (sumOdd over nOdd samples, the rest
/// of sum over n - nOdd): |A - B| sqrt(nA nB) / n, largest channel, at most 1; 0 for fewer than 2 samples or an
/// empty half.
inline float calibratedSampling(const Color& sum, const Color& sumOdd, int n, int nOdd) {
  const int nEven = n - nOdd;
  if (n < 2 || nOdd < 1 || nEven < 1) return 0.0f;
  const Color d = glm::abs((sum - sumOdd) / float(nEven) - sumOdd / float(nOdd));
  return std::min(1.0f, maxComponent(d) * std::sqrt(float(nEven) * float(nOdd)) / float(n));
}

/// A pixel's calibrated total: truncation bound and calibrated sampling estimate in quadrature, at most 1.
inline float calibratedTotal(float truncation, float sampling) {
  return std::min(1.0f, std::sqrt(truncation * truncation + sampling * sampling));
}

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
