#include "image/renderer.h"

#include <emmintrin.h>  // SSE2: part of every x86-64 CPU (Debian 12's baseline)

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <utility>

namespace whitted {

void FrameBuffer::resize(int w, int h) {
  width = std::max(0, w);
  height = std::max(0, h);
  std::size_t n = std::size_t(width) * height;
  color.assign(n, Color4(0.0f));
  depth.assign(n, 1.0f);
  traced.assign(n, 0);
  truncation.assign(n, 0.0f);
  sampling.assign(n, 0.0f);
  samples.assign(n, 0);
}

namespace {

// Root mean square, 95th percentile (upper edge of a 1/4096 bin) and maximum of per-pixel values in [0, 1]
class ErrorHistogram {
 public:
  void add(float e) {
    sum2_ += double(e) * e;
    max_ = std::max(max_, e);
    ++hist_[std::min(kBins - 1, int(e * kBins))];
    ++count_;
  }
  ErrorSummary summary() const {
    ErrorSummary out;
    if (count_ == 0) return out;
    out.rms = std::sqrt(sum2_ / double(count_));
    out.max = max_;
    std::size_t cum = 0;
    for (int b = 0; b < kBins; ++b) {
      cum += hist_[b];
      if (double(cum) >= 0.95 * double(count_)) {
        out.p95 = std::min(double(max_), double(b + 1) / kBins);
        break;
      }
    }
    return out;
  }

 private:
  static constexpr int kBins = 4096;
  std::vector<uint32_t> hist_ = std::vector<uint32_t>(kBins, 0);
  double sum2_ = 0.0;
  float max_ = 0.0f;
  std::size_t count_ = 0;
};

// The integrator settings of the frame: without error estimates (interactive frames) no bound rays are traced
IntegratorSettings frameIntegratorSettings(const RenderSettings& s) {
  IntegratorSettings is = s.integrator;
  if (!s.errorEstimates) is.truncationLookahead = 0;
  return is;
}

class FrameJob {
 public:
  FrameJob(const Scene& scene, const Camera& camera, const RenderSettings& s, int w, int h, FrameBuffer& fb)
      : scene_(scene),
        camera_(camera),
        s_(s),
        w_(w),
        h_(h),
        fb_(fb),
        integ_(scene, frameIntegratorSettings(s), camera.up()) {
    ts_ = std::max(1, s.tileSize);
    tilesX_ = (w + ts_ - 1) / ts_;
    tilesY_ = (h + ts_ - 1) / ts_;
    int stride = std::max(1, s.tileStride);
    for (int t = 0; t < tilesX_ * tilesY_; ++t)
      if (t % stride == ((s.tileOffset % stride) + stride) % stride) myTiles_.push_back(t);
    tileStats_.resize(myTiles_.size());
    hitMask_.assign(std::size_t(w) * h, 0);
  }

  FrameStats run() {
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
    int threads = s_.threads > 0 ? s_.threads : hardwareThreads();
    fs.threads = threads;
    bool adaptive = s_.adaptive && n > 1;
    if (resume) {
      restorePixels();
    } else {
      // Pass 1: the full sample set, or only centres in adaptive mode
      runPass(threads, [&](int tile) { tracePixels(tile, adaptive ? 1 : n, false); });
      // Pass 2 (adaptive): full sample set where neighbouring centre samples disagree
      if (adaptive && !aborted_) {
        marks_.assign(std::size_t(w_) * h_, 0);
        markDisagreements();
        runPass(threads, [&](int tile) { tracePixels(tile, n, true); });
      }
    }
    // The neighbour part of the sampling estimate, from the final colours
    if (s_.errorEstimates) {
      if (!aborted_)
        runPass(
            threads, [&](int tile) { estimateFromNeighbours(tile); }, false, false);
      summarizeErrors(fs);
      if (progressive_) {
        if (resume) {
          fs.refinementRounds = keep->rounds;
          fs.progress = keep->progress;
        }
        const double before = resume ? keep->seconds : 0.0;
        if (resume && keep->finished)
          fs.targetMet = s_.targetError > 0.0 && fs.total.rms <= s_.targetError;
        else
          refine(threads, start, before, fs, keep);
      }
    }
    fs.secondsTrace = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (keep) {
      keep->seconds += fs.secondsTrace;
      keep->samples += samples_.load();
      keep->rounds = fs.refinementRounds;
      keep->progress = fs.progress;
      keep->finished = fs.refinementFinished;
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
    fs.longestTileSeconds = longestTile_.load();
    fs.aborted = aborted_;
    fs.kernelReflection = integ_.usesReflection();
    fs.kernelRefraction = integ_.usesRefraction();
    fs.kernelShadows = integ_.usesShadows();
    return fs;
  }

 private:
  /// Runs tileFn over this process's tiles on threads workers; the abort check (if checkAbort) and progress (if
  /// reportProgress) run between tiles. Past deadline_ (if set) no new tile starts. tileFn gets 0..tiles-1 (this
  /// process's tile slots, or fewer if tiles is smaller).
  template <typename Fn>
  void runPass(int threads, Fn&& tileFn, bool reportProgress = true, bool checkAbort = true,
               std::size_t tiles = std::size_t(-1)) {
    std::atomic<std::size_t> next{0};
    std::atomic<std::size_t> done{0};
    std::atomic<bool> abortFlag{aborted_};
    std::mutex errorMutex;
    std::exception_ptr error;
    const std::size_t total = std::min(tiles, myTiles_.size());
    std::size_t reported = 0;
    // VTK's abort check and progress must run on the calling (GL) thread
    auto report = [&](std::size_t d) {
      if (s_.progress && reportProgress && d > reported) {
        reported = d;
        s_.progress(double(d) / double(total));
      }
    };
    auto poll = [&](std::size_t d) {
      if (s_.abortCheck && checkAbort && s_.abortCheck()) abortFlag = true;
      report(d);
    };
    auto worker = [&](bool mainThread) {
      for (bool first = true;; first = false) {
        if (abortFlag.load(std::memory_order_relaxed)) return;
        if (deadline_ && std::chrono::steady_clock::now() >= *deadline_) break;  // budget spent: no new tile
        if (checkAbort && !first && sliceOver()) break;  // slice over: no new tile (each worker takes one)
        std::size_t i = next.fetch_add(1);
        if (i >= total) break;
        if (checkAbort && s_.abortAfterTiles >= 0 && i >= std::size_t(s_.abortAfterTiles)) {
          abortFlag = true;  // testing: the deterministic abort (every earlier slot was taken before this one)
          return;
        }
        try {
          const auto t0 = std::chrono::steady_clock::now();
          tileFn(int(i));
          const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
          double seen = longestTile_.load(std::memory_order_relaxed);
          while (dt > seen && !longestTile_.compare_exchange_weak(seen, dt)) {
          }
        } catch (...) {
          // An exception (std::bad_alloc) stops the frame and is rethrown on the calling thread after the join
          std::lock_guard<std::mutex> lock(errorMutex);
          if (!error) error = std::current_exception();
          abortFlag = true;
          return;
        }
        std::size_t d = done.fetch_add(1) + 1;
        if (mainThread) poll(d);
      }
      // Out of tiles: the calling thread keeps polling until the workers finish their last tiles, so progress
      // always reaches 1 and an abort stays responsive even when the workers took every tile. Without callbacks
      // there is nothing to poll, and the join below waits without the up to 1 ms a polling step adds.
      const bool callbacks = (s_.progress && reportProgress) || (s_.abortCheck && checkAbort);
      while (mainThread && callbacks && !abortFlag.load()) {
        std::size_t d = done.load();
        if (d >= total) {  // complete: no abort check, which could only mark a finished frame as aborted
          report(d);
          break;
        }
        if (deadline_ && std::chrono::steady_clock::now() >= *deadline_) break;  // the join waits for tiles taken
        if (checkAbort && sliceOver()) break;
        poll(d);
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
      }
    };
    std::vector<std::thread> pool;
    try {
      for (int t = 1; t < threads && std::size_t(t) < total; ++t) pool.emplace_back(worker, false);
      worker(true);  // the callbacks may throw too (a VTK observer): caught below after stopping the workers
    } catch (...) {
      std::lock_guard<std::mutex> lock(errorMutex);
      if (!error) error = std::current_exception();
      abortFlag = true;
    }
    for (auto& th : pool) th.join();
    aborted_ = abortFlag.load();
    if (error) std::rethrow_exception(error);
  }

  // Sample position inside a pixel: centre for one sample, jittered strata otherwise.
  Vec2 samplePos(int px, int py, int s, int n) const {
    if (n == 1) return Vec2(px + 0.5, py + 0.5);
    int nx = int(std::ceil(std::sqrt(double(n))));
    int ny = (n + nx - 1) / nx;
    int cx = s % nx, cy = s / nx;
    double jx = hashFloat(uint32_t(px), uint32_t(py), uint32_t(s), 0u);
    double jy = hashFloat(uint32_t(px), uint32_t(py), uint32_t(s), 1u);
    return Vec2(px + (cx + jx) / nx, py + (cy + jy) / ny);
  }

  // The background behind a pixel row, as VTK draws it: solid, or a vertical gradient from the bottom colour to
  // the top colour across the viewport
  Color screenBackground(int py) const {
    if (scene_.gradientBackground) return glm::mix(scene_.background, scene_.background2, float((py + 0.5) / h_));
    return scene_.background;
  }

  // Position of a pixel's sample s after the first pass's strata (progressive refinement): the 2D R2
  // low-discrepancy sequence (Roberts), rotated per pixel (Cranley-Patterson), so that every prefix of the extra
  // samples covers the pixel evenly
  static Vec2 sequencePos(int px, int py, int k) {
    constexpr double a1 = 0.7548776662466927, a2 = 0.5698402909980532;  // 1/g, 1/g^2 for g^3 = g + 1
    const double x = hashFloat(uint32_t(px), uint32_t(py), 0x52325232u, 2u) + a1 * k;
    const double y = hashFloat(uint32_t(px), uint32_t(py), 0x52325232u, 3u) + a2 * k;
    return Vec2(px + (x - std::floor(x)), py + (y - std::floor(y)));
  }

  // Adds samples [first, last) of pixel (px, py) to ps, traced by integ; sample s of a pixel is at
  // samplePos(s, ps.strata) while s < ps.strata, on the pixel's sequence beyond (progressive refinement)
  void addSamples(int px, int py, int first, int last, const Integrator& integ, PixelSums& ps, RayStats& st,
                  const Color& rowBackground) const {
    // Performance note: the stratified samples and the sequence's in two loops (same order), so the sequence's
    // per-pixel hashes, which the compiler hoists out of a joint loop, are not computed for every pixel; each
    // traced in blocks (Integrator::traceBlock: the first hits' shadow rays as packets)
    constexpr int kBlock = Integrator::kBlock;
    const int strata = std::min(std::max(ps.strata, first), last);
    Ray rays[kBlock];
    for (int s = first; s < strata; s += kBlock) {
      const int m = std::min(kBlock, strata - s);
      for (int k = 0; k < m; ++k) rays[k] = cameraRay(samplePos(px, py, s + k, ps.strata));
      traceSamples(rays, m, integ, &ps, st, &rowBackground, 0);
    }
    for (int s = strata; s < last; s += kBlock) {
      const int m = std::min(kBlock, last - s);
      for (int k = 0; k < m; ++k) rays[k] = cameraRay(sequencePos(px, py, s + k - ps.strata));
      traceSamples(rays, m, integ, &ps, st, &rowBackground, 0);
    }
    ps.n += last - first;
  }

  Ray cameraRay(const Vec2& p) const { return camera_.rayPixel(p.x, p.y, w_, h_); }

  // Traces n <= Integrator::kBlock camera rays as one block and adds sample k and the rays it took to pixel sums
  // ps[k * psStride] (stride 0: all to one pixel), with screen background background[k * psStride]
  void traceSamples(const Ray* rays, int n, const Integrator& integ, PixelSums* ps, RayStats& st,
                    const Color* background, int psStride) const {
    constexpr int kBlock = Integrator::kBlock;
    RayStats stats[kBlock];
    Color bg[kBlock];
    Sample smp[kBlock];
    for (int k = 0; k < n; ++k) bg[k] = background[k * psStride];
    integ.traceBlock(rays, n, stats, bg, smp);
    for (int k = 0; k < n; ++k) {
      st += stats[k];
      PixelSums& p = ps[k * psStride];
      addSample(smp[k], p, st);
      p.rays += uint32_t(std::min<uint64_t>(stats[k].traversals(), UINT32_MAX - p.rays));
    }
  }

  // Adds one traced camera sample to ps
  void addSample(const Sample& smp, PixelSums& ps, RayStats& st) const {
    ps.sum += smp.color;  // premultiplied; a miss carries backgroundAlpha x the screen background
    ps.sum2 += smp.color * smp.color;
    if (smp.hit) {
      ps.anyHit = true;
      const double z = camera_.glDepth(smp.firstHit);
      if (!(z >= -1e-6 && z <= 1.0 + 1e-6)) ++st.clampedDepth;  // safety net, counted
      ps.depth = std::min(ps.depth, float(std::clamp(std::isfinite(z) ? z : 1.0, 0.0, 1.0)));
    }
    ps.alpha += smp.alpha;
    ps.err += smp.truncationBound;
  }

  // Writes a pixel's colour, depth and error estimates from its sums
  void writePixel(std::size_t idx, const PixelSums& ps, RayStats& st) {
    const int n = ps.n;
    float inv = 1.0f / float(n);
    Color4 out(ps.sum * inv, ps.alpha * inv);
    bool finite = true;
    for (int k = 0; k < 4; ++k)
      if (!std::isfinite(out[k])) {  // last line of defence: never a non-finite pixel (counted)
        out[k] = 0.0f;
        finite = false;
      }
    if (!finite) ++st.nonFinitePixels;
    fb_.color[idx] = out;
    fb_.depth[idx] = ps.depth;
    fb_.traced[idx] = 1;
    fb_.samples[idx] = uint16_t(std::min(n, 65535));
    // Error estimates in the units of the clamped colour: the pixel can rise by at most its headroom to 1
    const float headroom = 1.0f - std::clamp(std::min(std::min(out.x, out.y), out.z), 0.0f, 1.0f);
    fb_.truncation[idx] = std::min(headroom, ps.err * inv);
    fb_.sampling[idx] = n > 1 ? samplingEstimate(ps.sum, ps.sum2, n) : 0.0f;
    hitMask_[idx] = ps.anyHit ? 1 : 0;
  }

  template <typename PixelFn>
  void forTilePixels(int tileSlot, PixelFn&& fn) {
    int tile = myTiles_[tileSlot];
    int x0 = (tile % tilesX_) * ts_, y0 = (tile / tilesX_) * ts_;
    int x1 = std::min(w_, x0 + ts_), y1 = std::min(h_, y0 + ts_);
    for (int py = y0; py < y1; ++py) {
      const Color rowBackground = screenBackground(py);
      for (int px = x0; px < x1; ++px) fn(px, py, index(px, py), rowBackground);
    }
  }

  void tracePixels(int tileSlot, int n, bool refineOnly) {
    RayStats& st = tileStats_[tileSlot];
    uint64_t samples = 0, refined = 0;
    // One sample per pixel: neighbouring pixels of a row are traced as one block (Integrator::traceBlock), so
    // their shadow rays go as packets; several samples per pixel: the pixel's samples form the blocks
    constexpr int kBlock = Integrator::kBlock;
    struct Pending {
      std::size_t idx;
      int px, py;
    } pending[kBlock];
    PixelSums sums[kBlock];
    Color bg[kBlock];
    int np = 0;
    auto finish = [&](std::size_t idx, PixelSums& ps) {
      samples += n;
      if (refineOnly) ++refined;
      writePixel(idx, ps, st);
      if (progressive_) acc_[idx] = ps;
    };
    auto flush = [&] {
      Ray rays[kBlock];
      for (int k = 0; k < np; ++k) rays[k] = cameraRay(samplePos(pending[k].px, pending[k].py, 0, 1));
      traceSamples(rays, np, integ_, sums, st, bg, 1);
      for (int k = 0; k < np; ++k) {
        sums[k].n = 1;
        finish(pending[k].idx, sums[k]);
      }
      np = 0;
    };
    forTilePixels(tileSlot, [&](int px, int py, std::size_t idx, const Color& rowBackground) {
      if (refineOnly && !marks_[idx]) return;
      if (n == 1) {
        pending[np] = Pending{idx, px, py};
        sums[np] = PixelSums{};
        bg[np] = rowBackground;
        if (++np == kBlock) flush();
        return;
      }
      PixelSums ps;
      ps.strata = n;
      addSamples(px, py, 0, n, integ_, ps, st, rowBackground);
      finish(idx, ps);
    });
    if (np > 0) flush();
    samples_ += samples;
    supersampled_ += refined;
  }

  // Progressive rounds: pick the pixels whose refinement removes the most estimated squared error per ray (see
  // RenderSettings::targetError), each with its better way (more samples or one loosening level deeper), up to the
  // round's rays; re-estimate, until the target is met, the budget is spent, nothing is left to refine or the
  // call's rounds are used (progressive display). A round cut short by an abort or the call's time slice keeps
  // its pixels still to refine in the RefinementState, and the next call finishes it first: the pixels refined
  // and the frame reached are the same as without the cut. before: tracing seconds earlier calls spent on this
  // frame.
  void refine(int threads, std::chrono::steady_clock::time_point start, double before, FrameStats& fs,
              RefinementState* keep) {
    auto elapsed = [&] {
      return before + std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    };
    const int maxSamples = std::clamp(s_.maxProgressiveSamples, 1, 65535);
    if (s_.timeBudget > 0.0)
      deadline_ = start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                              std::chrono::duration<double>(s_.timeBudget - before));
    if (s_.refinementSlice > 0.0)
      sliceEnd_ = start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                              std::chrono::duration<double>(s_.refinementSlice));
    if (fs.progress.empty()) fs.progress.emplace_back(elapsed(), fs.total.rms);
    // A round an earlier call cut short: its pixels still to refine, finished before anything else
    bool pending = keep && keep->pending.size() == std::size_t(w_) * h_;
    if (pending)
      marks_ = std::move(keep->pending);
    else
      marks_.assign(std::size_t(w_) * h_, 0);
    if (keep) keep->pending.clear();
    coarse_ = makeCoarse();
    const int maxLevel = loosestLevel();
    int rounds = 0;
    bool worked = false;  // this call has refined something (a call always does, whatever its slice)
    fs.refinementFinished = false;
    for (;;) {
      // (a pending round is finished first: the image it left half refined may meet the target early)
      fs.targetMet = s_.targetError > 0.0 && fs.total.rms <= s_.targetError;
      if ((fs.targetMet && !pending) || (deadline_ && std::chrono::steady_clock::now() >= *deadline_)) {
        fs.refinementFinished = true;
        break;
      }
      if (aborted_ || (s_.maxRefinementRounds > 0 && rounds >= s_.maxRefinementRounds) || (worked && sliceOver())) {
        if (pending && keep) keep->pending = std::move(marks_);
        break;
      }
      if (pending) {
        pending = false;
        worked = true;
        refineRound(threads, maxSamples);
        if (cutShort(threads, fs, keep)) break;
        finishRound(threads, fs, rounds, elapsed());
        continue;
      }
      // What each pixel can still get: more samples (if its samples disagree), a looser level (if anything was
      // cut)
      auto canSample = [&](std::size_t i) { return acc_[i].n < maxSamples && fb_.sampling[i] > 0.0f; };
      auto canLoosen = [&](std::size_t i) { return acc_[i].level < maxLevel && fb_.truncation[i] > 0.0f; };
      auto estimate = [&](std::size_t i) { return fb_.truncation[i] + fb_.sampling[i]; };
      // What refining a pixel gains per ray it costs, for each way to refine it: the drop of its expected squared
      // error (the share of the image's squared error it can remove) over the rays it will take (its own rays per
      // sample so far, for a looser level times the growth measured on the pixels loosened before). Picks the
      // better way per pixel. The truncation part is systematic and the sampling part random (the estimate is
      // kSamplingStandardErrors standard errors), so their squares add: samples remove only the sampling part's
      // variance, a looser level only the truncation part.
      std::vector<float> loosenGrowth(std::size_t(maxLevel) + 2), share(std::size_t(maxLevel) + 2), gridGrowth(2);
      for (int l = -1; l <= maxLevel; ++l) {
        loosenGrowth[std::size_t(l + 1)] = measures_.loosenGrowth(l);
        share[std::size_t(l + 1)] = measures_.truncationShare(l);
      }
      for (int c = 0; c < 2; ++c) gridGrowth[std::size_t(c)] = measures_.gridGrowth(c == 1);
      struct Choice {
        float gainPerRay = 0.0f, rays = 0.0f;
        uint8_t action = kKeep;
      };
      auto choose = [&](std::size_t i) {
        const PixelSums& ps = acc_[i];
        // The truncation bound scaled by the share of it that loosening changed so far at this level
        const float t = fb_.truncation[i] * share[std::size_t(ps.level + 1)], smp = fb_.sampling[i];
        const float variance = (smp / kSamplingStandardErrors) * (smp / kSamplingStandardErrors);
        const float raysPerSample = std::max(1.0f, float(ps.rays)) / float(ps.n);
        Choice c;
        if (canSample(i)) {
          float gain;
          if (ps.n == 1 && ps.strata == 1 && maxSamples >= kFirstStrata) {
            // Centre sample -> jittered 2x2 grid (coarse when its sampling estimate is well above its bound)
            const bool coarse = ps.level == 0 && coarse_ && t * kCoarseMargin < smp;
            c.action = coarse ? kSampleCoarse : kSample;
            gain = 0.75f * variance;  // 4 samples: a quarter of the variance
            c.rays = float(kFirstStrata) * raysPerSample * gridGrowth[coarse ? 1 : 0];
          } else {
            const int add = std::min(ps.n, maxSamples - ps.n);
            gain = variance * float(add) / float(ps.n + add);  // n / (n + add) of the variance left
            c.action = kSample;
            c.rays = float(add) * raysPerSample;
          }
          c.gainPerRay = gain / c.rays;
        }
        if (canLoosen(i)) {
          // A looser level (depth x2, threshold / 16) is taken to leave a 16th of the truncation part
          const float rays = float(ps.n) * raysPerSample * loosenGrowth[std::size_t(ps.level + 1)];
          const float gain = t * t * (1.0f - 1.0f / 256.0f) / rays;
          if (gain > c.gainPerRay) c = Choice{gain, rays, kLoosen};
        }
        return c;
      };
      // The round's size in rays: half the rays of the image so far (rounds grow geometrically, so their
      // re-estimates cost little), with a budget at most what the time left can trace (at the rate so far), all
      // of it if a round that size would leave less than half a round
      double imageRays = 0.0;
      for (const PixelSums& ps : acc_) imageRays += ps.rays;
      double roundRays = kRoundShare * imageRays;
      if (deadline_) {
        RayStats traced;
        for (const RayStats& r : tileStats_) traced += r;
        const double spent = elapsed() - before;
        const double left = std::chrono::duration<double>(*deadline_ - std::chrono::steady_clock::now()).count();
        if (spent > 0.0 && left > 0.0) {
          const double affordable = double(traced.traversals()) / spent * left;
          if (1.5 * roundRays > affordable) roundRays = affordable;
        }
      }
      // The pixels with the most gain per ray whose rays add up to the round's size: costs summed per priority
      // bucket (a quarter octave each), taken from the top bucket down
      const float least = float(0.5 * s_.targetError);
      std::vector<Choice> choices(acc_.size());
      std::vector<double> bucketRays(kBuckets, 0.0);
      auto bucketOf = [](float g) {
        return std::clamp(int(std::floor(4.0f * std::log2(g))) + kBuckets / 2, 0, kBuckets - 1);
      };
      for (std::size_t i = 0; i < acc_.size(); ++i) {
        if (!fb_.traced[i] || estimate(i) < least || estimate(i) <= 0.0f || !(canSample(i) || canLoosen(i))) continue;
        choices[i] = choose(i);
        if (choices[i].action != kKeep && choices[i].gainPerRay > 0.0f)
          bucketRays[std::size_t(bucketOf(choices[i].gainPerRay))] += choices[i].rays;
        else
          choices[i].action = kKeep;
      }
      int cutBucket = kBuckets;
      for (double sum = 0.0; cutBucket > 0 && sum < roundRays;) sum += bucketRays[std::size_t(--cutBucket)];
      std::size_t marked = 0;
      for (std::size_t i = 0; i < acc_.size(); ++i) {
        const Choice& c = choices[i];
        marks_[i] = c.action != kKeep && bucketOf(c.gainPerRay) >= cutBucket ? c.action : uint8_t(kKeep);
        marked += marks_[i] != kKeep;
      }
      if (marked == 0) {
        fs.refinementFinished = true;
        break;
      }
      worked = true;
      refineRound(threads, maxSamples);
      if (cutShort(threads, fs, keep)) break;
      finishRound(threads, fs, rounds, elapsed());
    }
    deadline_.reset();
    sliceEnd_.reset();
  }

  // Refines the marked pixels over the tiles that have any (a tile's pixels are unmarked as they are refined)
  void refineRound(int threads, int maxSamples) {
    int deepest = 0;  // the loosest level a marked pixel is traced at
    for (std::size_t i = 0; i < acc_.size(); ++i)
      if (marks_[i] == kLoosen)
        deepest = std::max(deepest, acc_[i].level + 1);
      else if (marks_[i] == kSample)
        deepest = std::max(deepest, acc_[i].level);
    prepareLevels(deepest);
    std::vector<int> slots;
    for (int slot = 0; slot < int(myTiles_.size()); ++slot) {
      bool any = false;
      forTilePixels(slot, [&](int, int, std::size_t idx, const Color&) { any = any || marks_[idx] != kKeep; });
      if (any) slots.push_back(slot);
    }
    runPass(
        threads, [&](int i) { refinePixels(slots[std::size_t(i)], maxSamples); }, false, true, slots.size());
  }

  // Whether the round just run was cut short by an abort or the time slice (not the budget, which ends the
  // frame): then its pixels still marked are kept
  // for the next call (and, unless aborted, the estimate is brought up to the image shown)
  bool cutShort(int threads, FrameStats& fs, RefinementState* keep) {
    if (deadline_ && std::chrono::steady_clock::now() >= *deadline_) return false;
    if (std::none_of(marks_.begin(), marks_.end(), [](uint8_t m) { return m != kKeep; })) return false;
    if (keep) keep->pending = std::move(marks_);
    if (!aborted_) {
      runPass(
          threads, [&](int tile) { estimateFromNeighbours(tile); }, false, false);
      summarizeErrors(fs);
    }
    return true;
  }

  // After a round: re-estimate, count it and record the progress
  void finishRound(int threads, FrameStats& fs, int& rounds, double seconds) {
    ++fs.refinementRounds;
    ++rounds;
    runPass(
        threads, [&](int tile) { estimateFromNeighbours(tile); }, false, false);
    summarizeErrors(fs);
    fs.progress.emplace_back(seconds, fs.total.rms);
  }

  // The call's time slice (RenderSettings::refinementSlice) is over
  bool sliceOver() const { return sliceEnd_ && std::chrono::steady_clock::now() >= *sliceEnd_; }

  enum : uint8_t { kKeep = 0, kSample = 1, kLoosen = 2, kSampleCoarse = 3 };

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
    static constexpr std::size_t kSlots = kTruncation + kLevels;
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

  static constexpr int kFirstStrata = 4;  ///< A refined one-sample pixel's first stratified grid.
  /// Coarse level of extra samples (see makeCoarse): the threshold factor and cap, and how far a pixel's sampling
  /// estimate must exceed its truncation bound for its refined samples to be traced coarse.
  static constexpr float kCoarseFactor = 16.0f;
  static constexpr float kCoarseThreshold = 64.0f / 255.0f;
  static constexpr float kCoarseMargin = 4.0f;
  /// A refinement round's rays, as a share of the image's so far; priority buckets of the round's selection.
  static constexpr double kRoundShare = 0.5;
  static constexpr int kBuckets = 512;

  // The integrator settings of a loosening level: maxDepth doubled (at least +2, at most 64) and the threshold
  // divided by 16 per level
  IntegratorSettings levelSettings(int level) const {
    IntegratorSettings is = s_.integrator;
    for (int k = 0; k < level; ++k) {
      is.maxDepth = std::min(64, std::max(2 * is.maxDepth, is.maxDepth + 2));
      is.contributionThreshold /= 16.0f;
    }
    return is;
  }

  // The deepest level that still loosens anything (levels past depth 64 and threshold ~0 change nothing)
  int loosestLevel() const {
    int level = 0;
    while (level < kMaxLoosening) {
      const IntegratorSettings a = levelSettings(level), b = levelSettings(level + 1);
      if (a.maxDepth == b.maxDepth && a.contributionThreshold < 1e-6f) break;
      ++level;
    }
    return level;
  }

  // The coarse level -1 of extra samples: the contribution threshold x kCoarseFactor (at most kCoarseThreshold,
  // never below the frame's), depth as the frame's. Null when it would trace as the frame does (threshold 0 or
  // already at the cap).
  std::unique_ptr<Integrator> makeCoarse() const {
    IntegratorSettings is = s_.integrator;
    const float t =
        std::max(is.contributionThreshold, std::min(kCoarseThreshold, is.contributionThreshold * kCoarseFactor));
    if (!(t > is.contributionThreshold)) return nullptr;
    is.contributionThreshold = t;
    return std::make_unique<Integrator>(scene_, is, camera_.up());
  }

  // Builds the integrators of levels 1..level not built yet (on the calling thread)
  void prepareLevels(int level) {
    while (int(levels_.size()) < level)
      levels_.push_back(std::make_unique<Integrator>(scene_, levelSettings(int(levels_.size()) + 1), camera_.up()));
  }
  const Integrator& integratorAt(int level) const {
    return level == 0 ? integ_ : level < 0 ? *coarse_ : *levels_[std::size_t(level - 1)];
  }

  void refinePixels(int tileSlot, int maxSamples) {
    RayStats& st = tileStats_[tileSlot];
    uint64_t samples = 0, retraced = 0;
    forTilePixels(tileSlot, [&](int px, int py, std::size_t idx, const Color& rowBackground) {
      if (marks_[idx] == kKeep) return;
      PixelSums& ps = acc_[idx];
      bool loosened = false;
      int levelBefore = 0;
      uint32_t raysBefore = 0;
      const Color4 colorBefore = fb_.color[idx];
      const float boundBefore = fb_.truncation[idx];
      if (marks_[idx] == kLoosen) {
        // The same samples again, one level looser
        PixelSums fresh;
        fresh.strata = ps.strata;
        fresh.level = ps.level + 1;
        addSamples(px, py, 0, ps.n, integratorAt(fresh.level), fresh, st, rowBackground);
        loosened = true;
        levelBefore = ps.level;
        raysBefore = ps.rays;
        retraced += std::size_t(ps.n);
        ps = fresh;
      } else if (ps.n == 1 && ps.strata == 1 && maxSamples >= kFirstStrata) {
        // Only the centre sample: replaced by a jittered 2x2 grid (as adaptive sampling's second pass does),
        // which later rounds continue with the sequence; at the coarse level if so marked (its own truncation
        // bound is summed as for any sample)
        PixelSums fresh;
        fresh.strata = kFirstStrata;
        fresh.level = marks_[idx] == kSampleCoarse ? -1 : ps.level;
        addSamples(px, py, 0, kFirstStrata, integratorAt(fresh.level), fresh, st, rowBackground);
        measures_.addGrid(fresh.level < 0, uint64_t(ps.rays) * kFirstStrata, fresh.rays);
        samples += kFirstStrata - 1;
        retraced += 1;
        ps = fresh;
      } else {
        const int add = std::min(ps.n, maxSamples - ps.n);
        addSamples(px, py, ps.n, ps.n + add, integratorAt(ps.level), ps, st, rowBackground);
        samples += add;
      }
      marks_[idx] = kKeep;
      writePixel(idx, ps, st);
      if (loosened) {
        const Color4 d = glm::abs(glm::clamp(fb_.color[idx], Color4(0.0f), Color4(1.0f)) -
                                  glm::clamp(colorBefore, Color4(0.0f), Color4(1.0f)));
        measures_.addLoosen(levelBefore, raysBefore, ps.rays, boundBefore, std::max(std::max(d.x, d.y), d.z));
      }
    });
    samples_ += samples;
    retraced_ += retraced;
  }

  // Progressive display: the image of the kept sums (pixels with no sample are not this process's)
  void restorePixels() {
    RayStats st;
    for (std::size_t i = 0; i < acc_.size(); ++i)
      if (acc_[i].n > 0) writePixel(i, acc_[i], st);
    if (!tileStats_.empty()) tileStats_.front() += st;
  }

  // Twice the standard error of the mean of n samples with these sums, largest channel, at most 1
  static float samplingEstimate(const Color& sum, const Color& sum2, int n) {
    const Color var = glm::max(Color(0.0f), (sum2 - sum * sum / float(n)) / float(n - 1));
    return std::min(1.0f, kSamplingStandardErrors * std::sqrt(maxComponent(var) / float(n)));
  }

  // The sampling estimate of a tile's pixels from their neighbours (see kSamplingConfidence)
  void estimateFromNeighbours(int tileSlot) {
    int tile = myTiles_[tileSlot];
    int x0 = (tile % tilesX_) * ts_, y0 = (tile / tilesX_) * ts_;
    int x1 = std::min(w_, x0 + ts_), y1 = std::min(h_, y0 + ts_);
    const float* color = &fb_.color.data()->x;  // RGBA floats (glm's operator[] would branch per channel)
    const uint8_t* traced = fb_.traced.data();
    float* sampling = fb_.sampling.data();
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) {
        const std::size_t i = index(x, y);
        if (!traced[i]) continue;
        const int n = fb_.samples[i];
        // Several samples: their spread, but at least the neighbours' disagreement scaled as a mean of n samples
        // (samples that all fell on one side of an edge show no spread)
        const float spread = n == 1         ? 0.0f
                             : progressive_ ? samplingEstimate(acc_[i].sum, acc_[i].sum2, n)
                                            : sampling[i];
        const float scale = n == 1 ? 1.0f : 1.0f / std::sqrt(float(n));
        const bool interior = x > 0 && y > 0 && x + 1 < w_ && y + 1 < h_ && traced[i - 1] && traced[i + 1] &&
                              traced[i - w_] && traced[i + w_];
        if (!interior) {
          sampling[i] = std::min(1.0f, std::max(spread, scale * unpredicted(x, y).second));
          continue;
        }
        // Performance note: the common case without unpredicted()'s border logic, the four channels at once in
        // SSE2 with the scalar rule's very operations (min(1, max(0, x)) as MINPS(MAXPS(x, 0), 1), then
        // |c - 0.5 (a + b)| on both axes and the largest lane), so the estimate keeps its bits
        const __m128 zero = _mm_setzero_ps(), one = _mm_set1_ps(1.0f), half = _mm_set1_ps(0.5f);
        const __m128 absMask = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
        auto v = [&](std::size_t j) { return _mm_min_ps(_mm_max_ps(_mm_loadu_ps(color + 4 * j), zero), one); };
        const __m128 c = v(i);
        const __m128 dx = _mm_and_ps(absMask, _mm_sub_ps(c, _mm_mul_ps(half, _mm_add_ps(v(i - 1), v(i + 1)))));
        const __m128 dy = _mm_and_ps(absMask, _mm_sub_ps(c, _mm_mul_ps(half, _mm_add_ps(v(i - w_), v(i + w_)))));
        __m128 m = _mm_max_ps(dx, dy);
        m = _mm_max_ps(m, _mm_shuffle_ps(m, m, _MM_SHUFFLE(1, 0, 3, 2)));
        m = _mm_max_ps(m, _mm_shuffle_ps(m, m, _MM_SHUFFLE(2, 3, 0, 1)));
        const float d = _mm_cvtss_f32(m);
        sampling[i] = std::min(1.0f, std::max(spread, scale * d));
      }
  }

  void summarizeErrors(FrameStats& fs) const {
    ErrorHistogram truncation, sampling, total;
    for (std::size_t i = 0; i < fb_.traced.size(); ++i) {
      if (!fb_.traced[i]) continue;
      truncation.add(fb_.truncation[i]);
      sampling.add(fb_.sampling[i]);
      total.add(std::min(1.0f, fb_.truncation[i] + fb_.sampling[i]));
    }
    fs.truncation = truncation.summary();
    fs.sampling = sampling.summary();
    fs.total = total.summary();
  }

  // How far a pixel's neighbours fail to predict its (clamped) colour: whether a neighbour hits where it misses
  // or the reverse, and the largest over both axes of half the second difference (the pixel against the mean of
  // its two neighbours; at the image border, against the line through the two pixels on the inner side). A
  // linear ramp (smooth shading) has none; edges, silhouettes, highlights and texture detail do.
  std::pair<bool, float> unpredicted(int x, int y) const {
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

  // Marks the pixels whose centre sample its neighbours do not predict (see unpredicted) by more than the
  // adaptive threshold, so only edges, silhouettes, highlights and texture detail are supersampled.
  void markDisagreements() {
    for (int y = 0; y < h_; ++y)
      for (int x = 0; x < w_; ++x) {
        const std::size_t i = index(x, y);
        if (!fb_.traced[i]) continue;
        const auto [hitDiffers, diff] = unpredicted(x, y);
        marks_[i] = hitDiffers || diff > s_.adaptiveThreshold ? 1 : 0;
      }
  }

  std::size_t index(int x, int y) const { return std::size_t(y) * w_ + x; }

  const Scene& scene_;
  const Camera& camera_;
  const RenderSettings& s_;
  int w_, h_;
  FrameBuffer& fb_;
  Integrator integ_;
  int ts_, tilesX_, tilesY_;
  std::vector<int> myTiles_;
  std::vector<RayStats> tileStats_;
  std::vector<uint8_t> hitMask_, marks_;
  bool progressive_ = false;
  std::vector<PixelSums> acc_;                                     ///< Per-pixel sums, kept for progressive refinement.
  std::optional<std::chrono::steady_clock::time_point> deadline_;  ///< Refinement stops taking tiles past it.
  std::optional<std::chrono::steady_clock::time_point> sliceEnd_;  ///< The call's refinement slice ends here.
  std::vector<std::unique_ptr<Integrator>> levels_;                ///< Loosening levels 1.. (progressive refinement).
  std::unique_ptr<Integrator> coarse_;                             ///< Level -1 (see makeCoarse); may be null.
  RefineMeasures measures_;  ///< What refinement measured so far (see RefineMeasures).
  std::atomic<uint64_t> samples_{0}, supersampled_{0}, retraced_{0};
  std::atomic<double> longestTile_{0.0};
  bool aborted_ = false;
};

}  // namespace

FrameStats render(const Scene& scene, const Camera& camera, const RenderSettings& settings, int width, int height,
                  FrameBuffer& fb) {
  fb.resize(width, height);
  if (width <= 0 || height <= 0) return FrameStats{};
  FrameJob job(scene, camera, settings, width, height, fb);
  return job.run();
}

}  // namespace whitted
