// A volume: point scalars on a regular grid (origin, spacing, direction matrix, as vtkImageData), a transfer function
// (piecewise-linear RGB colour and scalar opacity with VTK's ScalarOpacityUnitDistance) and the emission-absorption
// march of one ray segment through it, front to back. The scene keeps volumes beside its objects (Scene::addVolume)
// and orders the segments of several volumes along a ray (scene/volumes.cpp); the integrator composites them with
// the surfaces (shading/volume_march.cpp).
#pragma once

#include "util/math.h"
#include "util/memory.h"
#include "util/parallel.h"

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace whitted {

/// Piecewise-linear functions of the scalar, clamped to their end values outside their range (VTK's Clamping on).
/// Nodes must be in increasing x; Volume::prepare sorts them and clamps values to [0, 1].
struct TransferFunction {
  std::vector<float> colorX;
  std::vector<Color> colorY;  ///< Linear RGB in [0, 1]. No node: white.
  std::vector<float> opacityX;
  std::vector<float> opacityY;  ///< Opacity per unitDistance of path, in [0, 1]. No node: fully transparent.
  /// vtkVolumeProperty::ScalarOpacityUnitDistance: the path length over which a sample's opacity applies as given;
  /// a step of length h has alpha 1 - (1 - opacity)^(h / unitDistance). Default 1.
  double unitDistance = 1.0;
  /// vtkVolumeProperty Shade: each sample's colour C is lit as VTK's GPU mapper lights it (a headlight scene of
  /// VTK 9.1's): ambient C + sum over lights of diffuse |n . l| C + specular |n . h|^specularPower (light
  /// colours times intensity; n the scalar's gradient direction, two-sided; h the half vector of l and the
  /// direction back along the ray), clamped to [0, 1], before it is weighted by its alpha. VTK's defaults.
  bool shade = false;
  float ambient = 0.1f, diffuse = 0.7f, specular = 0.2f, specularPower = 10.0f;
  /// Gradient opacity (VTK's, with its default range): a sample's alpha times this function of the gradient
  /// magnitude m, given at m = gradientOpacityMax * i / (size - 1) and clamped beyond; m is the scalar's change per
  /// mean voxel spacing (|gradient| x (spacing x + y + z) / 3, in the grid's own axes). Empty: off.
  std::vector<float> gradientOpacity;
  double gradientOpacityMax = 0.0;

  Color color(float s) const;
  float opacity(float s) const;
};

enum class VolumeInterpolation { Nearest, Linear };

/// A light as volume shading sees it (Scene makes them from its lights at commit): directional (toward the light)
/// or positional (VTK's attenuation and spot cone), colour times intensity.
struct VolumeLight {
  bool positional = false;
  Vec3 toLight{0.0, 0.0, 1.0};      ///< Directional: unit vector toward the light.
  Vec3 position{0.0};               ///< Positional: where the light is.
  Vec3 attenuation{1.0, 0.0, 0.0};  ///< Positional: constant, linear, quadratic.
  Vec3 axis{0.0, 0.0, -1.0};        ///< Spot: unit direction the light travels.
  double cosCone = -1.0;            ///< Spot: cosine of the cone's half angle (-1: not a spot).
  double exponent = 1.0;            ///< Spot exponent.
  Color radiance{1.0f};             ///< Colour x intensity.
};

/// The lights of volume shading and how they light (Scene::volumeLighting; VTK's GPU mapper's two cases).
struct VolumeLighting {
  const VolumeLight* lights = nullptr;
  std::size_t count = 0;
  /// The ambient term is ambient x this, times the sample's colour along rays. VTK's GPU mapper: ambient x C for a
  /// lone headlight (this 1), else ambient x the sum of the lights' ambient colours times their intensities
  /// (vtkLight's default ambient colour is black), not times C.
  Color ambient{1.0f};
  /// Every light arrives along the viewing ray (l = the direction back along the ray), as VTK's GPU mapper lights
  /// a lone headlight of intensity 1 (a lamp at the eye); else each light's own direction.
  bool alongRays = false;
};

/// A grid's scalars: resize() leaves them uninitialised (they are written in full right after; util/memory.h).
using VolumeScalars = UninitLargeVector<float>;

/// One-component point scalars on a regular grid: the point (i, j, k) is at origin + direction * (spacing * (i, j, k))
/// (vtkImageData's index-to-physical map; direction is a GLM matrix, its columns the grid axes). Scalars x fastest,
/// stored as float (convert once with fromScalars).
struct VolumeGrid {
  int dims[3] = {0, 0, 0};
  Vec3 origin{0.0};
  Vec3 spacing{1.0};
  Mat3 direction{1.0};
  VolumeScalars scalars;  ///< (huge pages: a 256^3 grid in 32 page faults, not 16384: util/memory.h)

  /// A grid of data[nx * ny * nz] of any arithmetic type (float, double, integers), converted to float once.
  template <typename T>
  static VolumeGrid fromScalars(const int dims[3], const T* data) {
    VolumeGrid g;
    std::size_t n = 1;
    for (int a = 0; a < 3; ++a) {
      g.dims[a] = dims[a];
      n *= std::size_t(dims[a] > 0 ? dims[a] : 0);
    }
    convertScalars(data, n, g.scalars);
    return g;
  }
  /// data[0 .. n) as float into out (resized only when its size differs, and then not zeroed first); returns how
  /// many are not finite. On all cores for a large grid (countInPieces: a fresh array's pages are first touched by
  /// the threads that fill them; a 2 GiB 8-bit grid's zeroing pass on one thread had taken as long as the copy).
  template <typename T>
  static std::size_t convertScalars(const T* data, std::size_t n, VolumeScalars& out) {
    out.resize(n);
    float* o = out.data();
    return countInPieces(n, [&](std::size_t i) {
      o[i] = float(data[i]);
      return !std::isfinite(o[i]);
    });
  }
  /// Scalars per piece of the passes over a grid. Fixed, so counts do not depend on the thread count.
  static constexpr std::size_t kPiece = std::size_t(1) << 20;
  /// Threads for a pass over n scalars: all cores from 4 pieces on, else the calling thread alone.
  static int threadsFor(std::size_t n) { return n >= 4 * kPiece ? hardwareThreads() : 1; }
  /// Calls visit(i) for every i in [0, n), in pieces of kPiece on threadsFor(n) threads; returns how many calls
  /// returned true.
  template <typename Visit>
  static std::size_t countInPieces(std::size_t n, Visit&& visit) {
    std::vector<std::size_t> counts((n + kPiece - 1) / kPiece, 0);
    WorkerPool pool(threadsFor(n));
    forChunks(pool, n, kPiece, [&](std::size_t b, std::size_t e) {
      std::size_t k = 0;
      for (std::size_t i = b; i < e; ++i) k += visit(i) ? 1 : 0;
      counts[b / kPiece] = k;
    });
    std::size_t total = 0;
    for (std::size_t k : counts) total += k;
    return total;
  }
  std::size_t memoryBytes() const { return scalars.capacity() * sizeof(float); }
};

/// Front-to-back accumulation along a ray: premultiplied colour and transmittance (1 - opacity).
struct VolumeMarch {
  Color color{0.0f};
  float transmittance = 1.0f;
  bool terminated = false;        ///< Stopped early: transmittance fell below the stop threshold.
  uint64_t samples = 0;           ///< Samples taken.
  uint64_t invalidSamples = 0;    ///< Samples that read a non-finite scalar (taken as transparent).
};

/// How a ray marches the volumes it crosses: at step() x 2^scale (Volume::march's stepScale: 0 the volume's own
/// step, -1, -2, ... the looser levels of progressive refinement), and, where error is given, with the step
/// truncation's estimate added to *error (the march again at twice that step; the difference of the two results).
struct VolumeStep {
  int scale = 0;
  float* error = nullptr;
};

struct Volume {
  VolumeGrid grid;
  TransferFunction transfer;
  VolumeInterpolation interpolation = VolumeInterpolation::Linear;
  /// Step along rays; 0 (default): half the shortest grid axis spacing (a mapper's usual sample distance). At
  /// least the grid's diagonal / kMaxSteps. Measured, like unitDistance, with lengthMetric.
  double sampleDistance = 0.0;
  /// How lengths along a ray are measured for the step and the unit distance: a direction d has length
  /// |lengthMetric x d|. Identity (default): world units. VTK's GPU mapper measures them in the dataset's space,
  /// before the vtkVolume's matrix: the VTK converter sets the inverse of that matrix's linear part.
  Mat3 lengthMetric{1.0};
  bool visible = true;
  /// Empty-space skipping: the march steps over macro cells (kMacroCell^3 grid cells) where no sample can have an
  /// opacity above 0 (by the cells' scalar range and the transfer function), taking exactly the samples it would
  /// take otherwise wherever they can add anything: the same colour and transmittance, bit for bit; fewer samples
  /// counted. Off: every step is sampled (tests compare the two). Default on.
  bool skipEmptySpace = true;
  static constexpr double kMaxSteps = 20000.0;
  /// Points per axis at most: sample points are single precision, whose integers are exact up to 2^24 (so the
  /// last cell's index never rounds up past the grid).
  static constexpr int kMaxPointsPerAxis = 1 << 24;
  static constexpr int kMacroCell = 16;

  /// Checks and prepares the volume for marching (world bounds, index map, step; transfer functions sorted and
  /// clamped; infinite scalars made NaN). Returns an empty string if it can be traced, else why not (it is then
  /// skipped). invalidScalars gets the number of non-finite scalars (traced as transparent).
  std::string prepare(std::size_t& invalidScalars);
  bool ready() const { return ready_; }
  const Bounds3& bounds() const { return bounds_; }  ///< World bounds (after prepare).
  double step() const { return step_; }
  /// Entries of the transfer-function table (colour, opacity and a full step's alpha over the range of the nodes,
  /// interpolated linearly like the 1D textures of VTK's GPU mapper): exact where the functions are linear between
  /// table entries, e.g. constant.
  static constexpr int kTableSize = 1024;

  /// Parameter interval of the ray inside the grid's box, intersected with (t0, t1); false if empty.
  bool clip(const Ray& ray, double& t0, double& t1) const;
  /// The scalar at a point in index coordinates (clamped to the grid), by the interpolation mode, computed in single
  /// precision (as the march samples). NaN where a non-finite scalar is used.
  float sample(const Vec3& index) const;
  /// Emission-absorption over the ray parameter interval [t0, t1] (inside the box: see clip), front to back into
  /// acc: samples at the middle of steps of step() (the last one shorter), each with alpha
  /// 1 - (1 - opacity)^(length / unitDistance), colour added as acc.transmittance x alpha x colour (emission false:
  /// transmittance only). Stops once acc.transmittance < stopBelow (acc.terminated).
  /// With transfer.shade, each sample's colour is lit by lighting (none: ambient only); gradient opacity
  /// (transfer.gradientOpacity) scales each alpha. stepScale marches at step() x 2^stepScale instead (the step
  /// truncation's estimate marches at +1, progressive refinement's looser levels at -1, -2, ...: each full step's
  /// alpha from the table's by 1 - (1 - a)^(2^stepScale)), at most as fine as twice kMaxSteps over the grid's
  /// longest diagonal (a finer scale is taken as that one: finestStepScale).
  void march(const Ray& ray, double t0, double t1, bool emission, float stopBelow, VolumeMarch& acc,
             const VolumeLighting& lighting = VolumeLighting(), int stepScale = 0) const;
  /// The finest stepScale march() takes for this volume (after prepare): 0 or below.
  int finestStepScale() const { return finestScale_; }
  const Mat3& toIndex() const { return toIndex_; }  ///< World vector -> index-space vector (after prepare).

 private:
  bool ready_ = false;
  Bounds3 bounds_;
  Mat3 toIndex_{1.0};  ///< World vector -> index-space vector.
  double step_ = 1.0;
  int finestScale_ = 0;  ///< The least stepScale whose step is at least the longest diagonal / (2 kMaxSteps).
  struct Entry {
    Color color;
    float opacity;
    float alphaStep;  ///< 1 - (1 - opacity)^(step / unitDistance)
  };
  std::vector<Entry> table_;  ///< kTableSize entries (1 without a range), then the last one again.
  float tableMin_ = 0.0f, tableScale_ = 0.0f;  ///< Entry index = (scalar - tableMin_) x tableScale_.
  float tableLast_ = 0.0f;                     ///< The last entry's index (the repeated one not counted).
  /// Table indices x whose interpolated opacity may be above 0 lie in [opaqueLo_, opaqueHi_) (one entry beyond the
  /// first and last entries above 0: the lerp of two zero entries is 0 exactly); empty when none is.
  float opaqueLo_ = 0.0f, opaqueHi_ = 0.0f;
  /// Macro cells, x fastest: the scalar range over each one's points (its kMacroCell^3 cells and the points on their
  /// far faces, which trilinear samples inside read; NaN when a point is not finite), computed at a prepare whose
  /// grid differs from the last one's (scalars' address and size, dimensions), and whether every sample inside has
  /// opacity 0 (per transfer function, at every prepare).
  int macroDims_[3] = {0, 0, 0};
  std::vector<float> macroMin_, macroMax_;
  const float* rangesOf_ = nullptr;  ///< The scalars the ranges were computed from (compared, never read).
  std::size_t rangesSize_ = 0;
  int rangesDims_[3] = {0, 0, 0};
  std::vector<uint8_t> macroEmpty_;
  void buildMacroCells();
  struct CellLook;  ///< The march's macro-cell look-ups (volume_cells.h)
  void buildTable();
  Entry lookup(float s) const;
  struct Sampler;  ///< The march's per-sample constants and reads (volume_sampling.cpp)
  /// march(): Shaded reads each sample's gradient for shader (shading, gradient opacity; else nullptr).
  /// Scaled: stepScale != 0, each full step's alpha from the table's (scaledAlpha).
  template <bool Shaded, bool Scaled>
  void marchWith(const Ray& ray, double t0, double t1, bool emission, float stopBelow, VolumeMarch& acc,
                 const class VolumeShader* shader, int stepScale) const;
};

}  // namespace whitted
