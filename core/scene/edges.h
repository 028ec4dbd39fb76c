// Surface with edges: the distance, measured across the ray, from a hit point to the nearest drawn edge of the hit
// triangle. Compared with the pixel footprint at the hit (IntegratorSettings::pixelSize / pixelAngle) this draws
// edges of a given width in pixels, as VTK's wireframe over a surface, without a second primitive that could
// speckle against the surface (z-fighting): the edge is part of the surface's own hit.
#pragma once

#include "util/math.h"

#include <cstdint>

namespace whitted {

/// Distance from point p (on the triangle v0 v1 v2) to the nearest edge of the triangle whose bit is set in flags
/// (bit k: edge v_k -> v_(k+1)%3), measured in the plane perpendicular to the unit direction dir: every point is
/// projected along dir, as a camera ray's pixel sees it. Segments, not lines, so the distance near a vertex is the
/// distance to the vertex. Infinity when no bit is set. Units: those of the positions.
double edgeDistance(const Vec3 v[3], uint8_t flags, const Vec3& p, const Vec3& dir);

}  // namespace whitted
