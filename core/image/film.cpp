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
    if (!(z >= -1e-6 && z <= 1.0 + 1e-6)) ++st.clampedDepth;  // safety net, counted
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

void FrameJob::writePixel(std::size_t idx, const PixelSums& ps, RayStats& st) {
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
  fb_.samplingRms[idx] = calibratedSampling(ps.sum, ps.sumOdd, n, ps.nOdd);  // one sample: see estimateErrors
  hitMask_[idx] = ps.anyHit ? 1 : 0;
}

void FrameJob::tracePixels(int tileSlot, int n, bool refineOnly) {
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
    for (int k = 0; k < np; ++k) rays[k] = cameraRay(stratifiedSamplePos(pending[k].px, pending[k].py, 0, 1));
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

void FrameJob::restorePixels() {
  RayStats st;
  for (std::size_t i = 0; i < acc_.size(); ++i)
    if (acc_[i].n > 0) writePixel(i, acc_[i], st);
  if (!tileStats_.empty()) tileStats_.front() += st;
}

}  // namespace whitted
