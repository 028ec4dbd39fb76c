// All shapes: triangle meshes, sphere sets and tube sets, each with its container, ray intersection routine and
// shape class in its own file pair (shape_triangles, shape_spheres, shape_tubes; shared types in shape.h).
//
// All intersection routines work in double precision and take rays whose direction need not be normalised; t is
// the ray parameter. Each routine is exact at edges and vertices where the method allows (the triangle test is
// watertight) and re-centres far-away origins before solving quadratics, so a camera at 1e7 units does not lose
// the hit to cancellation.
#pragma once

#include "geometry/shape_tubes.h"
#include "geometry/shape_spheres.h"
#include "geometry/shape_triangles.h"
