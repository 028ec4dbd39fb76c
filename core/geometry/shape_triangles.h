// Triangle meshes: the container, the watertight ray/triangle test, and the triangle shape (primitive bounds,
// leaf tester, surface data at a hit) the scene's traversal is templated on.
//
// Intersection routines work in double precision and take rays whose direction need not be normalised; t is the
// ray parameter.
#pragma once

#include "util/memory.h"
#include "geometry/shape.h"

namespace whitted {

/// Indexed triangle mesh in object space.
struct TriangleMesh {
  LargeVector<Vec3> positions;         ///< Vertex positions (object space, double; huge pages: memory.h).
  LargeVector<glm::uvec3> triangles;   ///< Vertex indices per triangle (huge pages: memory.h).
  std::vector<Vec3f> normals;          ///< Optional per-vertex normals (empty = use facet normals).
  std::vector<Color4> vertexColors;    ///< Optional per-vertex RGBA in [0,1].
  std::vector<Color4> triangleColors;  ///< Optional per-triangle RGBA in [0,1] (wins over vertexColors).
  std::vector<Vec2f> texcoords;        ///< Optional per-vertex texture coordinates.
  /// Optional per-vertex colour-map coordinate in [0,1] (VTK's InterpolateScalarsBeforeMapping): interpolated,
  /// then looked up in Scene texture colorMap (nearest, clamped, row 0) as the geometry colour, before lighting.
  std::vector<float> colorCoords;
  int32_t colorMap = -1;
  /// Optional per-triangle (original index) mask of the edges that are polygon edges, drawn when the material has
  /// edges (Material::edgeWidth): bit k = the edge from vertex k to vertex (k+1) % 3. Empty (or of another size)
  /// = all three. A triangulated polygon marks its boundary edges only, as VTK draws them.
  std::vector<uint8_t> edgeFlags;
};

/// Per-ray constants of the watertight triangle test (axis permutation and shear), computed once per ray.
struct TriangleRay {
  int kx = 0, ky = 1, kz = 2;
  double sx = 0.0, sy = 0.0, sz = 0.0;
  bool valid = false;  ///< false for a zero or non-finite direction (then nothing is hit)
  explicit TriangleRay(const Ray& ray) {
    // Permute axes so the ray direction's largest component is z (on ties y over x, z over both), keeping the
    // winding: (kx, ky) = the two following axes, swapped for a negative dz
    const double ax = std::abs(ray.dir.x), ay = std::abs(ray.dir.y), az = std::abs(ray.dir.z);
    static constexpr int kNext[3][2] = {{1, 2}, {2, 0}, {0, 1}};
    kz = (ax > ay) ? (ax > az ? 0 : 2) : (ay > az ? 1 : 2);
    const double* d = &ray.dir.x;
    const double dz = d[kz];
    const bool flip = dz < 0.0;
    kx = kNext[kz][flip];
    ky = kNext[kz][!flip];
    valid = dz != 0.0 && isFinite(ray.dir);
    if (!valid) return;
    sx = d[kx] / dz;
    sy = d[ky] / dz;
    sz = 1.0 / dz;
  }
};

namespace triangle_detail {
/// Re-evaluates the edge functions in extended precision when one is exactly zero, so the sign decision on an edge
/// or vertex is consistent between the triangles sharing it (rare: out of line).
[[gnu::noinline, gnu::cold]] void edgeFunctionsExtended(double ax, double ay, double bx, double by, double cx,
                                                        double cy, double& u, double& v, double& w);
}  // namespace triangle_detail

/// The watertight test on a ray given by its origin and range (tMin, tMax): true and hit set on a hit. Inline, for
/// the traversal's leaf loops (no call, no Ray copy per triangle); the optional-returning form below calls it.
inline bool intersectTriangle(const Vec3& origin, double tMin, double tMax, const TriangleRay& tr, const Vec3& p0,
                              const Vec3& p1, const Vec3& p2, PrimHit& hit) {
  if (!tr.valid) return false;
  const int kx = tr.kx, ky = tr.ky, kz = tr.kz;
  const double sx = tr.sx, sy = tr.sy, sz = tr.sz;

  // Translate vertices to the ray origin and shear so the ray becomes the +z axis. The permuted coordinates are
  // loaded by index (a runtime index into a Vec3 temporary compiles to compare-and-branch chains per use)
  static_assert(sizeof(Vec3) == 3 * sizeof(double), "x, y, z contiguous");
  const double *o = &origin.x, *q0 = &p0.x, *q1 = &p1.x, *q2 = &p2.x;
  const double oX = o[kx], oY = o[ky], oZ = o[kz];
  const double aZ = q0[kz] - oZ, bZ = q1[kz] - oZ, cZ = q2[kz] - oZ;
  double ax = (q0[kx] - oX) - sx * aZ, ay = (q0[ky] - oY) - sy * aZ;
  double bx = (q1[kx] - oX) - sx * bZ, by = (q1[ky] - oY) - sy * bZ;
  double cx = (q2[kx] - oX) - sx * cZ, cy = (q2[ky] - oY) - sy * cZ;

  // Scaled barycentrics (edge functions)
  double u = cx * by - cy * bx;
  double v = ax * cy - ay * cx;
  double w = bx * ay - by * ax;
  if (u == 0.0 || v == 0.0 || w == 0.0) triangle_detail::edgeFunctionsExtended(ax, ay, bx, by, cx, cy, u, v, w);
  if ((u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0)) return false;
  double det = u + v + w;
  if (det == 0.0 || !std::isfinite(det)) return false;

  // Scaled hit distance and range test without division
  double az = sz * aZ, bz = sz * bZ, cz = sz * cZ;
  double tScaled = u * az + v * bz + w * cz;
  double invDet = 1.0 / det;
  double t = tScaled * invDet;
  if (!(t > tMin && t < tMax)) return false;

  // Reject t that is not conservatively positive given its rounding error (pbrt-v4, section 6.8.7): a ray
  // leaving a surface can then never re-hit that surface near t = 0, whatever the scene's scale
  double maxZt = std::max(std::abs(az), std::max(std::abs(bz), std::abs(cz)));
  double maxXt = std::max(std::abs(ax), std::max(std::abs(bx), std::abs(cx)));
  double maxYt = std::max(std::abs(ay), std::max(std::abs(by), std::abs(cy)));
  double deltaZ = gammaBound(3) * maxZt;
  double deltaX = gammaBound(5) * (maxXt + maxZt);
  double deltaY = gammaBound(5) * (maxYt + maxZt);
  double deltaE = 2.0 * (gammaBound(2) * maxXt * maxYt + deltaY * maxXt + deltaX * maxYt);
  double maxE = std::max(std::abs(u), std::max(std::abs(v), std::abs(w)));
  double deltaT = 3.0 * (gammaBound(3) * maxE * maxZt + deltaE * maxZt + deltaZ * maxE) * std::abs(invDet);
  if (t <= deltaT) return false;
  // An edge function exactly zero: the ray meets an edge or vertex, which the neighbouring triangle accepts too
  hit = PrimHit{t, v * invDet, w * invDet, deltaT, u == 0.0 || v == 0.0 || w == 0.0};
  return true;
}

/// Watertight ray/triangle test (Woop, Benthin, Wald 2013). Returns a hit with t in (tMin, tMax). Exact at edges
/// and vertices: a ray through a shared edge hits at least one of the two triangles.
/// Performance note: pass the precomputed TriangleRay when testing many triangles against one ray.
std::optional<PrimHit> intersectTriangle(const Ray& ray, const TriangleRay& tr, const Vec3& p0, const Vec3& p1,
                                         const Vec3& p2);
inline std::optional<PrimHit> intersectTriangle(const Ray& ray, const Vec3& p0, const Vec3& p1, const Vec3& p2) {
  return intersectTriangle(ray, TriangleRay(ray), p0, p1, p2);
}

/// Per-axis bound on the absolute error of the point b0*p0 + b1*p1 + b2*p2 (pbrt-v4, section 6.8).
Vec3 triangleHitError(const Vec3& p0, const Vec3& p1, const Vec3& p2, double b0, double b1, double b2);

/// The triangle shape. The scene stores a committed mesh's triangles in BVH leaf order (LeafOrdered), so leaf
/// tests read consecutive memory; every other array stays indexed by the original vertex or triangle index.
struct TriangleShape {
  using Geometry = TriangleMesh;
  static constexpr GeometryType kType = GeometryType::Triangles;
  /// Stored in BVH leaf order once committed (leafOrdered() is the permuted array).
  static constexpr bool kLeafOrdered = true;
  static constexpr bool kCrossedOnce = true;  ///< A ray crosses a triangle at most once.
  /// The per-primitive array kept in BVH leaf order.
  static LargeVector<glm::uvec3>& leafOrdered(TriangleMesh& m) { return m.triangles; }
  static const LargeVector<glm::uvec3>& leafOrdered(const TriangleMesh& m) { return m.triangles; }

  /// Number of primitives, valid or not.
  static std::size_t count(const TriangleMesh& m) { return m.triangles.size(); }
  /// Box of triangle i; false if it cannot be hit (vertex index out of range, non-finite or degenerate).
  static bool bounds(const TriangleMesh& m, uint32_t i, Bounds3& box);
  /// True if a and b have bit-identical geometry apart from the leaf-ordered triangles (the caller compares those
  /// through the leaf order).
  static bool sameGeometry(const TriangleMesh& a, const TriangleMesh& b) { return sameBits(a.positions, b.positions); }
  /// Clamps the colours to [0,1] (see sanitizeColors).
  static void sanitize(TriangleMesh& m) {
    sanitizeColors(m.vertexColors);
    sanitizeColors(m.triangleColors);
  }
  /// Memory of the geometry arrays, bytes (allocated capacity).
  static std::size_t bytes(const TriangleMesh& m);

  /// Leaf tests of one object visit: slot indexes the leaf-ordered triangles.
  class Tester {
   public:
    Tester(const TriangleMesh& m, const uint32_t* /*leafPrims*/, const Ray& ray)
        : positions_(m.positions.data()), triangles_(m.triangles.data()), tr_(ray) {}
    std::optional<PrimHit> operator()(uint32_t slot, const Ray& r) const {
      const glm::uvec3& t = triangles_[slot];
      return intersectTriangle(r, tr_, positions_[t.x], positions_[t.y], positions_[t.z]);
    }
    /// The test of slot on r limited to tMax: true and h set on a hit (inline; the traversal's leaf loops).
    bool hit(uint32_t slot, const Ray& r, double tMax, PrimHit& h) const {
      const glm::uvec3& t = triangles_[slot];
      return intersectTriangle(r.origin, r.tMin, tMax, tr_, positions_[t.x], positions_[t.y], positions_[t.z], h);
    }

   private:
    const Vec3* positions_;
    const glm::uvec3* triangles_;
    TriangleRay tr_;
  };

  /// Object-space surface data of hit (found along objectRay): point and error bound, normals, colour (colour map,
  /// triangle colour or interpolated vertex colour, in that order) and texture coordinates.
  static void surface(const TriangleMesh& m, const Hit& hit, const Ray& objectRay, const std::vector<Texture>& textures,
                      SurfacePoint& sp);
};

}  // namespace whitted
