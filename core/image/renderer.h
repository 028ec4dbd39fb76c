// Renderer: splits the image into tiles handed to all cores from a work queue, runs the integrator for each
// sample, and fills linear RGBA and OpenGL-depth buffers. Output is bit-identical for any thread count: sample
// positions are a deterministic function of (pixel, sample index) and statistics are summed per pixel/tile.
#pragma once

#include "image/error_estimate.h"  // kSamplingConfidence, ErrorSummary, totalEstimate
#include "shading/camera.h"
#include "shading/integrator.h"
#include "util/parallel.h"  // hardwareThreads()

#include <functional>
#include <utility>
#include <vector>

namespace whitted {

/// Linear float buffers, rows bottom to top (OpenGL / VTK order).
struct FrameBuffer {
  int width = 0, height = 0;
  std::vector<Color4> color;    ///< Linear RGBA, premultiplied by alpha (not clamped).
  std::vector<float> depth;     ///< OpenGL window depth in [0,1]; 1 where nothing was hit.
  std::vector<uint8_t> traced;  ///< 1 where this process traced the pixel (see RenderSettings::tileStride).
  /// Per-pixel error estimate, in the units of color clamped to [0, 1] (largest channel), 0 where not traced:
  /// - truncation: an upper bound on what the depth cap and the contribution threshold left out (against the
  ///   image traced without threshold and at infinite depth, or see IntegratorSettings::truncationReferenceDepth),
  ///   plus, with IntegratorSettings::volumeStepEstimate, the estimate of the volumes' step error (an estimate,
  ///   not a bound: volume_step_error_test.cpp measures how often it is under);
  /// - sampling: an estimate of the pixel's anti-aliasing error (see kSamplingConfidence).
  std::vector<float> truncation, sampling;
  /// The calibrated sampling estimate (an RMS estimate, not a bound; see kCalibratedConfidence): from the two
  /// interleaved halves of a pixel's samples; for a one-sample pixel, sampling (the neighbour rule; with a
  /// TargetError its probes' bucket mean, see kProbeStride in image/refinement.h). 0 where not
  /// traced.
  std::vector<float> samplingRms;
  std::vector<uint16_t> samples;  ///< Camera samples taken per pixel.
  /// Sets the size and clears every pixel (colour 0, depth 1, not traced).
  void resize(int w, int h);
  /// Whether the buffers hold w x h pixels.
  bool sized(int w, int h) const;
  /// Clears pixel i as resize() does.
  void clearPixel(std::size_t i);
};

/// Loosening levels progressive refinement may apply per pixel (see RenderSettings::targetError).
constexpr int kMaxLoosening = 3;

/// Running sums of one pixel's camera samples, kept for progressive refinement.
struct PixelSums {
  Color sum{0.0f}, sum2{0.0f};                   ///< Sum of the samples' colours and of their squares.
  Color sumOdd{0.0f};  ///< Sum of the colours of the samples of half 1 (sampleHalf; the calibrated estimate).
  int added = 0, nOdd = 0;  ///< Samples added to these sums since they were cleared, and of them in half 1.
  float alpha = 0.0f, err = 0.0f, depth = 1.0f;  ///< Sums of alpha and truncation bounds; nearest depth.
  int n = 0;                                     ///< Samples summed (0: the pixel is not traced by this process).
  int strata = 1;  ///< Samples of the first pass (a stratified grid); later samples continue a 2D sequence.
  int level = 0;  ///< Loosening level the samples were traced at, -1 = coarse (see RenderSettings::targetError).
  uint32_t rays = 0;  ///< Rays (traced and bound rays) for the samples summed (what tracing them again costs).
  /// A one-sample pixel marked as a probe (kProbeStride in image/refinement.h): its neighbour-rule estimate then
  /// (kept with the marks, so a round split over calls records the same); -1 otherwise.
  float probeEstimate = -1.0f;
  bool anyHit = false;
};

/// A still frame refined over several render() calls (progressive display). Keep one per view and pass it in
/// RenderSettings::refinement: a call with an empty state (or another image size) traces the first pass and up to
/// maxRefinementRounds rounds and stores the pixels' sums here; each later call restores the image from them and
/// runs the next rounds. The caller calls reset() whenever the scene, camera or settings change (render() cannot
/// tell). TimeBudget counts the tracing time of all calls.
struct RefinementState {
  std::vector<PixelSums> pixels;  ///< Per-pixel sums, rows bottom to top; empty before the first call.
  int width = 0, height = 0;
  double seconds = 0.0;   ///< Tracing seconds spent on this frame over all calls.
  int rounds = 0;         ///< Refinement rounds run over all calls.
  uint64_t samples = 0;   ///< Camera samples traced over all calls.
  bool finished = false;  ///< Target met, budget spent or nothing left to refine: a call adds nothing.
  bool exhausted = false;  ///< Finished because nothing was left to refine (FrameStats::refinementExhausted).
  /// A round cut short (abort, RenderSettings::refinementSlice): per pixel, what it still has to do (0: nothing);
  /// empty when no round is pending. The next call finishes it first.
  std::vector<uint8_t> pending;
  std::vector<std::pair<double, double>> progress;  ///< As FrameStats::progress, over all calls.
  std::vector<uint64_t> measures;  ///< What refinement measured so far (ray growth, truncation share), to steer by.
  void reset() { *this = RefinementState{}; }
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
  /// Camera rays of one-sample pixels (1 spp, adaptive mode's first pass) skip tracing in 8x8 blocks whose frustum
  /// misses every leaf box of the scene (Scene::frustumMayHit); the image is the same, bit for bit. Off: every
  /// camera ray is traced (tests compare the two). Not with volumes or progressive frames.
  bool blockCulling = true;
  /// Pixel split between processes: this process traces tiles with index % tileStride == tileOffset, and writes
  /// depth 1 / alpha 0 elsewhere (for sort-last compositing). Default 1/0 = everything.
  int tileStride = 1;
  int tileOffset = 0;
  /// Compute the neighbour part of the per-pixel sampling estimate (one more pass over the image, about 5% of a
  /// 1-spp frame of the classic scene) and the error summaries of FrameStats. Off (e.g. for interactive frames):
  /// FrameBuffer::sampling is the samples' spread alone (0 for one-sample pixels), the summaries are 0. Default on.
  bool errorEstimates = true;
  /// Progressive refinement of a still frame (with errorEstimates): after the first pass, rounds refine the
  /// pixels where refining removes the most estimated squared error per ray it costs, until the calibrated RMS
  /// estimate (FrameStats::calibrated.rms, not the bound total) is at most targetError, after at least one round
  /// while one-sample pixels are left (the first round grids a fixed sample of them, the probes, which rate the
  /// rest: kProbeStride in image/refinement.h; a first pass under the target instead gives every one-sample pixel
  /// its 2x2 grid; with maxProgressiveSamples >= 4), the frame has taken timeBudget seconds, or no pixel can be
  /// refined. Either at 0 (the default) leaves it out; both 0: no refinement. A pixel can get more samples (a
  /// pixel with only its centre sample a jittered 2x2 grid instead, as adaptive sampling does, traced at the
  /// coarse level -- contribution threshold x 16, at most 64/255, never below the frame's -- when its sampling
  /// estimate is over 4x its truncation part; any other pixel twice its samples at its level, continuing a
  /// low-discrepancy sequence, R2 rotated per pixel, after its stratified grid), or be traced again with its
  /// samples at the next loosening level (maxDepth doubled, at least +2, up to 64; contribution threshold / 16;
  /// the volumes' step halved; at most kMaxLoosening levels). Each way's gain is the drop of the pixel's squared
  /// estimate (truncation part + calibrated sampling estimate, FrameBuffer::samplingRms, in quadrature; a
  /// one-sample pixel's at least twice the target, see kMinimumVariance; with a timeBudget and no target, a
  /// several-sample pixel's squared sampling part is the larger of that and its samples' spread, rescaled so the
  /// several-sample pixels' sum is unchanged, see budgetRanksBySpread), its cost the rays it takes (the pixel's
  /// rays per sample so far; for a grid or a looser level times the growth measured on the pixels refined so
  /// far); the truncation part is the bound scaled by the share of it that loosening actually changed on the
  /// pixels loosened so far from that level (the bound is an upper bound, up to 40x the measured truncation on
  /// glass; the truncation part reported stays the bound). Each pixel takes its better way; a round takes the
  /// pixels with the most gain per ray (only those above half the target, and one-sample pixels) up to half the
  /// rays of the image so far (near the target fewer: an expected drop kNeedMargin x what the target still
  /// needs), with a timeBudget at most what the time left can trace at the rate so far (the whole rest when less
  /// than 1.5 rounds are left).
  double targetError = 0.0;
  double timeBudget = 0.0;          ///< Seconds for the whole frame; checked between tiles (overshoot <= one tile).
  int maxProgressiveSamples = 256;  ///< Most samples a pixel gets from refinement. Default 256.
  /// Progressive display: state kept between calls (see RefinementState); null (the default): every call is a
  /// whole frame.
  RefinementState* refinement = nullptr;
  int maxRefinementRounds = 0;  ///< Refinement rounds per call; 0 (the default) = until finished.
  /// Progressive display: seconds after which a call's refinement starts no new tile (checked with abortCheck,
  /// between tiles), cutting a round short; the next call finishes that round first, so the frames reached are
  /// those of uncut rounds. Bounds how long a call keeps the caller (a GUI) from reacting. 0 (the default): none.
  double refinementSlice = 0.0;
  /// Called on the calling thread between tiles; return true to abort the frame. May be empty.
  std::function<bool()> abortCheck;
  /// Called on the calling thread with the fraction done. May be empty.
  std::function<void(double)> progress;
  /// Testing: a deterministic abort. The frame aborts (as if abortCheck had returned true) when a worker would
  /// start tile slot abortAfterTiles of a pass that checks for aborts: exactly slots 0..abortAfterTiles-1 are
  /// traced, for any thread count and however the threads are scheduled. -1 (the default): never.
  long long abortAfterTiles = -1;
  /// Testing: with a time budget and no target, refinement ranks a several-sample pixel by the larger of its
  /// squared calibrated estimate and its samples' variance of the mean (times the image's ratio of the two sums,
  /// at most 1), all rescaled to the calibrated estimates' sum (see FrameJob::refine); false ranks by the
  /// calibrated estimate alone, as with a TargetError (tests compare the two). Default true.
  bool budgetRanksBySpread = true;
};

struct FrameStats {
  double secondsTrace = 0.0;  ///< Wall time of tracing (all passes).
  RayStats rays;
  uint64_t samples = 0;             ///< Camera samples taken.
  uint64_t pixelsSupersampled = 0;  ///< Adaptive mode: pixels that got the full sample count.
  /// One-sample pixels whose camera ray was not traced: the frustum of their 8x8 block misses every leaf box of the
  /// scene (RenderSettings::blockCulling); written as misses, exactly as traced misses are.
  uint64_t pixelsCulled = 0;
  /// Progressive refinement: samples traced again at a looser depth and threshold (they replace samples counted
  /// in samples, so the per-pixel counts of FrameBuffer::samples sum to samples).
  uint64_t samplesRetraced = 0;
  /// Per-pixel error estimates summarised over the traced pixels (FrameBuffer::truncation, sampling and their
  /// sum per pixel, total): total is the honest bound (the sampling part about 95% per pixel, the truncation part
  /// never under).
  ErrorSummary truncation, sampling, total;
  /// The calibrated estimate (kCalibratedConfidence): calibratedSampling summarises FrameBuffer::samplingRms,
  /// calibrated the per-pixel calibratedTotal(truncation, samplingRms). calibrated.rms estimates the image's
  /// measured RMS error (largest channel per pixel); TargetError is compared with it.
  ErrorSummary calibratedSampling, calibrated;
  bool aborted = false;
  /// Progressive refinement: rounds run, whether the target error was met (false without a target), and the
  /// calibrated RMS estimate (calibrated.rms) after the first pass and after each round (with its elapsed seconds).
  int refinementRounds = 0;
  double longestTileSeconds = 0.0;  ///< Wall time of the slowest tile of any pass (the budget's granularity).
  bool targetMet = false;
  /// Refinement is over (target met, budget spent, nothing left to refine, or no refinement asked for); false
  /// when it stopped at RenderSettings::maxRefinementRounds, its slice or an abort, so another call would
  /// improve it.
  bool refinementFinished = true;
  /// The refinement ended because nothing was left to refine (every pixel whose estimate is not zero has the most
  /// samples a still frame takes and its loosest depth): the end of a refinement without a target before its Time
  /// Budget is spent, or with a target it cannot reach.
  bool refinementExhausted = false;
  std::vector<std::pair<double, double>> progress;
  int threads = 1;
  bool kernelReflection = false, kernelRefraction = false, kernelShadows = false;
};

/// Renders scene (committed) through camera into fb (resized to width x height). Every pixel of fb is written:
/// the pixels not traced (other processes' tiles, an aborted frame) are cleared, so fb can be kept between frames
/// (a frame that throws leaves fb undefined: the next frame writes it all again).
FrameStats render(const Scene& scene, const Camera& camera, const RenderSettings& settings, int width, int height,
                  FrameBuffer& fb);

}  // namespace whitted
