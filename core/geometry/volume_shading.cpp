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
  active_ = shade_ || gradientOpacity_;
  // A world vector w has index coordinates toIndex w, so the scalar's world gradient is toIndex^T times its
  // index-space gradient
  toWorldGradient_ = glm::transpose(v.toIndex());
  // In the grid's own axes (direction matrix left out: a rotation keeps the magnitude) a difference over two
  // points is (s+ - s-) / (2 spacing); times the mean spacing
  const Vec3& sp = v.grid.spacing;
  const double mean = (std::abs(sp.x) + std::abs(sp.y) + std::abs(sp.z)) / 3.0;
  dataScale_ = Vec3(mean / (2.0 * std::abs(sp.x)), mean / (2.0 * std::abs(sp.y)), mean / (2.0 * std::abs(sp.z)));
  goScale_ = gradientOpacity_ ? double(v.transfer.gradientOpacity.size() - 1) / v.transfer.gradientOpacityMax : 0.0;
  const double len = glm::length(ray.dir);
  toEye_ = len > 0.0 ? -ray.dir / len : Vec3(0.0);
}

float VolumeShader::opacityFactor(const Vec3f& g) const {
  if (!gradientOpacity_) return 1.0f;
  const Vec3 gi(g);
  {
    // The function's table, interpolated linearly and clamped (VTK's 1D texture); a NaN magnitude: its first value
    const double m = glm::length(gi * dataScale_) * goScale_;
    const std::vector<float>& t = tf_.gradientOpacity;
    const double last = double(t.size() - 1);
    const double u = m > 0.0 ? std::min(m, last) : 0.0;
    const std::size_t i = std::min(std::size_t(u), t.size() - 1);
    const std::size_t j = std::min(i + 1, t.size() - 1);
    return float(double(t[i]) + (u - double(i)) * (double(t[j]) - double(t[i])));
  }
}

Color VolumeShader::shade(const Vec3f& g, const Vec3& x, const Color& c) const {
  if (!shade_) return c;
  const Vec3 gi(g);
  Color diffuse(0.0f), specular(0.0f);
  const Vec3 gw = toWorldGradient_ * gi;
  const double len = glm::length(gw);
  if (len > 0.0 && std::isfinite(len)) {
    const Vec3 n = gw / len;
    for (std::size_t k = 0; lighting_.lights && k < lighting_.count; ++k) {
      const VolumeLight& l = lighting_.lights[k];
      Vec3 toLight = lighting_.alongRays ? toEye_ : l.toLight;
      double att = 1.0;
      if (l.positional && !lighting_.alongRays) {
        // VTK's attenuation 1 / (a0 + a1 d + a2 d^2) and spot cone
        const Vec3 d = l.position - x;
        const double dist = glm::length(d);
        if (!(dist > 0.0)) continue;
        toLight = d / dist;
        const double a = l.attenuation.x + dist * (l.attenuation.y + dist * l.attenuation.z);
        att = a > 0.0 ? 1.0 / a : 1.0;
        if (l.cosCone > -1.0) {
          const double cd = -glm::dot(toLight, l.axis);
          att = cd >= l.cosCone ? att * std::pow(cd, l.exponent) : 0.0;
        }
        if (!(att > 0.0)) continue;
      }
      // Two-sided (VTK's renderer default): the gradient's sign does not matter
      const double nl = std::abs(glm::dot(n, toLight));
      diffuse += float(att * nl) * l.radiance;
      const Vec3 h = toLight + toEye_;
      const double hl = glm::length(h);
      if (hl > 0.0) {
        const double nh = std::abs(glm::dot(n, h)) / hl;
        specular += float(att * std::pow(nh, double(tf_.specularPower))) * l.radiance;
      }
    }
  }
  const Color lit = tf_.ambient * lighting_.ambient * c + tf_.diffuse * diffuse * c + tf_.specular * specular;
  return glm::clamp(lit, Color(0.0f), Color(1.0f));
}

}  // namespace whitted
