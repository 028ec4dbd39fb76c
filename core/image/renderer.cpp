// render(): the passes of a frame in order. FrameJob (image/frame_job.h) holds the frame's state; its other
// concepts are in film.cpp, adaptive.cpp, error_estimate.cpp and refinement.cpp.
#include "image/frame_job.h"

#include <chrono>
#include <utility>

namespace whitted {

namespace {

// The integrator settings of the frame: without error estimates (interactive frames) no bound rays are traced
IntegratorSettings frameIntegratorSettings(const RenderSettings& s) {
  IntegratorSettings is = s.integrator;
  if (!s.errorEstimates) {
    is.truncationLookahead = 0;
    is.volumeStepEstimate = false;
  }
  return is;
}

}  // namespace

FrameJob::FrameJob(const Scene& scene, const Camera& camera, const RenderSettings& s, int w, int h, FrameBuffer& fb)
    : scene_(scene),
      camera_(camera),
      s_(s),
      w_(w),
      h_(h),
      fb_(fb),
      integ_(scene, frameIntegratorSettings(s), camera.up()),
      tiles_(s.threads > 0 ? s.threads : hardwareThreads(), s.abortCheck, s.progress, s.abortAfterTiles) {
  ts_ = std::max(1, s.tileSize);
  tilesX_ = (w + ts_ - 1) / ts_;
  tilesY_ = (h + ts_ - 1) / ts_;
  int stride = std::max(1, s.tileStride);
  for (int t = 0; t < tilesX_ * tilesY_; ++t)
    if (t % stride == ((s.tileOffset % stride) + stride) % stride) myTiles_.push_back(t);
  tileStats_.resize(myTiles_.size());
  tileDone_.assign(myTiles_.size(), 0);
  hitMask_.assign(std::size_t(w) * h, 0);
}

FrameStats FrameJob::run() {
  FrameStats fs;
  auto start = std::chrono::steady_clock::now();
  progressive_ = s_.errorEstimates && (s_.targetError > 0.0 || s_.timeBudget > 0.0);
  // Progressive display: continue the frame whose sums the caller kept, if it is this size
  RefinementState* keep = progressive_ ? s_.refinement : nullptr;
  const bool resume = keep && !keep->pixels.empty() && keep->width == w_ && keep->height == h_ &&
                      keep->pixels.size() == std::size_t(w_) * h_;
  if (keep && !resume) keep->reset();
  if (resume) {
    acc_ = std::move(keep->pixels);
    measures_.restore(keep->measures);
  } else if (progressive_) {
    acc_.assign(std::size_t(w_) * h_, PixelSums{});
  }
  int n = s_.samplesPerPixel < 1 ? 1 : s_.samplesPerPixel;
  fs.threads = tiles_.threads();
  bool adaptive = s_.adaptive && n > 1;
  if (resume) {
    restorePixels();
  } else {
    // Pass 1: the full sample set, or only centres in adaptive mode
    runPass([&](int tile) { tracePixels(tile, adaptive ? 1 : n, false); });
    // Pass 2 (adaptive): full sample set where neighbouring centre samples disagree
    // The frame buffer is kept from the last frame: clear what pass 1 did not write
    clearUntraced();
    if (adaptive && !tiles_.aborted()) supersampleDisagreements(n);
  }
  // The neighbour part of the sampling estimate, from the final colours
  if (s_.errorEstimates) {
    estimateErrors(fs);
    if (progressive_) {
      if (resume) {
        fs.refinementRounds = keep->rounds;
        fs.progress = keep->progress;
      }
      const double before = resume ? keep->seconds : 0.0;
      if (resume && keep->finished) {
        fs.targetMet = s_.targetError > 0.0 && fs.calibrated.rms <= s_.targetError;
        fs.refinementExhausted = keep->exhausted;
      } else {
        refine(start, before, fs, keep);
      }
    }
  }
  fs.secondsTrace = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (keep) {
    keep->seconds += fs.secondsTrace;
    keep->samples += samples_.load();
    keep->rounds = fs.refinementRounds;
    keep->progress = fs.progress;
    keep->finished = fs.refinementFinished;
    keep->exhausted = fs.refinementExhausted;
    keep->width = w_;
    keep->height = h_;
    keep->pixels = std::move(acc_);
    measures_.save(keep->measures);
  }

  // Deterministic reductions (fixed order, independent of thread count)
  for (const RayStats& r : tileStats_) fs.rays += r;
  fs.samples = keep ? keep->samples : samples_.load();
  fs.samplesRetraced = retraced_.load();
  fs.pixelsSupersampled = supersampled_.load();
  fs.pixelsCulled = culled_.load();
  fs.longestTileSeconds = tiles_.longestTileSeconds();
  fs.aborted = tiles_.aborted();
  fs.kernelReflection = integ_.usesReflection();
  fs.kernelRefraction = integ_.usesRefraction();
  fs.kernelShadows = integ_.usesShadows();
  return fs;
}

FrameStats render(const Scene& scene, const Camera& camera, const RenderSettings& settings, int width, int height,
                  FrameBuffer& fb) {
  // Performance note: a frame of the size of the last one reuses its buffers as they are (allocating and
  // clearing 32 bytes a pixel took about 5% of a 1-spp frame): the frame writes every pixel it traces and clears
  // the others (FrameJob::clearUntraced, restorePixels)
  if (!fb.sized(width, height)) fb.resize(width, height);
  if (width <= 0 || height <= 0) return FrameStats{};
  FrameJob job(scene, camera, settings, width, height, fb);
  return job.run();
}

}  // namespace whitted
