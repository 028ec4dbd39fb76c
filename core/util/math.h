// Basic value types and numeric helpers shared by the whole core.
//
// Precision policy: world-space positions, ray origins and transforms are double precision, so a scene
// translated to 1e7 or scaled by 1e-6 keeps the relative precision VTK's double points carry. Colours,
// normals used only for shading, and BVH node bounds (rounded outward) are single precision.
#pragma once

#include <emmintrin.h>  // SSE2: part of every x86-64 CPU (Debian 12's baseline)
#include <glm/glm.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <limits>
#include <type_traits>

namespace whitted {

using Vec2 = glm::dvec2;
using Vec3 = glm::dvec3;
using Vec4 = glm::dvec4;
using Mat3 = glm::dmat3;
using Mat4 = glm::dmat4;
using Vec2f = glm::vec2;
using Vec3f = glm::vec3;
using Vec4f = glm::vec4;
using Color = glm::vec3;   ///< Linear RGB radiance / reflectance, single precision.
using Color4 = glm::vec4;  ///< Linear RGBA.

constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr double kPi = 3.14159265358979323846;

/// Largest component of a colour (used for contribution weights).
inline float maxComponent(const Color& c) {
  return std::max(c.x, std::max(c.y, c.z));
}

/// True when every component is finite.
inline bool isFinite(const Vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
inline bool isFinite(const Vec3f& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

/// gamma(n) of Higham / pbrt: bound on the relative error of n chained double-precision operations.
constexpr double gammaBound(int n) {
  constexpr double eps = std::numeric_limits<double>::epsilon() * 0.5;
  return (n * eps) / (1.0 - n * eps);
}

/// The next value toward +inf / -inf of a float or double (IEEE nextafter without the libm call: this runs per ray
/// in traversal setup and for every secondary ray's origin). NaN and the infinity in the direction of the step are
/// returned unchanged.
template <typename T>
inline T nextUp(T f) {
  static_assert(std::is_floating_point_v<T> && (sizeof(T) == 4 || sizeof(T) == 8));
  using Bits = std::conditional_t<sizeof(T) == 4, uint32_t, uint64_t>;
  if (!(f < std::numeric_limits<T>::infinity())) return f;  // NaN, +inf
  if (f == T(0)) return std::numeric_limits<T>::denorm_min();
  Bits u;
  std::memcpy(&u, &f, sizeof u);
  u = f > T(0) ? u + 1 : u - 1;
  std::memcpy(&f, &u, sizeof u);
  return f;
}
template <typename T>
inline T nextDown(T f) {
  return -nextUp(-f);
}
/// x rounded to the nearest float, returned as a double. Through SSE2 intrinsics on purpose: GCC 12's vectorizer
/// (at -O2, and at our -O3 in some loop shapes) folds double(float(x)) back to x in loops over glm vectors, so the
/// plain casts can silently not round at all (floatBelow/floatAbove stay conservative under that fold: they step).
inline double roundToFloat(double x) {
  const __m128d d = _mm_set_sd(x);
  return _mm_cvtsd_f64(_mm_cvtss_sd(d, _mm_cvtsd_ss(_mm_setzero_ps(), d)));
}
/// The largest float strictly below x / the smallest float strictly above x (conservative bounds of a double that
/// may itself carry one rounding: a float strictly below a double is at least one double ulp below it). Doubles
/// beyond float range give +-FLT_MAX or +-inf on the conservative side.
inline float floatBelow(double x) {
  const float f = static_cast<float>(x);
  return double(f) < x ? f : nextDown(f);
}
inline float floatAbove(double x) {
  const float f = static_cast<float>(x);
  return double(f) > x ? f : nextUp(f);
}

/// A ray: origin + t * dir for t in [tMin, tMax]. dir need not be normalised.
struct Ray {
  Vec3 origin{0.0};
  Vec3 dir{0.0, 0.0, 1.0};
  double tMin = 0.0;
  double tMax = kInfinity;
};

/// Axis-aligned box in double precision.
struct Bounds3 {
  Vec3 lo{kInfinity};
  Vec3 hi{-kInfinity};

  bool valid() const { return lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z; }
  void extend(const Vec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  void extend(const Bounds3& b) {
    lo = glm::min(lo, b.lo);
    hi = glm::max(hi, b.hi);
  }
  Vec3 center() const { return 0.5 * (lo + hi); }
  Vec3 extent() const { return hi - lo; }
  double halfArea() const {
    Vec3 d = glm::max(hi - lo, Vec3(0.0));
    return d.x * d.y + d.y * d.z + d.z * d.x;
  }
  double diagonal() const { return valid() ? glm::length(hi - lo) : 0.0; }
  /// Largest absolute coordinate (scale of floating-point error for points inside).
  double maxAbs() const {
    if (!valid()) return 0.0;
    Vec3 m = glm::max(glm::abs(lo), glm::abs(hi));
    return std::max(m.x, std::max(m.y, m.z));
  }
};

/// The region swept by the lines of a bundle of rays through a screen rectangle (a pinhole or parallel camera): four
/// side planes, each through one edge of the rectangle's rays. A point p is inside plane k when
/// dot(normal[k], p - point[k]) >= 0. Built by Camera::pixelBlockFrustum; valid false when it could not be (then
/// it excludes nothing).
struct Frustum {
  Vec3 point[4]{}, normal[4]{};
  bool valid = false;
  /// Whether box b lies wholly outside one of the planes by more than a margin of 1e-6 relative (the float
  /// rounding of the rays' directions is about 1e-16 relative): then no ray of the bundle can meet anything in b.
  /// Conservative: NaN or infinite values never exclude.
  bool excludes(const Bounds3& b) const {
    if (!valid) return false;
    for (int k = 0; k < 4; ++k) {
      const Vec3& n = normal[k];
      const Vec3 lo = b.lo - point[k], hi = b.hi - point[k];
      // The box corner farthest inside the plane
      const double far = (n.x > 0.0 ? n.x * hi.x : n.x * lo.x) + (n.y > 0.0 ? n.y * hi.y : n.y * lo.y) +
                         (n.z > 0.0 ? n.z * hi.z : n.z * lo.z);
      if (!(far < 0.0)) continue;  // (the margin only matters for a box outside: most boxes met are not)
      const Vec3 reach = glm::max(glm::abs(lo), glm::abs(hi));
      const double margin = 1e-6 * (std::abs(n.x) + std::abs(n.y) + std::abs(n.z)) *
                            std::max(reach.x, std::max(reach.y, reach.z));
      if (far < -margin) return true;
    }
    return false;
  }
};

/// v / |v|, or fallback when v is zero or not finite.
inline Vec3 safeNormalize(const Vec3& v, const Vec3& fallback) {
  double l = glm::length(v);
  return (l > 0.0 && std::isfinite(l)) ? v / l : fallback;
}

/// Transforms a point by an affine 4x4 matrix.
inline Vec3 transformPoint(const Mat4& m, const Vec3& p) {
  return Vec3(m * Vec4(p, 1.0));
}
/// Transforms a direction (no translation).
inline Vec3 transformVector(const Mat4& m, const Vec3& v) {
  return Mat3(m) * v;
}
/// Box of the 8 transformed corners.
Bounds3 transformBounds(const Mat4& m, const Bounds3& b);

/// Robust origin for a secondary ray leaving a surface (pbrt-v4 style, no scene-dependent epsilon).
/// p is the computed hit point, pError a per-axis bound on its absolute floating-point error, n the geometric
/// normal and w the new direction. The point is pushed along n by the error bound projected on |n|, to the side
/// w points to, then rounded away from the surface by one ulp per axis.
/// Performance note: inline, without libm's nextafter: it runs for every shadow, reflected and refracted ray.
inline Vec3 offsetRayOrigin(const Vec3& p, const Vec3& pError, const Vec3& n, const Vec3& w) {
  // Distance along the normal that is guaranteed to clear the error box around p
  const double d = glm::dot(glm::abs(n), pError);
  Vec3 offset = d * n;
  if (glm::dot(w, n) < 0.0) offset = -offset;
  Vec3 po = p + offset;
  // Round away from p so the addition's own rounding cannot bring the origin back inside the box
  for (int i = 0; i < 3; ++i) {
    if (offset[i] > 0.0)
      po[i] = nextUp(po[i]);
    else if (offset[i] < 0.0)
      po[i] = nextDown(po[i]);
  }
  return po;
}

/// Deterministic hash of up to four integers to a float in [0,1) (PCG-style mixing).
inline uint32_t hashU32(uint32_t a, uint32_t b = 0, uint32_t c = 0, uint32_t d = 0) {
  uint64_t h = 0x9E3779B97F4A7C15ull;
  for (uint32_t v : {a, b, c, d}) {
    h ^= v + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 31;
  }
  return static_cast<uint32_t>(h >> 32);
}
inline float hashFloat(uint32_t a, uint32_t b = 0, uint32_t c = 0, uint32_t d = 0) {
  return static_cast<float>(hashU32(a, b, c, d) >> 8) * (1.0f / 16777216.0f);
}

}  // namespace whitted
