// The frame's error estimate: the neighbour part of the sampling estimate (a pass over the finished colours) and
// the summaries of FrameStats. What the estimate states: image/error_estimate.h.
#include "image/error_estimate.h"

#include "image/frame_job.h"

#include <emmintrin.h>  // SSE2: part of every x86-64 CPU (Debian 12's baseline)

#include <algorithm>
#include <cmath>
#include <vector>

namespace whitted {

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
  /// n values of 0 (or -0): what n calls of add(0) do (sum2_ and max_ keep their bits: adding +0 to a sum of
  /// non-negative terms, and max with 0 from 0 up, change nothing).
  void addZeros(std::size_t n) {
    hist_[0] += uint32_t(n);
    count_ += n;
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

}  // namespace

void FrameJob::estimateErrors(FrameStats& fs, bool evenIfAborted) {
  if (!tiles_.aborted()) {
    // Every tile, past a time budget's deadline too (no tile of any pass starts after it): the figures decide
    // whether the target is met, and a pass cut there would leave some pixels' estimates from the round before
    const std::optional<std::chrono::steady_clock::time_point> deadline = tiles_.deadline();
    tiles_.setDeadline(std::nullopt);
    runPass([&](int tile) { estimateFromNeighbours(tile); }, false, false);
    tiles_.setDeadline(deadline);
  } else if (evenIfAborted) {
    // (an aborted frame's scheduler runs no pass: on this thread, the same per-tile rule)
    for (int slot = 0; slot < int(myTiles_.size()); ++slot) estimateFromNeighbours(slot);
  }
  poolCalibrated();
  summarizeErrors(fs);
}

// The calibrated estimate pooled over 3 x 3 pixels (error_estimate.h): each pixel's half difference gives one
// noisy estimate of the variance of one sample there, n (A - B)^2 nA nB / n^2; a pixel takes the mean of those of
// its traced several-sample neighbours (itself included) over its own n. A box filter keeps the image's sum of
// variances at equal sample counts, so the RMS stays unbiased, and refinement, which picks pixels by this estimate
// (with only a time budget, by the larger of it and the samples' spread: FrameJob::refine), no longer picks the
// pixels whose own difference came out large by chance (and leaves those whose came out small): that choice alone
// made the refined image's estimate fall below its measured error.
void FrameJob::poolCalibrated() {
  const std::size_t size = std::size_t(w_) * h_;
  std::vector<float> perSample(size, -1.0f);  // -1: no estimate (not traced, or one sample)
  const bool probed = progressive_ && s_.targetError > 0.0;
  for (std::size_t i = 0; i < size; ++i) {
    const int n = fb_.samples[i];
    if (fb_.traced[i] && n == 1 && probed) {
      // A one-sample pixel: the mean squared change the probes of its neighbour rule's bucket measured
      // (kProbeStride), where there were enough of them
      const float m = measures_.probeMean(fb_.samplingRms[i]);
      if (m >= 0.0f)
        fb_.samplingRms[i] = std::min(1.0f, std::sqrt(m));
    }
    if (!fb_.traced[i] || n < 2) continue;
    const float e = progressive_ ? calibratedSampling(acc_[i].sum, acc_[i].sumOdd, acc_[i].n, acc_[i].nOdd)
                                 : fb_.samplingRms[i];
    perSample[i] = float(n) * e * e;
  }
  for (int y = 0; y < h_; ++y)
    for (int x = 0; x < w_; ++x) {
      const std::size_t i = index(x, y);
      if (perSample[i] < 0.0f) continue;
      double sum = 0.0;
      int count = 0;
      for (int v = std::max(0, y - 1); v <= std::min(h_ - 1, y + 1); ++v)
        for (int u = std::max(0, x - 1); u <= std::min(w_ - 1, x + 1); ++u) {
          const float p = perSample[index(u, v)];
          if (p >= 0.0f) {
            sum += p;
            ++count;
          }
        }
      fb_.samplingRms[i] = std::min(1.0f, float(std::sqrt(sum / count / fb_.samples[i])));
    }
}

void FrameJob::estimateFromNeighbours(int tileSlot) {
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
        if (n == 1) fb_.samplingRms[i] = sampling[i];
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
      if (n == 1) fb_.samplingRms[i] = sampling[i];  // the calibrated estimate of one sample: the neighbour rule
    }
}

void FrameJob::summarizeErrors(FrameStats& fs) const {
  ErrorHistogram truncation, sampling, total, calibratedSampling, calibrated;
  // Performance note: this runs on one thread; the pixels whose estimates are all zero (a miss on a plain
  // background: most of a typical view) are only counted, then added to every summary at once (the same summaries,
  // bit for bit: 2.9% of an iso1m 1-spp frame's instructions before, all of them on the calling thread)
  std::size_t zeros = 0;
  for (std::size_t i = 0; i < fb_.traced.size(); ++i) {
    if (!fb_.traced[i]) continue;
    if (fb_.truncation[i] == 0.0f && fb_.sampling[i] == 0.0f && fb_.samplingRms[i] == 0.0f) {
      ++zeros;
      continue;
    }
    truncation.add(fb_.truncation[i]);
    sampling.add(fb_.sampling[i]);
    total.add(totalEstimate(fb_.truncation[i], fb_.sampling[i]));
    calibratedSampling.add(fb_.samplingRms[i]);
    calibrated.add(calibratedTotal(fb_.truncation[i], fb_.samplingRms[i]));
  }
  for (ErrorHistogram* h : {&truncation, &sampling, &total, &calibratedSampling, &calibrated}) h->addZeros(zeros);
  fs.truncation = truncation.summary();
  fs.sampling = sampling.summary();
  fs.total = total.summary();
  fs.calibratedSampling = calibratedSampling.summary();
  fs.calibrated = calibrated.summary();
}

}  // namespace whitted
