// The volume primitive: transfer functions, validation, grid sampling and the march of one ray segment.
#include "geometry/volume.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace whitted {

namespace {

// The segment of a piecewise-linear function's nodes around s: index of the left node and the weight of the right
template <typename X>
void locate(const X& xs, float s, std::size_t& i, float& w) {
  const auto it = std::upper_bound(xs.begin(), xs.end(), s);
  if (it == xs.begin()) {
    i = 0;
    w = 0.0f;
    return;
  }
  if (it == xs.end()) {
    i = xs.size() - 1;
    w = 0.0f;
    return;
  }
  i = std::size_t(it - xs.begin()) - 1;
  const float span = xs[i + 1] - xs[i];
  w = span > 0.0f ? (s - xs[i]) / span : 1.0f;
}

// Sorts the nodes by x (stable) and keeps the finite ones, values clamped to [0, 1]
template <typename Y>
void sortNodes(std::vector<float>& xs, std::vector<Y>& ys) {
  const std::size_t n = std::min(xs.size(), ys.size());
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return xs[a] < xs[b]; });
  std::vector<float> nx;
  std::vector<Y> ny;
  for (std::size_t k : order) {
    if (!std::isfinite(xs[k])) continue;
    Y y = ys[k];
    if constexpr (std::is_same_v<Y, float>) {
      y = std::isfinite(y) ? std::clamp(y, 0.0f, 1.0f) : 0.0f;
    } else {
      for (int c = 0; c < 3; ++c) y[c] = std::isfinite(y[c]) ? std::clamp(y[c], 0.0f, 1.0f) : 0.0f;
    }
    nx.push_back(xs[k]);
    ny.push_back(y);
  }
  xs.swap(nx);
  ys.swap(ny);
}

}  // namespace

Color TransferFunction::color(float s) const {
  if (colorX.empty()) return Color(1.0f);
  std::size_t i;
  float w;
  locate(colorX, s, i, w);
  return w > 0.0f ? colorY[i] + w * (colorY[i + 1] - colorY[i]) : colorY[i];
}

float TransferFunction::opacity(float s) const {
  if (opacityX.empty()) return 0.0f;
  std::size_t i;
  float w;
  locate(opacityX, s, i, w);
  return w > 0.0f ? opacityY[i] + w * (opacityY[i + 1] - opacityY[i]) : opacityY[i];
}

std::string Volume::prepare(std::size_t& invalidScalars) {
  ready_ = false;
  invalidScalars = 0;
  static const char* kAxis[3] = {"x", "y", "z"};
  std::size_t n = 1;
  for (int a = 0; a < 3; ++a) {
    if (grid.dims[a] < 1) return "volume: no points along " + std::string(kAxis[a]);
    if (grid.dims[a] == 1)
      return "volume: a single point along " + std::string(kAxis[a]) + " (a slice has no thickness to march)";
    n *= std::size_t(grid.dims[a]);
  }
  if (grid.scalars.size() != n)
    return "volume: " + std::to_string(grid.scalars.size()) + " scalars for " + std::to_string(n) + " points";
  if (!isFinite(grid.origin)) return "volume: non-finite origin";
  for (int a = 0; a < 3; ++a)
    if (!(std::isfinite(grid.spacing[a]) && grid.spacing[a] != 0.0))
      return "volume: spacing along " + std::string(kAxis[a]) + " is zero or not finite";
  Mat3 toWorld = grid.direction;
  for (int a = 0; a < 3; ++a) toWorld[a] *= grid.spacing[a];
  const double det = glm::determinant(toWorld);
  if (!(std::isfinite(det) && det != 0.0)) return "volume: direction matrix singular or not finite";
  toIndex_ = glm::inverse(toWorld);
  if (!std::isfinite(transfer.unitDistance) || transfer.unitDistance <= 0.0)
    return "volume: scalar opacity unit distance must be positive";
  sortNodes(transfer.colorX, transfer.colorY);
  sortNodes(transfer.opacityX, transfer.opacityY);

  // Non-finite scalars: NaN, which sampling reads as transparent
  for (float& s : grid.scalars)
    if (!std::isfinite(s)) {
      s = std::numeric_limits<float>::quiet_NaN();
      ++invalidScalars;
    }

  // World bounds: the eight corners of the point box
  bounds_ = Bounds3();
  for (int c = 0; c < 8; ++c) {
    Vec3 idx((c & 1) ? grid.dims[0] - 1 : 0, (c & 2) ? grid.dims[1] - 1 : 0, (c & 4) ? grid.dims[2] - 1 : 0);
    const Vec3 p = grid.origin + toWorld * idx;
    bounds_.lo = glm::min(bounds_.lo, p);
    bounds_.hi = glm::max(bounds_.hi, p);
  }
  if (!(isFinite(lengthMetric[0]) && isFinite(lengthMetric[1]) && isFinite(lengthMetric[2]) &&
        glm::determinant(lengthMetric) != 0.0))
    return "volume: length metric singular or not finite";
  const Mat3 measured = lengthMetric * toWorld;  // grid axes, measured
  double shortest = kInfinity;
  for (int a = 0; a < 3; ++a) shortest = std::min(shortest, glm::length(measured[a]));
  const double diagonal = glm::length(measured * Vec3(grid.dims[0] - 1, grid.dims[1] - 1, grid.dims[2] - 1));
  step_ = std::isfinite(sampleDistance) && sampleDistance > 0.0 ? sampleDistance : 0.5 * shortest;
  step_ = std::max(step_, diagonal / kMaxSteps);
  if (!(std::isfinite(step_) && step_ > 0.0)) return "volume: no usable step (grid extent not finite)";
  buildTable();
  buildMacroCells();
  ready_ = true;
  return std::string();
}

void Volume::buildMacroCells() {
  const int* n = grid.dims;
  // The scalar ranges: once per grid (the same scalars at the same address, size and dimensions: a transfer
  // function edit re-prepares the volume with its grid)
  const bool sameGrid = !macroMin_.empty() && rangesOf_ == grid.scalars.data() &&
                        rangesSize_ == grid.scalars.size() && std::equal(n, n + 3, rangesDims_);
  if (!sameGrid) {
    rangesOf_ = grid.scalars.data();
    rangesSize_ = grid.scalars.size();
    std::copy(n, n + 3, rangesDims_);
    for (int a = 0; a < 3; ++a) macroDims_[a] = std::max(1, (n[a] - 1 + kMacroCell - 1) / kMacroCell);
    const std::size_t cells = std::size_t(macroDims_[0]) * macroDims_[1] * macroDims_[2];
    macroMin_.assign(cells, std::numeric_limits<float>::infinity());
    macroMax_.assign(cells, -std::numeric_limits<float>::infinity());
    const float* sc = grid.scalars.data();
    for (int cz = 0; cz < macroDims_[2]; ++cz)
      for (int cy = 0; cy < macroDims_[1]; ++cy)
        for (int cx = 0; cx < macroDims_[0]; ++cx) {
          float lo = std::numeric_limits<float>::infinity(), hi = -lo;
          bool nan = false;
          for (int k = cz * kMacroCell; k <= std::min((cz + 1) * kMacroCell, n[2] - 1); ++k)
            for (int j = cy * kMacroCell; j <= std::min((cy + 1) * kMacroCell, n[1] - 1); ++j) {
              const float* row = sc + (std::size_t(k) * n[1] + j) * n[0];
              for (int i = cx * kMacroCell; i <= std::min((cx + 1) * kMacroCell, n[0] - 1); ++i) {
                const float v = row[i];
                nan |= std::isnan(v);
                lo = std::min(lo, v);
                hi = std::max(hi, v);
              }
            }
          const std::size_t c = (std::size_t(cz) * macroDims_[1] + cy) * macroDims_[0] + cx;
          macroMin_[c] = nan ? std::numeric_limits<float>::quiet_NaN() : lo;
          macroMax_[c] = hi;
        }
  }
  // Empty: no sample inside can have an opacity above 0 (NaN points are sampled, and counted). A constant cell's
  // samples are that constant exactly (a + f (b - a) with a = b): the lookup the march would make decides. Else every
  // table entry a sample in the range can interpolate between must have opacity 0: the range widened by 8 float
  // ulps of its largest magnitude (trilinear interpolation's a + f (b - a) can pass b by about an ulp of the larger
  // value), then one entry more on each side (the rounding of the entry index)
  macroEmpty_.assign(macroMin_.size(), 0);
  const float last = float(table_.size() - 1);
  for (std::size_t c = 0; c < macroMin_.size(); ++c) {
    if (std::isnan(macroMin_[c])) continue;
    if (macroMin_[c] == macroMax_[c]) {
      macroEmpty_[c] = !(lookup(macroMin_[c]).opacity > 0.0f);
      continue;
    }
    const float margin = 8.0f * std::numeric_limits<float>::epsilon() *
                             std::max(std::abs(macroMin_[c]), std::abs(macroMax_[c]));
    const float xa = (macroMin_[c] - margin - tableMin_) * tableScale_,
                xb = (macroMax_[c] + margin - tableMin_) * tableScale_;
    if (!std::isfinite(xa) || !std::isfinite(xb)) continue;
    const int j0 = int(std::clamp(std::floor(xa) - 1.0f, 0.0f, last));
    const int j1 = int(std::clamp(std::ceil(xb) + 1.0f, 0.0f, last));
    bool empty = true;
    for (int j = j0; j <= j1 && empty; ++j) empty = table_[std::size_t(j)].opacity <= 0.0f;
    macroEmpty_[c] = empty;
  }
}

int64_t Volume::skipEmptyCell(const Vec3& o, const Vec3& d, const int cell[3], double t0, double dt, int64_t k0) const {
  // The ray leaves the cell through the far plane of one axis: in index space cell c spans [c K, (c + 1) K) (the
  // first and last cells reach on outward, as the cell of a point is clamped)
  double tExit = kInfinity;
  for (int a = 0; a < 3; ++a) {
    const int c = cell[a];
    double plane;
    if (d[a] > 0.0 && c + 1 < macroDims_[a])
      plane = double(c + 1) * kMacroCell;
    else if (d[a] < 0.0 && c > 0)
      plane = double(c) * kMacroCell;
    else
      continue;
    tExit = std::min(tExit, (plane - o[a]) / d[a]);
  }
  // Steps whose middle lies before the exit by more than a step stay inside (by far more than rounding): skipped;
  // the march samples from the step before the first middle past the exit and looks again
  const double k = std::ceil((tExit - t0) / dt - 0.5) - 1.0;
  return k > double(k0 + 1) ? int64_t(std::min(k, 0x1p60)) : k0 + 1;  // capped: the caller adds 1
}

void Volume::buildTable() {
  // Over the range of both functions' nodes; outside it both are constant (clamped)
  float lo = std::numeric_limits<float>::infinity(), hi = -lo;
  for (const std::vector<float>* xs : {&transfer.colorX, &transfer.opacityX})
    for (float x : *xs) {
      lo = std::min(lo, x);
      hi = std::max(hi, x);
    }
  if (!(lo <= hi)) lo = hi = 0.0f;  // no nodes
  const int n = hi > lo ? kTableSize : 1;
  tableMin_ = lo;
  tableScale_ = hi > lo ? float(double(n - 1) / (double(hi) - double(lo))) : 0.0f;
  if (!std::isfinite(tableScale_)) tableScale_ = 0.0f;
  table_.resize(std::size_t(n));
  const double ratio = step_ / transfer.unitDistance;
  for (int i = 0; i < n; ++i) {
    const float s = n > 1 ? float(double(lo) + (double(hi) - double(lo)) * i / (n - 1)) : lo;
    Entry& e = table_[std::size_t(i)];
    e.color = transfer.color(s);
    e.opacity = transfer.opacity(s);
    e.alphaStep = float(-std::expm1(std::log1p(-double(e.opacity)) * ratio));
  }
}

Volume::Entry Volume::lookup(float s) const {
  float x = (s - tableMin_) * tableScale_;
  const float last = float(table_.size() - 1);
  x = x > 0.0f ? (x < last ? x : last) : 0.0f;  // NaN (an overflowed s - tableMin_ times 0) gives 0
  const std::size_t i = std::size_t(x);
  const std::size_t j = std::min(i + 1, table_.size() - 1);
  const float f = x - float(i);
  const Entry &a = table_[i], &b = table_[j];
  return Entry{a.color + f * (b.color - a.color), a.opacity + f * (b.opacity - a.opacity),
               a.alphaStep + f * (b.alphaStep - a.alphaStep)};
}

bool Volume::clip(const Ray& ray, double& t0, double& t1) const {
  // Slabs of the index box [0, n - 1] per axis, in index space (t keeps its meaning)
  const Vec3 o = toIndex_ * (ray.origin - grid.origin);
  const Vec3 d = toIndex_ * ray.dir;
  for (int a = 0; a < 3; ++a) {
    const double hi = double(grid.dims[a] - 1);
    if (d[a] == 0.0) {
      if (!(o[a] >= 0.0 && o[a] <= hi)) return false;
      continue;
    }
    double ta = (0.0 - o[a]) / d[a], tb = (hi - o[a]) / d[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return t0 < t1;
}

float Volume::sample(const Vec3& index) const {
  return sampleIndex(index);
}

inline float Volume::sampleIndex(const Vec3& index) const {
  const int nx = grid.dims[0], ny = grid.dims[1], nz = grid.dims[2];
  double p[3];
  for (int a = 0; a < 3; ++a) {
    const double hi = double(grid.dims[a] - 1);
    p[a] = index[a] >= 0.0 ? (index[a] <= hi ? index[a] : hi) : 0.0;  // NaN -> 0
  }
  const float* s = grid.scalars.data();
  if (interpolation == VolumeInterpolation::Nearest) {
    const std::size_t i = std::size_t(p[0] + 0.5), j = std::size_t(p[1] + 0.5), k = std::size_t(p[2] + 0.5);
    return s[(k * std::size_t(ny) + j) * std::size_t(nx) + i];
  }
  int i0[3];
  float f[3];
  for (int a = 0; a < 3; ++a) {
    i0[a] = std::min(int(p[a]), grid.dims[a] - 2);
    f[a] = float(p[a] - double(i0[a]));
  }
  const std::size_t sx = 1, sy = std::size_t(nx), sz = std::size_t(nx) * std::size_t(ny);
  const float* c = s + std::size_t(i0[2]) * sz + std::size_t(i0[1]) * sy + std::size_t(i0[0]);
  const float c00 = c[0] + f[0] * (c[sx] - c[0]);
  const float c10 = c[sy] + f[0] * (c[sy + sx] - c[sy]);
  const float c01 = c[sz] + f[0] * (c[sz + sx] - c[sz]);
  const float c11 = c[sz + sy] + f[0] * (c[sz + sy + sx] - c[sz + sy]);
  const float c0 = c00 + f[1] * (c10 - c00);
  const float c1 = c01 + f[1] * (c11 - c01);
  (void)nz;
  return c0 + f[2] * (c1 - c0);
}

void Volume::march(const Ray& ray, double t0, double t1, bool emission, float stopBelow, VolumeMarch& acc) const {
  const double len = glm::length(lengthMetric * ray.dir);
  if (!(t1 > t0) || !(len > 0.0)) return;
  const Vec3 o = toIndex_ * (ray.origin - grid.origin);
  const Vec3 d = toIndex_ * ray.dir;
  const double dt = step_ / len;
  const double count = std::ceil((t1 - t0) / dt);
  if (!(count >= 1.0)) return;
  const int64_t steps = int64_t(std::min(count, 2.0 * kMaxSteps));
  const double perUnit = len / transfer.unitDistance;
  const bool skip = skipEmptySpace && !macroEmpty_.empty();
  // The macro cell is looked up at the first step and then only at the first step that may lie outside the last
  // one looked up (skipEmptyCell: steps before it lie inside by more than a step): an empty cell's steps are
  // skipped, a non-empty cell's sampled without looking again; the step a skip lands on (about at the exit) is
  // sampled without looking
  int64_t nextLook = skip ? 0 : std::numeric_limits<int64_t>::max();
  for (int64_t k = 0; k < steps; ++k) {
    const double ta = t0 + double(k) * dt;
    const bool full = k + 1 < steps && ta + dt <= t1;
    const double tb = full ? ta + dt : t1;
    if (!(tb > ta)) continue;
    const Vec3 p = o + (0.5 * (ta + tb)) * d;
    if (k >= nextLook) {
      const int cell[3] = {macroCell(p.x, 0), macroCell(p.y, 1), macroCell(p.z, 2)};
      const std::size_t c =
          (std::size_t(cell[2]) * std::size_t(macroDims_[1]) + std::size_t(cell[1])) * std::size_t(macroDims_[0]) +
          std::size_t(cell[0]);
      const int64_t exit = skipEmptyCell(o, d, cell, t0, dt, k);
      if (macroEmpty_[c]) {  // no sample here adds anything: on to the first that may be outside the cell
        nextLook = exit + 1;
        k = exit - 1;
        continue;
      }
      nextLook = exit;
    }
    const float s = sampleIndex(p);
    ++acc.samples;
    if (std::isnan(s)) {
      ++acc.invalidSamples;
      continue;
    }
    const Entry e = lookup(s);
    if (e.opacity <= 0.0f) continue;
    // 1 - (1 - a)^(h / unitDistance), from the table for a full step; a = 1 gives log1p(-1) = -inf and alpha 1
    const float alpha = full ? e.alphaStep : float(-std::expm1(std::log1p(-double(e.opacity)) * (tb - ta) * perUnit));
    if (emission) acc.color += (acc.transmittance * alpha) * e.color;
    acc.transmittance *= 1.0f - alpha;
    if (acc.transmittance < stopBelow) {
      acc.terminated = true;
      return;
    }
  }
}

}  // namespace whitted
