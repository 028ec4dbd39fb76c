// Progressive refinement (RenderSettings::targetError, timeBudget, refinement): rounds that refine the pixels
// whose refinement removes the most estimated squared error per ray, each by more samples or a looser depth and
// threshold, until the target is met, the budget is spent or nothing is left to refine. Tuning numbers and what
// refinement measures to steer by: image/refinement.h.
#include "image/refinement.h"

#include "image/error_estimate.h"  // calibratedTotal, samplingEstimate
#include "image/frame_job.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>

namespace whitted {

namespace {

// The integrator settings of a loosening level: maxDepth times kLoosenDepthFactor (at least + kLoosenDepthStep, at
// most kLoosenMaxDepth), the threshold divided by kLoosenThresholdDivisor and the volumes' step halved per level
IntegratorSettings levelSettings(const IntegratorSettings& frame, int level) {
  IntegratorSettings is = frame;
  for (int k = 0; k < level; ++k) {
    is.maxDepth =
        std::min(kLoosenMaxDepth, std::max(kLoosenDepthFactor * is.maxDepth, is.maxDepth + kLoosenDepthStep));
    is.contributionThreshold /= kLoosenThresholdDivisor;
    --is.volumeStepScale;
  }
  return is;
}

// The deepest level that still loosens anything (levels past kLoosenMaxDepth and a negligible threshold change
// nothing, nor does a step halved past every volume's finest: finestVolumeStep, Scene::finestVolumeStepScale)
int loosestLevel(const IntegratorSettings& frame, int finestVolumeStep) {
  int level = 0;
  while (level < kMaxLoosening) {
    const IntegratorSettings a = levelSettings(frame, level), b = levelSettings(frame, level + 1);
    if (a.maxDepth == b.maxDepth && a.contributionThreshold < kNegligibleThreshold &&
        b.volumeStepScale < finestVolumeStep)
      break;
    ++level;
  }
  return level;
}

}  // namespace

// Progressive rounds: pick the pixels whose refinement removes the most estimated squared error per ray (see
// RenderSettings::targetError), each with its better way (more samples or one loosening level deeper), up to the
// round's rays; re-estimate, until the target is met, the budget is spent, nothing is left to refine or the
// call's rounds are used (progressive display). A round cut short by an abort or the call's time slice keeps
// its pixels still to refine in the RefinementState, and the next call finishes it first: the pixels refined
// and the frame reached are the same as without the cut. before: tracing seconds earlier calls spent on this
// frame.
void FrameJob::refine(std::chrono::steady_clock::time_point start, double before, FrameStats& fs,
                      RefinementState* keep) {
  auto elapsed = [&] {
    return before + std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  const int maxSamples = std::clamp(s_.maxProgressiveSamples, 1, 65535);
  if (s_.timeBudget > 0.0)
    tiles_.setDeadline(start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                   std::chrono::duration<double>(s_.timeBudget - before)));
  if (s_.refinementSlice > 0.0)
    tiles_.setSliceEnd(start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                   std::chrono::duration<double>(s_.refinementSlice)));
  if (fs.progress.empty()) fs.progress.emplace_back(elapsed(), fs.calibrated.rms);
  // A round an earlier call cut short: its pixels still to refine, finished before anything else
  bool pending = keep && keep->pending.size() == std::size_t(w_) * h_;
  if (pending)
    marks_ = std::move(keep->pending);
  else
    marks_.assign(std::size_t(w_) * h_, 0);
  if (keep) keep->pending.clear();
  coarse_ = makeCoarse();
  const int maxLevel = loosestLevel(s_.integrator, scene_.finestVolumeStepScale());
  // A pixel with one sample has no calibrated estimate of its own (its neighbour rule cannot see a thin feature its
  // centre sample missed): until the first round's probes have rated such pixels (kProbeStride) the target is not
  // met while any is left, and they stay candidates whatever their estimate (kMinimumVariance)
  auto single = [&](std::size_t i) { return fb_.traced[i] && acc_[i].n == 1 && maxSamples >= kFirstStrata; };
  auto anySingle = [&] {
    for (std::size_t i = 0; i < acc_.size(); ++i)
      if (single(i)) return true;
    return false;
  };
  int rounds = 0;
  bool worked = false;  // this call has refined something (a call always does, whatever its slice)
  fs.refinementFinished = false;
  fs.refinementExhausted = false;
  for (;;) {
    // (a pending round is finished first: the image it left half refined may meet the target early)
    fs.targetMet = s_.targetError > 0.0 && fs.calibrated.rms <= s_.targetError &&
                   ((fs.refinementRounds > 0 && measures_.probesComplete()) || !anySingle());
    if ((fs.targetMet && !pending) || tiles_.pastDeadline()) {
      fs.refinementFinished = true;
      break;
    }
    if (tiles_.aborted() || (s_.maxRefinementRounds > 0 && rounds >= s_.maxRefinementRounds) ||
        (worked && tiles_.sliceOver())) {
      if (pending && keep) keep->pending = std::move(marks_);
      break;
    }
    if (pending) {
      pending = false;
      worked = true;
      refineRound(maxSamples);
      if (cutShort(fs, keep)) break;
      finishRound(fs, rounds, elapsed());
      continue;
    }
    // What each pixel can still get: more samples (if its samples disagree), a looser level (if anything was
    // cut)
    auto canSample = [&](std::size_t i) {
      return acc_[i].n < maxSamples && (fb_.sampling[i] > 0.0f || single(i));
    };
    auto canLoosen = [&](std::size_t i) { return acc_[i].level < maxLevel && fb_.truncation[i] > 0.0f; };
    auto estimate = [&](std::size_t i) { return calibratedTotal(fb_.truncation[i], fb_.samplingRms[i]); };
    // What refining a pixel gains per ray it costs (rays: the proxy for time), for each way to refine it: the
    // drop of its expected squared error (the share of the image's squared error it can remove) over the rays it
    // will take (its own rays per sample so far, for a looser level times the growth measured on the pixels
    // loosened before). Picks the better way per pixel. The truncation part is systematic and the sampling part
    // random, so their squares add (as in calibratedTotal): samples remove only the sampling part's variance (the
    // calibrated estimate squared), a looser level only the truncation part.
    std::vector<float> loosenGrowth(std::size_t(maxLevel) + 2), share(std::size_t(maxLevel) + 2), gridGrowth(2);
    for (int l = -1; l <= maxLevel; ++l) {
      loosenGrowth[std::size_t(l + 1)] = measures_.loosenGrowth(l);
      share[std::size_t(l + 1)] = measures_.truncationShare(l);
    }
    for (int c = 0; c < 2; ++c) gridGrowth[std::size_t(c)] = measures_.gridGrowth(c == 1);
    // What a several-sample pixel's variance is ranked by. With a TargetError: its calibrated estimate, the figure
    // the target is compared with (refining where it is high makes it fall soonest). With only a time budget, the
    // aim is the least true error, and the calibrated estimate (a half difference: one degree of freedom, pooled
    // over 3 x 3 pixels) is noisy: picking by it leaves the pixels whose estimate came out low by chance. They are
    // ranked by the larger of it and the variance of the mean of the pixel's samples taken as independent (n - 1
    // degrees of freedom; an overstatement for stratified samples) times the image's ratio of the two sums (at most
    // 1); then all scaled so that they sum to the calibrated estimates' sum (the sampling part keeps its weight
    // against the truncation part: unscaled, the larger of two figures favoured samples over a looser depth,
    // 1.04-1.05x the error at 12x on mirrors and fence). Measured: data/benchmark/progressive and
    // Calibration.BudgetRefinementRanksBySamplesSpread; with a TargetError the same rule left the estimate 1.33x the
    // measured error at the stop (median of the target study) against 1.25x, so it is not used there. The sums are
    // this process's pixels' (RenderSettings::tileStride), as the round's size is.
    auto independentVariance = [&](std::size_t i) {
      const PixelSums& ps = acc_[i];
      const float e = 0.5f * samplingEstimate(ps.sum, ps.sum2, ps.n);  // (its two standard errors)
      return e * e;
    };
    const bool bySpread = !(s_.targetError > 0.0) && s_.budgetRanksBySpread;
    // Per pixel in bySpread's ranking: rank[i] = rankScale * max(calibrated^2, independentScale * independent).
    // One pass over the pixel sums, which are large, also sums the image's rays for the round's size (a second
    // pass cost a short budget's first round a few percent of its rays); the several-sample pixels' two figures
    // are kept for the scale.
    double imageRays = 0.0, calibratedSum = 0.0, independentSum = 0.0;
    std::vector<std::pair<float, float>> figures;  // (calibrated^2, independent) of the several-sample pixels
    for (std::size_t i = 0; i < acc_.size(); ++i) {
      imageRays += acc_[i].rays;
      if (bySpread && acc_[i].n >= 2 && fb_.traced[i]) {
        figures.emplace_back(fb_.samplingRms[i] * fb_.samplingRms[i], independentVariance(i));
        calibratedSum += double(figures.back().first);
        independentSum += double(figures.back().second);
      }
    }
    float independentScale = 0.0f, rankScale = 1.0f;  // (0: rank by the calibrated estimate alone)
    if (calibratedSum > 0.0 && independentSum > 0.0) {
      independentScale = float(std::min(1.0, calibratedSum / independentSum));
      double rankSum = 0.0;
      for (const auto& [calibrated, independent] : figures)
        rankSum += double(std::max(calibrated, independentScale * independent));
      rankScale = float(calibratedSum / rankSum);
    }
    struct Choice {
      float gainPerRay = 0.0f, rays = 0.0f;
      uint8_t action = kKeep;
    };
    // sampleOnly: the pixel's sampling way only (a one-sample pixel's grid, which a round of singles must give)
    auto choose = [&](std::size_t i, bool sampleOnly) {
      const PixelSums& ps = acc_[i];
      // The truncation bound scaled by the share of it that loosening changed so far at this level
      const float t = fb_.truncation[i] * share[std::size_t(ps.level + 1)], smp = fb_.sampling[i];
      const float floor = single(i) ? float(kMinimumVariance * s_.targetError * s_.targetError) : 0.0f;
      float variance = std::max(floor, fb_.samplingRms[i] * fb_.samplingRms[i]);
      if (independentScale > 0.0f && ps.n >= 2)
        variance = rankScale * std::max(variance, independentScale * independentVariance(i));
      const float raysPerSample = std::max(1.0f, float(ps.rays)) / float(ps.n);
      Choice c;
      if (canSample(i)) {
        float gain;
        if (ps.n == 1 && ps.strata == 1 && maxSamples >= kFirstStrata) {
          // Centre sample -> jittered 2x2 grid (coarse when its sampling estimate is well above its bound)
          const bool coarse = ps.level == 0 && coarse_ && t * kCoarseMargin < smp;
          c.action = coarse ? kSampleCoarse : kSample;
          gain = (1.0f - 1.0f / float(kFirstStrata)) * variance;  // 4 samples: a quarter of the variance
          c.rays = float(kFirstStrata) * raysPerSample * gridGrowth[coarse ? 1 : 0];
        } else {
          const int add = std::min(ps.n, maxSamples - ps.n);
          gain = variance * float(add) / float(ps.n + add);  // n / (n + add) of the variance left
          c.action = kSample;
          c.rays = float(add) * raysPerSample;
        }
        c.gainPerRay = gain / c.rays;
      }
      if (canLoosen(i) && !sampleOnly) {
        // A looser level is taken to leave kLoosenLeaves of the truncation part
        const float rays = float(ps.n) * raysPerSample * loosenGrowth[std::size_t(ps.level + 1)];
        const float gain = t * t * (1.0f - kLoosenLeaves * kLoosenLeaves) / rays;
        if (gain > c.gainPerRay) c = Choice{gain, rays, kLoosen};
      }
      return c;
    };
    // The round's size in rays: half the rays of the image so far (rounds grow geometrically, so their
    // re-estimates cost little), with a budget at most what the time left can trace (at the rate so far), all
    // of it if a round that size would leave less than half a round
    double roundRays = kRoundShare * imageRays;
    if (tiles_.deadline()) {
      RayStats traced;
      for (const RayStats& r : tileStats_) traced += r;
      const double spent = elapsed() - before;
      const double left = std::chrono::duration<double>(*tiles_.deadline() - std::chrono::steady_clock::now()).count();
      // This call's rate; a call that continues a frame has traced nothing yet: the earlier calls' rate (the image's
      // rays over their seconds). A rate of 0 made an empty round, which ended the refinement (issue 28)
      const double rate = traced.traversals() > 0 && spent > 0.0 ? double(traced.traversals()) / spent
                          : before > 0.0                        ? imageRays / before
                                                                : 0.0;
      if (rate > 0.0 && left > 0.0) {
        const double affordable = rate * left;
        if (kBudgetRoundsLeft * roundRays > affordable) roundRays = affordable;
      }
    }
    // The pixels with the most gain per ray whose rays add up to the round's size: costs summed per priority
    // bucket (a quarter octave each), taken from the top bucket down
    // The estimate is under the target but for the one-sample pixels: this round gives all of them (and only
    // them) their grids (not a looser level, which leaves them one sample), whatever the round's size
    const bool singlesOnly = s_.targetError > 0.0 && fs.calibrated.rms <= s_.targetError;
    const float least = float(kLeastEstimateShare * s_.targetError);
    std::vector<Choice> choices(acc_.size());
    std::vector<double> bucketRays(kBuckets, 0.0), bucketGain(kBuckets, 0.0);
    // A pixel kept (gain 0) has no bucket of its own: the lowest. Clamped in float, before the conversion to
    // int, which is undefined for log2(0) = -inf (UBSan's finding in CI)
    auto bucketOf = [](float g) {
      if (!(g > 0.0f)) return 0;
      const float b = std::floor(kBucketsPerOctave * std::log2(g)) + float(kBuckets / 2);
      return int(std::clamp(b, 0.0f, float(kBuckets - 1)));
    };
    for (std::size_t i = 0; i < acc_.size(); ++i) {
      if (!fb_.traced[i] || !(canSample(i) || canLoosen(i))) continue;
      if (!single(i) && (estimate(i) < least || estimate(i) <= 0.0f)) continue;
      choices[i] = choose(i, singlesOnly && single(i));
      if (choices[i].action != kKeep && choices[i].gainPerRay > 0.0f) {
        const std::size_t b = std::size_t(bucketOf(choices[i].gainPerRay));
        bucketRays[b] += choices[i].rays;
        bucketGain[b] += double(choices[i].gainPerRay) * choices[i].rays;  // its expected squared-error drop
      } else {
        choices[i].action = kKeep;
      }
    }
    // ... or, near the target, fewer: the top buckets whose expected drop of the image's squared error is
    // kNeedMargin times what the target still needs (a round of the full size overshot the target: 0.8x the
    // samples per pixel at the stop over the study's scenes, data/benchmark/target-error/README.md)
    double need = -1.0;
    if (s_.targetError > 0.0) {
      std::size_t traced = 0;
      for (std::size_t i = 0; i < acc_.size(); ++i) traced += fb_.traced[i] != 0;
      const double rms = fs.calibrated.rms, t = s_.targetError;
      need = rms > t ? kNeedMargin * (rms * rms - t * t) * double(traced) : -1.0;
    }
    int cutBucket = kBuckets;
    for (double sum = 0.0, gain = 0.0; cutBucket > 0 && sum < roundRays && (need < 0.0 || gain < need);) {
      sum += bucketRays[std::size_t(--cutBucket)];
      gain += bucketGain[std::size_t(cutBucket)];
    }
    // The frame's first round with a target also grids every one-sample pixel on the probe pattern
    const bool probe = s_.targetError > 0.0 && fs.refinementRounds == 0;
    std::size_t marked = 0, probes = 0;
    for (std::size_t i = 0; i < acc_.size(); ++i) {
      const Choice& c = choices[i];
      const bool take = singlesOnly ? single(i) : bucketOf(c.gainPerRay) >= cutBucket;
      marks_[i] = c.action != kKeep && take ? c.action : uint8_t(kKeep);
      if (probe && single(i) && probePixel(int(i % std::size_t(w_)), int(i / std::size_t(w_)))) {
        if (marks_[i] != kSample && marks_[i] != kSampleCoarse)
          marks_[i] = choose(i, true).action == kSampleCoarse ? kSampleCoarse : kSample;
        acc_[i].probeEstimate = fb_.samplingRms[i];
        ++probes;
      }
      marked += marks_[i] != kKeep;
    }
    measures_.addProbesMarked(probes);
    if (marked == 0) {
      fs.refinementFinished = true;
      fs.refinementExhausted = true;
      break;
    }
    worked = true;
    refineRound(maxSamples);
    if (cutShort(fs, keep)) break;
    finishRound(fs, rounds, elapsed());
  }
  tiles_.setDeadline(std::nullopt);
  tiles_.setSliceEnd(std::nullopt);
}

// Refines the marked pixels over the tiles that have any (a tile's pixels are unmarked as they are refined)
void FrameJob::refineRound(int maxSamples) {
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
  tiles_.run(
      slots.size(), [&](int i) { refinePixels(slots[std::size_t(i)], maxSamples); }, false, true);
}

// Whether the round just run was cut short by an abort or the time slice (not the budget, which ends the
// frame): then its pixels still marked are kept for the next call (and, unless aborted, the estimate is brought up
// to the image shown)
bool FrameJob::cutShort(FrameStats& fs, RefinementState* keep) {
  if (tiles_.pastDeadline()) return false;
  if (std::none_of(marks_.begin(), marks_.end(), [](uint8_t m) { return m != kKeep; })) return false;
  if (keep) keep->pending = std::move(marks_);
  if (!tiles_.aborted()) estimateErrors(fs);
  return true;
}

// After a round: re-estimate, count it and record the progress
void FrameJob::finishRound(FrameStats& fs, int& rounds, double seconds) {
  ++fs.refinementRounds;
  ++rounds;
  estimateErrors(fs, true);
  fs.progress.emplace_back(seconds, fs.calibrated.rms);
}

// The coarse level -1 of extra samples: the contribution threshold x kCoarseFactor (at most kCoarseThreshold,
// never below the frame's), depth as the frame's. Null when it would trace as the frame does (threshold 0 or
// already at the cap).
std::unique_ptr<Integrator> FrameJob::makeCoarse() const {
  IntegratorSettings is = s_.integrator;
  const float t =
      std::max(is.contributionThreshold, std::min(kCoarseThreshold, is.contributionThreshold * kCoarseFactor));
  if (!(t > is.contributionThreshold)) return nullptr;
  is.contributionThreshold = t;
  return std::make_unique<Integrator>(scene_, is, camera_.up());
}

// Builds the integrators of levels 1..level not built yet (on the calling thread)
void FrameJob::prepareLevels(int level) {
  while (int(levels_.size()) < level)
    levels_.push_back(
        std::make_unique<Integrator>(scene_, levelSettings(s_.integrator, int(levels_.size()) + 1), camera_.up()));
}

void FrameJob::refinePixels(int tileSlot, int maxSamples) {
  TileCounts counts(tileStats_[tileSlot]);
  RayStats& st = counts.st;
  uint64_t samples = 0, retraced = 0;
  forTilePixels(tileSlot, [&](int px, int py, std::size_t idx, const Color& rowBackground) {
    if (marks_[idx] == kKeep) return;
    PixelSums& ps = acc_[idx];
    bool loosened = false;
    int levelBefore = 0;
    uint32_t raysBefore = 0;
    const float probeEstimate = ps.probeEstimate;  // (a probe's: see kProbeStride)
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
    const bool probed = probeEstimate >= 0.0f && ps.n > 1;  // a probe that got its grid (once: the grid clears it)
    if (loosened || probed) {
      const Color4 d = glm::abs(glm::clamp(fb_.color[idx], Color4(0.0f), Color4(1.0f)) -
                                glm::clamp(colorBefore, Color4(0.0f), Color4(1.0f)));
      const float change = std::max(std::max(d.x, d.y), d.z);
      if (loosened) measures_.addLoosen(levelBefore, raysBefore, ps.rays, boundBefore, change);
      if (probed) measures_.addProbe(probeEstimate, change);
    }
  });
  samples_ += samples;
  retraced_ += retraced;
}

}  // namespace whitted
