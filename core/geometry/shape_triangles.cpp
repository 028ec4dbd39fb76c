#include "geometry/shape_triangles.h"

#include <algorithm>
#include <utility>

namespace whitted {

void triangle_detail::edgeFunctionsExtended(double ax, double ay, double bx, double by, double cx, double cy,
                                            double& u, double& v, double& w) {
  const long double lu = (long double)cx * by - (long double)cy * bx;
  const long double lv = (long double)ax * cy - (long double)ay * cx;
  const long double lw = (long double)bx * ay - (long double)by * ax;
  u = (double)lu;
  v = (double)lv;
  w = (double)lw;
}

std::optional<PrimHit> intersectTriangle(const Ray& ray, const TriangleRay& tr, const Vec3& p0, const Vec3& p1,
                                         const Vec3& p2) {
  PrimHit h;
  if (!intersectTriangle(ray.origin, ray.tMin, ray.tMax, tr, p0, p1, p2, h)) return std::nullopt;
  return h;
}

Vec3 triangleHitError(const Vec3& p0, const Vec3& p1, const Vec3& p2, double b0, double b1, double b2) {
  return gammaBound(7) * (glm::abs(b0 * p0) + glm::abs(b1 * p1) + glm::abs(b2 * p2));
}


bool TriangleShape::bounds(const TriangleMesh& m, uint32_t i, Bounds3& box) {
  const glm::uvec3& t = m.triangles[i];
  if (t.x >= m.positions.size() || t.y >= m.positions.size() || t.z >= m.positions.size()) return false;
  const Vec3 &a = m.positions[t.x], &b = m.positions[t.y], &c = m.positions[t.z];
  if (!isFinite(a) || !isFinite(b) || !isFinite(c)) return false;
  Vec3 n = glm::cross(b - a, c - a);
  if (!(glm::dot(n, n) > 0.0) || !isFinite(n)) return false;
  box = Bounds3();
  box.extend(a);
  box.extend(b);
  box.extend(c);
  return true;
}

std::size_t TriangleShape::bytes(const TriangleMesh& m) {
  return m.colorCoords.capacity() * sizeof(float) + m.positions.capacity() * sizeof(Vec3) +
         m.triangles.capacity() * sizeof(glm::uvec3) + m.normals.capacity() * sizeof(Vec3f) +
         m.vertexColors.capacity() * sizeof(Color4) + m.triangleColors.capacity() * sizeof(Color4) +
         m.texcoords.capacity() * sizeof(Vec2f);
}

void TriangleShape::surface(const TriangleMesh& m, const Hit& hit, const Ray&, const std::vector<Texture>& textures,
                            SurfacePoint& sp) {
  // The triangle sits at the hit's leaf slot (leaf order); per-triangle attributes use the original index
  const glm::uvec3& t = m.triangles[hit.slot];
  double b1 = hit.u, b2 = hit.v, b0 = 1.0 - b1 - b2;
  const Vec3 &p0 = m.positions[t.x], &p1 = m.positions[t.y], &p2 = m.positions[t.z];
  // Hit point from barycentrics (more accurate than o + t d) and its error bound
  sp.p = b0 * p0 + b1 * p1 + b2 * p2;
  sp.pError = triangleHitError(p0, p1, p2, b0, b1, b2);
  sp.ng = safeNormalize(glm::cross(p1 - p0, p2 - p0), Vec3(0, 0, 1));
  sp.ns = sp.ng;
  if (!m.normals.empty() && m.normals.size() == m.positions.size()) {
    Vec3 n = b0 * Vec3(m.normals[t.x]) + b1 * Vec3(m.normals[t.y]) + b2 * Vec3(m.normals[t.z]);
    sp.ns = safeNormalize(n, sp.ng);
  }
  // Colour: colour map, else triangle colour, else interpolated vertex colour
  if (m.colorMap >= 0 && size_t(m.colorMap) < textures.size() && m.colorCoords.size() == m.positions.size()) {
    float c = float(b0) * m.colorCoords[t.x] + float(b1) * m.colorCoords[t.y] + float(b2) * m.colorCoords[t.z];
    const Texture& lut = textures[size_t(m.colorMap)];
    int w = std::max(1, lut.width);
    int i = std::isfinite(c) ? std::clamp(int(std::floor(c * float(w))), 0, w - 1) : 0;
    sp.color = lut.sample((float(i) + 0.5f) / float(w), 0.5f / float(std::max(1, lut.height)));
    sp.hasColor = true;
  } else if (!m.triangleColors.empty() && hit.prim < m.triangleColors.size()) {
    sp.color = m.triangleColors[hit.prim];
    sp.hasColor = true;
  } else if (!m.vertexColors.empty() && m.vertexColors.size() == m.positions.size()) {
    sp.color = float(b0) * m.vertexColors[t.x] + float(b1) * m.vertexColors[t.y] + float(b2) * m.vertexColors[t.z];
    sp.hasColor = true;
  }
  if (!m.texcoords.empty() && m.texcoords.size() == m.positions.size()) {
    sp.uv = float(b0) * m.texcoords[t.x] + float(b1) * m.texcoords[t.y] + float(b2) * m.texcoords[t.z];
    sp.hasUV = true;
  }
}

}  // namespace whitted
