// The film: per-pixel sums of camera samples (PixelSums) and the frame buffer written from them. Samples are
// traced here into the sums (positions from image/sampling.h); a pixel's colour, depth and error estimates are
// its sums' means.
#include "image/error_estimate.h"  // samplingEstimate, calibratedSampling
#include "image/frame_job.h"
#include "image/sampling.h"

#include <algorithm>
#include <cmath>

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
  samplingRms.assign(n, 0.0f);  // the calibrated estimate (error_estimate.h)
  samples.assign(n, 0);
}

bool FrameBuffer::sized(int w, int h) const {
  const std::size_t n = std::size_t(std::max(0, w)) * std::max(0, h);
  return width == std::max(0, w) && height == std::max(0, h) && color.size() == n && depth.size() == n &&
         traced.size() == n && truncation.size() == n && sampling.size() == n && samplingRms.size() == n &&
         samples.size() == n;
}

void FrameBuffer::clearPixel(std::size_t i) {
  color[i] = Color4(0.0f);
  depth[i] = 1.0f;
  traced[i] = 0;
  truncation[i] = 0.0f;
  sampling[i] = 0.0f;
  samplingRms[i] = 0.0f;
  samples[i] = 0;
}

void FrameJob::clearUntraced() {
  std::size_t slot = 0;
  for (int t = 0; t < tilesX_ * tilesY_; ++t) {
    const bool mine = slot < myTiles_.size() && myTiles_[slot] == t;
    if (mine && tileDone_[slot++]) continue;
    const int x0 = (t % tilesX_) * ts_, y0 = (t / tilesX_) * ts_;
    const int x1 = std::min(w_, x0 + ts_), y1 = std::min(h_, y0 + ts_);
    for (int py = y0; py < y1; ++py)
      for (int px = x0; px < x1; ++px) fb_.clearPixel(index(px, py));
  }
}

Color FrameJob::screenBackground(int py) const {
  if (scene_.gradientBackground) return glm::mix(scene_.background, scene_.background2, float((py + 0.5) / h_));
  return scene_.background;
}

void FrameJob::addSamples(int px, int py, int first, int last, const Integrator& integ, PixelSums& ps, RayStats& st,
                          const Color& rowBackground) const {
  // Performance note: the stratified samples and the sequence's in two loops (same order), so the sequence's
  // per-pixel hashes, which the compiler hoists out of a joint loop, are not computed for every pixel; each
  // traced in blocks (Integrator::traceBlock: the first hits' shadow rays as packets)
  constexpr int kBlock = Integrator::kBlock;
  const int strata = std::min(std::max(ps.strata, first), last);
  Ray rays[kBlock];
  for (int s = first; s < strata; s += kBlock) {
    const int m = std::min(kBlock, strata - s);
    for (int k = 0; k < m; ++k) rays[k] = cameraRay(stratifiedSamplePos(px, py, s + k, ps.strata));
    traceSamples(rays, m, integ, &ps, st, &rowBackground, 0);
  }
  for (int s = strata; s < last; s += kBlock) {
    const int m = std::min(kBlock, last - s);
    for (int k = 0; k < m; ++k) rays[k] = cameraRay(sequenceSamplePos(px, py, s + k - ps.strata));
    traceSamples(rays, m, integ, &ps, st, &rowBackground, 0);
  }
  ps.n += last - first;
}

void FrameJob::traceSamples(const Ray* rays, int n, const Integrator& integ, PixelSums* ps, RayStats& st,
                            const Color* background, int psStride) const {
  constexpr int kBlock = Integrator::kBlock;
  RayStats stats[kBlock];
  Color bg[kBlock] = {};  // (zeroed only to quiet GCC's -Wmaybe-uninitialized: the first n are set below)
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

void FrameJob::addSample(const Sample& smp, PixelSums& ps, RayStats& st) const {
  ps.sum += smp.color;  // premultiplied; a miss carries backgroundAlpha x the screen background
  ps.sum2 += smp.color * smp.color;
  if (smp.hit) {
    ps.anyHit = true;
    const double z = camera_.glDepth(smp.firstHit);
    if (!(z >= -1e-6 && z <= 1.0 + 1e-6) && !depthWithinSlack(smp)) ++st.clampedDepth;  // safety net, counted
    ps.depth = std::min(ps.depth, float(std::clamp(std::isfinite(z) ? z : 1.0, 0.0, 1.0)));
  }
  ps.alpha += smp.alpha;
  ps.err += smp.truncationBound;
  // The calibrated estimate's second half (image/error_estimate.h): samples are added in index order
  if (sampleHalf(ps.added++, ps.strata)) {
    ps.sumOdd += smp.color;
    ++ps.nOdd;
  }
}

bool FrameJob::depthWithinSlack(const Sample& smp) const {
  const Vec3 step = double(smp.firstHitSlack) * camera_.viewDirection();
  const double a = camera_.glDepth(smp.firstHit - step), b = camera_.glDepth(smp.firstHit + step);
  return std::isfinite(a) && std::isfinite(b) && std::max(a, b) >= -1e-6 && std::min(a, b) <= 1.0 + 1e-6;
}

FrameJob::FilmPixel FrameJob::resolvePixel(const PixelSums& ps, RayStats& st) const {
  const int n = ps.n;
  float inv = 1.0f / float(n);
  FilmPixel p;
  p.color = Color4(ps.sum * inv, ps.alpha * inv);
  bool finite = true;
  for (int k = 0; k < 4; ++k)
    if (!std::isfinite(p.color[k])) {  // last line of defence: never a non-finite pixel (counted)
      p.color[k] = 0.0f;
      finite = false;
    }
  if (!finite) ++st.nonFinitePixels;
  p.depth = ps.depth;
  p.samples = uint16_t(std::min(n, 65535));
  // Error estimates in the units of the clamped colour: the pixel can rise by at most its headroom to 1
  const float headroom = 1.0f - std::clamp(std::min(std::min(p.color.x, p.color.y), p.color.z), 0.0f, 1.0f);
  p.truncation = std::min(headroom, ps.err * inv);
  p.sampling = n > 1 ? samplingEstimate(ps.sum, ps.sum2, n) : 0.0f;
  p.samplingRms = calibratedSampling(ps.sum, ps.sumOdd, n, ps.nOdd);  // one sample: see estimateErrors
  p.hit = ps.anyHit ? 1 : 0;
  return p;
}

void FrameJob::storePixel(std::size_t idx, const FilmPixel& p) {
  fb_.color[idx] = p.color;
  fb_.depth[idx] = p.depth;
  fb_.traced[idx] = 1;
  fb_.samples[idx] = p.samples;
  fb_.truncation[idx] = p.truncation;
  fb_.sampling[idx] = p.sampling;
  fb_.samplingRms[idx] = p.samplingRms;
  hitMask_[idx] = p.hit;
}

bool FrameJob::missPixel(const Color& background, FilmPixel& p) const {
  // The pipeline of a one-sample pixel (addSample, resolvePixel) applied to missSample: every miss of a row is
  // this pixel. Used only when it trips no safety net (which would count per pixel)
  RayStats st;
  PixelSums ps;
  addSample(integ_.missSample(background, st), ps, st);
  ps.n = 1;
  p = resolvePixel(ps, st);
  return st.safetyNetCatches() == 0;
}

void FrameJob::tracePixels(int tileSlot, int n, bool refineOnly) {
  TileCounts counts(tileStats_[tileSlot]);
  RayStats& st = counts.st;
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
  // Performance note: most camera rays of a typical view (an object on a background) miss; a miss's pixel is
  // computed once per background (row) and copied, instead of taking each miss through the pixel sums
  // (progressive frames keep every pixel's sums, so they take no shortcut)
  Color missBackground{0.0f};
  FilmPixel missValue;
  bool missKnown = false, missClean = false;
  int termRow = -1;  // the row of rowTerm (camera rays by rows: Camera::rayPixelRow)
  Vec4 rowTerm(0.0);
  // A miss's pixel for this row background: whether it trips no safety net (then missValue is it), computed once
  // per background
  auto cleanMiss = [&](const Color& background) {
    if (!missKnown || !(background == missBackground)) {
      missBackground = background;
      missClean = missPixel(background, missValue);
      missKnown = true;
    }
    return missClean;
  };
  // Writes the clean miss (missValue, found by cleanMiss) as pixel idx's n samples
  auto storeMiss = [&](std::size_t idx) {
    samples += n;
    if (refineOnly) ++refined;
    storePixel(idx, missValue);
  };
  // Block culling (RenderSettings::blockCulling): per 8x8 block of the tile, whether its frustum can meet anything
  // (0 not known yet, 1 yes, 2 no), found when one of its pixels first needs it
  constexpr int kCullBlock = 8, kMaxCullBlocks = 8;  // (tiles up to 64 pixels wide)
  const int tile = myTiles_[tileSlot];
  const int tx0 = (tile % tilesX_) * ts_, ty0 = (tile / tilesX_) * ts_;
  const int tx1 = std::min(w_, tx0 + ts_), ty1 = std::min(h_, ty0 + ts_);
  const bool cull = s_.blockCulling && n == 1 && !progressive_ && !scene_.features().volumes &&
                    ts_ <= kCullBlock * kMaxCullBlocks;
  uint8_t blockState[kMaxCullBlocks][kMaxCullBlocks] = {};
  auto blockCulled = [&](int px, int py) {
    const int bx = (px - tx0) / kCullBlock, by = (py - ty0) / kCullBlock;
    uint8_t& state = blockState[by][bx];
    if (state == 0) {
      const int x0 = tx0 + bx * kCullBlock, y0 = ty0 + by * kCullBlock;
      const Frustum f = camera_.pixelBlockFrustum(x0, y0, std::min(tx1, x0 + kCullBlock), std::min(ty1, y0 + kCullBlock),
                                                  w_, h_);
      state = scene_.frustumMayHit(f) ? 1 : 2;
    }
    return state == 2;
  };
  uint64_t culled = 0;
  auto flush = [&] {
    Ray rays[kBlock];
    for (int k = 0; k < np; ++k) {
      const Vec2 p = stratifiedSamplePos(pending[k].px, pending[k].py, 0, 1);
      if (pending[k].py != termRow) {
        termRow = pending[k].py;
        rowTerm = camera_.pixelRowTerm(p.y, h_);
      }
      rays[k] = camera_.rayPixelRow(p.x, w_, rowTerm);
    }
    unsigned misses = 0;
    if (progressive_) {
      traceSamples(rays, np, integ_, sums, st, bg, 1);
    } else {
      RayStats stats[kBlock];
      Sample smp[kBlock];
      integ_.traceBlock(rays, np, stats, bg, smp, &misses);
      for (int k = 0; k < np; ++k) {
        st += stats[k];
        if (misses >> k & 1) {
          if (cleanMiss(bg[k])) {
            storeMiss(pending[k].idx);
            continue;
          }
          misses &= ~(1u << k);
          smp[k] = integ_.missSample(bg[k], st);
        }
        addSample(smp[k], sums[k], st);
      }
    }
    for (int k = 0; k < np; ++k) {
      if (misses >> k & 1) continue;  // written above
      sums[k].n = 1;
      finish(pending[k].idx, sums[k]);
    }
    np = 0;
  };
  forTilePixels(tileSlot, [&](int px, int py, std::size_t idx, const Color& rowBackground) {
    if (refineOnly && !marks_[idx]) return;
    if (n == 1) {
      // A pixel of a culled block (block culling): not traced, its miss written at once, as flush() writes a clean
      // miss (the same pixel value and counts, no node visited); a miss that would trip a safety net is traced
      // (it finds the same miss) and goes through flush()'s path
      if (cull && blockCulled(px, py) && cleanMiss(rowBackground)) {
        ++st.primary;
        ++culled;
        storeMiss(idx);
        return;
      }
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
  if (!refineOnly) tileDone_[std::size_t(tileSlot)] = 1;
  samples_ += samples;
  supersampled_ += refined;
  culled_ += culled;
}

void FrameJob::restorePixels() {
  RayStats st;
  for (std::size_t i = 0; i < acc_.size(); ++i)
    if (acc_[i].n > 0)
      writePixel(i, acc_[i], st);
    else
      fb_.clearPixel(i);
  if (!tileStats_.empty()) tileStats_.front() += st;
}

}  // namespace whitted
