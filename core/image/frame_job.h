// Private to core/image: the state of one render() call, shared by the files that make a frame. Each file holds
// one concept of it:
//   renderer.cpp        the passes of a frame in order (render(), FrameJob::run)
//   film.cpp            pixel sums: tracing samples into them, writing the frame buffer from them
//   adaptive.cpp        adaptive sampling: the neighbour rule and the supersampling pass
//   error_estimate.cpp  the neighbour part of the sampling estimate, the error summaries
//   refinement.cpp      progressive refinement rounds (tuning numbers in refinement.h)
// Tile scheduling is util/tile_scheduler, sample positions image/sampling.h.
#pragma once

#include "image/refinement.h"  // RefineMeasures
#include "image/renderer.h"
#include "util/tile_scheduler.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

namespace whitted {

class FrameJob {
 public:
  FrameJob(const Scene& scene, const Camera& camera, const RenderSettings& s, int w, int h, FrameBuffer& fb);
  /// Traces the frame (renderer.cpp).
  FrameStats run();

 private:
  // Film (film.cpp)
  /// Traces n samples of every pixel of a tile (refineOnly: only the pixels marked) and writes them.
  void tracePixels(int tileSlot, int n, bool refineOnly);
  /// Adds samples [first, last) of pixel (px, py) to ps, traced by integ; sample s of a pixel is at
  /// stratifiedSamplePos(s, ps.strata) while s < ps.strata, on the pixel's sequence beyond (progressive refinement).
  void addSamples(int px, int py, int first, int last, const Integrator& integ, PixelSums& ps, RayStats& st,
                  const Color& rowBackground) const;
  /// Traces n <= Integrator::kBlock camera rays as one block and adds sample k and the rays it took to pixel sums
  /// ps[k * psStride] (stride 0: all to one pixel), with screen background background[k * psStride].
  void traceSamples(const Ray* rays, int n, const Integrator& integ, PixelSums* ps, RayStats& st,
                    const Color* background, int psStride) const;
  /// Adds one traced camera sample to ps.
  void addSample(const Sample& smp, PixelSums& ps, RayStats& st) const;
  /// Whether some point within smp.firstHitSlack of smp.firstHit along the view direction has a GL depth in [0, 1]
  /// (within 1e-6): a depth outside that can come from a surface crossing the near or far plane, not from a bug.
  bool depthWithinSlack(const Sample& smp) const;
  /// What the frame buffer gets for a pixel (and hitMask_).
  struct FilmPixel {
    Color4 color{0.0f};
    float depth = 1.0f, truncation = 0.0f, sampling = 0.0f, samplingRms = 0.0f;
    uint16_t samples = 0;
    uint8_t hit = 0;
  };
  /// A pixel's colour, depth and error estimates from its sums.
  FilmPixel resolvePixel(const PixelSums& ps, RayStats& st) const;
  /// Writes p to pixel idx (marked traced).
  void storePixel(std::size_t idx, const FilmPixel& p);
  /// Writes a pixel's colour, depth and error estimates from its sums.
  void writePixel(std::size_t idx, const PixelSums& ps, RayStats& st) { storePixel(idx, resolvePixel(ps, st)); }
  /// The pixel of one camera sample that missed everything in front of background; false if computing it tripped a
  /// safety net (then each miss must count it: no shortcut).
  bool missPixel(const Color& background, FilmPixel& p) const;
  /// Progressive display: the image of the kept sums (pixels with no sample are not this process's: cleared).
  void restorePixels();
  /// Clears the pixels pass 1 did not trace (other processes' tiles, tiles an abort or deadline skipped): the frame
  /// buffer is kept from the last frame.
  void clearUntraced();
  /// The background behind a pixel row, as VTK draws it: solid, or a vertical gradient from the bottom colour to
  /// the top colour across the viewport.
  Color screenBackground(int py) const;

  // Adaptive sampling (adaptive.cpp)
  /// Pass 2: n samples for the pixels whose centre sample its neighbours do not predict.
  void supersampleDisagreements(int n);
  /// Marks (marks_) the pixels whose centre sample its neighbours do not predict (see unpredicted) by more than
  /// the adaptive threshold, so only edges, silhouettes, highlights and texture detail are supersampled.
  void markDisagreements();
  /// How far a pixel's neighbours fail to predict its (clamped) colour: whether a neighbour hits where it misses
  /// or the reverse, and the largest over both axes of half the second difference.
  std::pair<bool, float> unpredicted(int x, int y) const;

  // Error estimate (error_estimate.cpp)
  /// The neighbour part of the sampling estimate over the image, then its summaries into fs.
  /// The neighbour part and the summaries; evenIfAborted: the neighbour part also after an abort (a round that
  /// completed: whether the target is met must not depend on where a call was cut).
  void estimateErrors(FrameStats& fs, bool evenIfAborted = false);
  /// The sampling estimate of a tile's pixels from their neighbours (see kSamplingConfidence).
  void estimateFromNeighbours(int tileSlot);
  /// FrameBuffer::samplingRms of the several-sample pixels: their half differences pooled over 3 x 3 pixels.
  void poolCalibrated();
  /// FrameStats::truncation, sampling and total from the frame buffer's traced pixels.
  void summarizeErrors(FrameStats& fs) const;

  // Progressive refinement (refinement.cpp)
  void refine(std::chrono::steady_clock::time_point start, double before, FrameStats& fs, RefinementState* keep);
  void refineRound(int maxSamples);
  bool cutShort(FrameStats& fs, RefinementState* keep);
  void finishRound(FrameStats& fs, int& rounds, double seconds);
  void refinePixels(int tileSlot, int maxSamples);
  std::unique_ptr<Integrator> makeCoarse() const;
  void prepareLevels(int level);
  const Integrator& integratorAt(int level) const {
    return level == 0 ? integ_ : level < 0 ? *coarse_ : *levels_[std::size_t(level - 1)];
  }

  // Tiles and pixels
  /// Calls fn(px, py, pixel index, row background) for the pixels of this process's tile slot tileSlot.
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
  /// Runs tileFn over all of this process's tile slots (see TileScheduler::run).
  template <typename Fn>
  void runPass(Fn&& tileFn, bool reportProgress = true, bool checkAbort = true) {
    tiles_.run(myTiles_.size(), tileFn, reportProgress, checkAbort);
  }
  Ray cameraRay(const Vec2& p) const { return camera_.rayPixel(p.x, p.y, w_, h_); }
  std::size_t index(int x, int y) const { return std::size_t(y) * w_ + x; }

  /// What refinement marks a pixel for in marks_ (adaptive sampling marks with kSample).
  enum : uint8_t { kKeep = 0, kSample = 1, kLoosen = 2, kSampleCoarse = 3 };

  const Scene& scene_;
  const Camera& camera_;
  const RenderSettings& s_;
  int w_, h_;
  FrameBuffer& fb_;
  Integrator integ_;
  int ts_, tilesX_, tilesY_;
  std::vector<int> myTiles_;         ///< This process's tiles (RenderSettings::tileStride), by slot.
  std::vector<RayStats> tileStats_;  ///< Per tile slot, summed in slot order.
  /// A tile's counts on its thread's stack, added to its slot of tileStats_ once, when the tile's work ends (also
  /// by an exception or an abort). Per-sample updates of tileStats_ itself had two threads writing neighbouring
  /// slots, which share cache lines: 4% of an iso1m frame's time on 2 threads for a few instructions.
  struct TileCounts {
    explicit TileCounts(RayStats& slot) : slot_(slot) {}
    ~TileCounts() { slot_ += st; }
    TileCounts(const TileCounts&) = delete;
    TileCounts& operator=(const TileCounts&) = delete;
    RayStats st;

   private:
    RayStats& slot_;
  };
  std::vector<uint8_t> tileDone_;    ///< Per tile slot, 1 once pass 1 traced it.
  std::vector<uint8_t> hitMask_;     ///< 1 where a pixel's samples hit anything.
  std::vector<uint8_t> marks_;       ///< Pixels to supersample (adaptive) or refine (see kKeep ...).
  TileScheduler tiles_;
  bool progressive_ = false;
  std::vector<PixelSums> acc_;                       ///< Per-pixel sums, kept for progressive refinement.
  std::vector<std::unique_ptr<Integrator>> levels_;  ///< Loosening levels 1.. (progressive refinement).
  std::unique_ptr<Integrator> coarse_;               ///< Level -1 (see makeCoarse); may be null.
  RefineMeasures measures_;                          ///< What refinement measured so far (see RefineMeasures).
  std::atomic<uint64_t> samples_{0}, supersampled_{0}, retraced_{0}, culled_{0};
};

}  // namespace whitted
