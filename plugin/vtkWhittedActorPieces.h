/**
 * @file    vtkWhittedActorPieces.h
 * @brief   internal: the polydata an actor draws, and the two rules read from them
 *
 * Private to the Whitted module. An actor's input as polydata pieces: its polydata, the outer
 * surface of another dataset (vtkDataSetMapper), or the visible blocks of a composite input with
 * their display-attribute overrides (vtkCompositePolyDataMapper2). The pieces decide whether the
 * tracer draws the actor at all (plain points and lines are left to OpenGL) and the size of its
 * spheres and tubes. Used for ordinary actors (vtkWhittedSceneConverter) and for glyph sources
 * (vtkWhittedGlyphConverter: each source one piece).
 *
 * @sa vtkWhittedSceneConverter vtkWhittedGeometryCache
 */

#ifndef vtkWhittedActorPieces_h
#define vtkWhittedActorPieces_h

#include "vtkWhittedMaterials.h" // for vtkWhittedMaterials::BlockAttributes

#include <vector> // for std::vector

class vtkActor;
class vtkMapper;
class vtkPolyData;
class vtkProperty;
class vtkWhittedGeometryCache;

namespace vtkWhittedActorPieces
{
/// A piece of an actor: its polydata, or one visible block of a composite input with its
/// display-attribute overrides.
struct Piece
{
  vtkPolyData* Poly = nullptr;
  vtkWhittedMaterials::BlockAttributes Block;
};

/**
 * The pieces actor draws, after the same update as vtkPolyDataMapper::Render /
 * vtkDataSetMapper::Render (the surface of a non-polydata input comes from geometries); false if it
 * has no input to draw.
 */
bool Collect(vtkActor* actor, vtkWhittedGeometryCache& geometries, std::vector<Piece>& pieces);

/**
 * True if pieces, drawn with property p (and mapper, if given), have only vertices or only lines
 * and no surface, in surface representation, without RenderPointsAsSpheres /
 * RenderLinesAsTubes: OpenGL draws those as plain points / lines. Point Gaussian splats are
 * spheres.
 */
bool OnlyPlainPointsOrLines(
  const std::vector<Piece>& pieces, vtkProperty* p, vtkMapper* mapper = nullptr);

/**
 * The factor from PointSize / LineWidth to sphere and tube radii, as VTK's OSPRay pass chooses
 * it: the diagonal of the finite points of all pieces / 1000 (1 / 1000 when there is no finite
 * diagonal).
 */
double RadiusScale(const std::vector<Piece>& pieces);
}

#endif
// VTK-HeaderTest-Exclude: vtkWhittedActorPieces.h
