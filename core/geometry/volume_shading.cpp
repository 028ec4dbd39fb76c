// Shading of volume samples (VolumeShader): VTK's GPU mapper's lighting of a sample by the direction of the scalar's
// gradient, and gradient opacity.
#include "geometry/volume_shading.h"

#include <algorithm>
#include <cmath>

namespace whitted {

VolumeShader::VolumeShader(const Volume& v, const Ray& ray, const VolumeLighting& lighting, bool emission)
    : tf_(v.transfer),
      lighting_(lighting),
      shade_(v.transfer.shade && emission),
      gradientOpacity_(!v.transfer.gradientOpacity.empty() && v.transfer.gradientOpacityMax > 0.0) {
  // A world vector w has index coordinates toIndex w, so the scalar's world gradient is toIndex^T times its
  // index-space gradient (single precision: only its direction is used, for 8-bit colours)
  toWorldGradient_ = glm::mat3(glm::transpose(v.toIndex()));
  // In the grid's own axes (direction matrix left out: a rotation keeps the magnitude) a difference over two
  // points is (s+ - s-) / (2 spacing); times the mean spacing
  const Vec3& sp = v.grid.spacing;
  const double mean = (std::abs(sp.x) + std::abs(sp.y) + std::abs(sp.z)) / 3.0;
  dataScale_ = Vec3(mean / (2.0 * std::abs(sp.x)), mean / (2.0 * std::abs(sp.y)), mean / (2.0 * std::abs(sp.z)));
  goScale_ = gradientOpacity_ ? double(v.transfer.gradientOpacity.size() - 1) / v.transfer.gradientOpacityMax : 0.0;
  const double len = glm::length(ray.dir);
  toEye_ = len > 0.0 ? Vec3f(-ray.dir / len) : Vec3f(0.0f);
  // Lights whose direction is the same all along the ray: direction and half vector once here
  for (std::size_t k = 0; shade_ && lighting.lights && k < lighting.count; ++k) {
    const VolumeLight& l = lighting.lights[k];
    if (fixedCount_ == kFixed) {  // full: this light and the rest per sample
      allFixed_ = false;
      break;
    }
    fixedUpTo_ = k + 1;
    if (l.positional && !lighting.alongRays) {
      allFixed_ = false;
      continue;
    }
    Fixed& f = fixed_[fixedCount_++];
    f.toLight = lighting.alongRays ? toEye_ : Vec3f(l.toLight);
    const Vec3f h = f.toLight + toEye_;
    const float hl = glm::length(h);
    f.half = hl > 0.0f ? h / hl : Vec3f(0.0f);
    f.radiance = l.radiance;
  }
}

float VolumeShader::opacityFactor(const Vec3f& g) const {
  if (!gradientOpacity_) return 1.0f;
  // The function's table, interpolated linearly and clamped (VTK's 1D texture); a NaN magnitude: its first value
  const double m = glm::length(Vec3(g) * dataScale_) * goScale_;
  const std::vector<float>& t = tf_.gradientOpacity;
  const double last = double(t.size() - 1);
  const double u = m > 0.0 ? std::min(m, last) : 0.0;
  const std::size_t i = std::min(std::size_t(u), t.size() - 1);
  const std::size_t j = std::min(i + 1, t.size() - 1);
  return float(double(t[i]) + (u - double(i)) * (double(t[j]) - double(t[i])));
}

Color VolumeShader::shade(const Vec3f& g, const Vec3& x, const Color& c) const {
  if (!shade_) return c;
  Color diffuse(0.0f), specular(0.0f);
  const Vec3f gw = toWorldGradient_ * g;
  const float len = glm::length(gw);
  const bool highlight = tf_.specular > 0.0f;
  if (len > 0.0f && std::isfinite(len)) {
    const Vec3f n = gw / len;
    // Two-sided (VTK's renderer default): the gradient's sign does not matter
    for (std::size_t k = 0; k < fixedCount_; ++k) {
      const Fixed& f = fixed_[k];
      diffuse += std::abs(glm::dot(n, f.toLight)) * f.radiance;
      if (highlight) specular += std::pow(std::abs(glm::dot(n, f.half)), tf_.specularPower) * f.radiance;
    }
    for (std::size_t k = 0; !allFixed_ && k < lighting_.count; ++k) {
      const VolumeLight& l = lighting_.lights[k];
      const bool direction = !l.positional || lighting_.alongRays;
      if (direction && k < fixedUpTo_) continue;  // (in fixed_)
      Vec3f lf = lighting_.alongRays ? toEye_ : Vec3f(l.toLight);
      double att = 1.0;
      if (!direction) {
        // VTK's attenuation 1 / (a0 + a1 d + a2 d^2) and spot cone
        const Vec3 d = l.position - x;
        const double dist = glm::length(d);
        if (!(dist > 0.0)) continue;
        const Vec3 toLight = d / dist;
        const double a = l.attenuation.x + dist * (l.attenuation.y + dist * l.attenuation.z);
        att = a > 0.0 ? 1.0 / a : 1.0;
        if (l.cosCone > -1.0) {
          const double cd = -glm::dot(toLight, l.axis);
          att = cd >= l.cosCone ? att * std::pow(cd, l.exponent) : 0.0;
        }
        if (!(att > 0.0)) continue;
        lf = Vec3f(toLight);
      }
      diffuse += float(att) * std::abs(glm::dot(n, lf)) * l.radiance;
      const Vec3f h = lf + toEye_;
      const float hl = glm::length(h);
      if (highlight && hl > 0.0f)
        specular += float(att) * std::pow(std::abs(glm::dot(n, h)) / hl, tf_.specularPower) * l.radiance;
    }
  }
  // The ambient term: ka C for a lone headlight, ka x the lights' ambient colours otherwise (VTK 9.1's two cases;
  // the second does not multiply it by the sample's colour)
  const Color ambient = lighting_.alongRays ? tf_.ambient * lighting_.ambient * c : tf_.ambient * lighting_.ambient;
  const Color lit = ambient + tf_.diffuse * diffuse * c + tf_.specular * specular;
  return glm::clamp(lit, Color(0.0f), Color(1.0f));
}

}  // namespace whitted
