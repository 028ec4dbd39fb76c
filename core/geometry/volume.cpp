// The volume primitive: transfer functions, validation, the transfer-function table and the macro cells (the march
// and the sampling: volume_sampling.cpp).
#include "geometry/volume.h"

#include "util/parallel.h"

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
    if (grid.dims[a] > kMaxPointsPerAxis)
      return "volume: more than 2^24 points along " + std::string(kAxis[a]) +
             " (sample points are single precision)";
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
  // Shading coefficients as vtkVolumeProperty clamps them (non-finite: 0); gradient opacity in [0, 1], off
  // without a usable range
  for (float* k : {&transfer.ambient, &transfer.diffuse, &transfer.specular})
    *k = std::isfinite(*k) ? std::clamp(*k, 0.0f, 1.0f) : 0.0f;
  transfer.specularPower =
      std::isfinite(transfer.specularPower) ? std::clamp(transfer.specularPower, 0.0f, 128.0f) : 0.0f;
  for (float& g : transfer.gradientOpacity) g = std::isfinite(g) ? std::clamp(g, 0.0f, 1.0f) : 0.0f;
  if (!(std::isfinite(transfer.gradientOpacityMax) && transfer.gradientOpacityMax > 0.0) ||
      transfer.gradientOpacity.size() < 2)
    transfer.gradientOpacity.clear();

  // Non-finite scalars: NaN, which sampling reads as transparent (on all cores for a large grid)
  float* sc = grid.scalars.data();
  invalidScalars = VolumeGrid::countInPieces(grid.scalars.size(), [&](std::size_t i) {
    if (std::isfinite(sc[i])) return false;
    sc[i] = std::numeric_limits<float>::quiet_NaN();
    return true;
  });

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
  // The finest scale's step is at least the longest diagonal / (2 kMaxSteps): no chord takes more steps than the
  // march's cap (a sheared grid's diagonals differ)
  double longest = 0.0;
  for (int c = 0; c < 4; ++c)
    longest = std::max(longest, glm::length(measured * Vec3((c & 1 ? -1.0 : 1.0) * (grid.dims[0] - 1),
                                                            (c & 2 ? -1.0 : 1.0) * (grid.dims[1] - 1), grid.dims[2] - 1)));
  finestScale_ = 0;
  while (finestScale_ > -30 && std::ldexp(step_, finestScale_ - 1) >= longest / (2.0 * kMaxSteps)) --finestScale_;
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
    // One job per slab of cells (each writes its own cells)
    WorkerPool pool(VolumeGrid::threadsFor(grid.scalars.size()));
    pool.run(uint32_t(macroDims_[2]), [&](uint32_t slab) {
      const int cz = int(slab);
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
    });
  }
  // Empty: no sample inside can have an opacity above 0 (NaN points are sampled, and counted). A constant cell's
  // samples are that constant exactly (a + f (b - a) with a = b): the lookup the march would make decides. Else every
  // table entry a sample in the range can interpolate between must have opacity 0: the range widened by 8 float
  // ulps of its largest magnitude (trilinear interpolation's a + f (b - a) can pass b by about an ulp of the larger
  // value), then one entry more on each side (the rounding of the entry index)
  macroEmpty_.assign(macroMin_.size(), 0);
  const float last = tableLast_;
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
  table_.resize(std::size_t(n) + 1);  // entry n repeats entry n - 1: lookups read i + 1 <= n unclamped
  tableLast_ = float(n - 1);
  const double ratio = step_ / transfer.unitDistance;
  for (int i = 0; i < n; ++i) {
    const float s = n > 1 ? float(double(lo) + (double(hi) - double(lo)) * i / (n - 1)) : lo;
    Entry& e = table_[std::size_t(i)];
    e.color = transfer.color(s);
    e.opacity = transfer.opacity(s);
    e.alphaStep = float(-std::expm1(std::log1p(-double(e.opacity)) * ratio));
  }
  table_[std::size_t(n)] = table_[std::size_t(n - 1)];
  int first = n, last = -1;
  for (int i = 0; i < n; ++i)
    if (table_[std::size_t(i)].opacity > 0.0f) {
      first = std::min(first, i);
      last = i;
    }
  opaqueLo_ = last < 0 ? std::numeric_limits<float>::infinity() : float(first - 1);
  opaqueHi_ = last < 0 ? -std::numeric_limits<float>::infinity() : float(last + 1);
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

}  // namespace whitted
