// Shading of volume samples (vtkVolumeProperty Shade and gradient opacity) for the march (volume_sampling.cpp):
// the per-ray constants, and a sample's lit colour and gradient-opacity factor from its central differences.
#pragma once

#include "geometry/volume.h"

namespace whitted {

/// What one march needs to shade samples: made once per ray segment.
class VolumeShader {
 public:
  /// emission false (a shadow ray's transmittance): gradient opacity only.
  VolumeShader(const Volume& v, const Ray& ray, const VolumeLighting& lighting, bool emission);
  /// The gradient-opacity factor of a sample's alpha (1 without gradient opacity); g holds the scalar's central
  /// differences along the grid's index axes, s(p + o e_a) - s(p - o e_a), taken as over two points (as VTK's GPU
  /// mapper takes them, whose offset o is n / (n - 1) points).
  float opacityFactor(const Vec3f& g) const;
  /// The colour c of the sample at world point x with central differences g, lit (transfer.shade; else c) and
  /// clamped to [0, 1]. A zero or non-finite gradient has no direction: ambient only.
  Color shade(const Vec3f& g, const Vec3& x, const Color& c) const;

 private:
  /// A light whose direction does not change along the ray (directional, or along the ray): its direction toward
  /// the light and its half vector with the view direction, set once per ray segment.
  struct Fixed {
    Vec3f toLight, half;
    Color radiance;
  };
  static constexpr std::size_t kFixed = 8;  ///< Lights set up per ray segment; others per sample.
  const TransferFunction& tf_;
  const VolumeLighting& lighting_;
  bool shade_, gradientOpacity_;
  glm::mat3 toWorldGradient_;///< Index-space differences -> world-space gradient direction (toIndex transposed).
  Vec3 dataScale_;         ///< Index-space differences -> gradient in the grid's axes times the mean spacing, x 2.
  double goScale_;         ///< Gradient magnitude -> index into tf.gradientOpacity.
  Vec3f toEye_;            ///< Unit vector back along the ray.
  Fixed fixed_[kFixed];
  std::size_t fixedCount_ = 0;
  /// Lights [0, fixedUpTo_) that are not positional (or all, along rays) are in fixed_; the others are lit per
  /// sample.
  std::size_t fixedUpTo_ = 0;
  bool allFixed_ = true;   ///< Every light is in fixed_.
};

}  // namespace whitted
