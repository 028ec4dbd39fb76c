/**
 * @class   vtkWhittedPolyDataConverter
 * @brief   internal: one vtkPolyData (as a mapper and property draw it) to tracer primitives
 *
 * Private to the Whitted module. Stateless; vtkWhittedSceneConverter decides when to call it
 * (caching) and places the result in the scene. The rules follow VTK 9.1's OpenGL mapper so that
 * the traced image matches VTK's own:
 *
 * - Polygons are split as a fan from their first point when convex (as the OpenGL mapper does, so
 *   interpolation matches) and by ear cutting when concave (which the OpenGL mapper draws wrongly);
 *   triangle strips alternate winding as OpenGL does. Cell ids follow VTK's order (verts, lines,
 * polys, strips) for cell colours and cell normals.
 * - Normals: point normals unless the interpolation is flat, else cell normals (each triangle gets
 * its own vertices), else none (the tracer uses facet normals turned toward the viewer, like VTK's
 * derivatives).
 * - Colours: the mapper's own MapScalars (scalar visibility, scalar mode, array, lookup table and
 * range, direct colours); point or cell colours decided by the scalar mode as the OpenGL mapper
 * does; with InterpolateScalarsBeforeMapping the mapper's colour texture and texture coordinates.
 * - Vertex cells become spheres, line cells tubes (capsules), of radius PointSize (LineWidth) times
 * the input's diagonal / 1000 (VTK's OSPRay pass makes the same choice). In points representation
 * every point used by a cell is a sphere; in wireframe representation every polygon / strip edge
 * (once) is a tube.
 */

#ifndef vtkWhittedPolyDataConverter_h
#define vtkWhittedPolyDataConverter_h

#include "vtkProperty.h" // for VTK_SURFACE

#include "material.h" // whitted::Texture
#include "shapes.h"   // whitted::TriangleMesh, SphereSet, CapsuleSet

#include <tuple> // for std::tuple

class vtkDataArray;
class vtkImageData;
class vtkMapper;
class vtkPolyData;
class vtkTexture;

class vtkWhittedPolyDataConverter
{
public:
  /// Settings of the actor that change the primitives (everything else only changes the material).
  struct Options
  {
    int Representation = VTK_SURFACE;
    bool Flat = false;    ///< Interpolation is VTK_FLAT: point normals are ignored.
    bool Spheres = false; ///< RenderPointsAsSpheres.
    bool Tubes = false;   ///< RenderLinesAsTubes.
    float PointSize = 1.0f;
    float LineWidth = 1.0f;
    bool TCoords = false; ///< The actor has a texture: keep the input's texture coordinates.

    auto Tie() const
    {
      return std::make_tuple(this->Representation, this->Flat, this->Spheres, this->Tubes,
        this->PointSize, this->LineWidth, this->TCoords);
    }
  };

  /// The primitives of one polydata, in the polydata's (object) coordinates.
  struct Primitives
  {
    whitted::TriangleMesh Mesh;
    whitted::SphereSet Spheres;
    whitted::CapsuleSet Capsules;
    bool ScalarColors = false;    ///< Primitives carry colours mapped from scalars.
    bool HasColorTexture = false; ///< InterpolateScalarsBeforeMapping: ColorTexture + texcoords.
    whitted::Texture ColorTexture;
    bool TCoords = false; ///< The triangles carry texture coordinates.
  };

  /**
   * Converts poly as mapper draws it with the given options. radiusScale turns PointSize and
   * LineWidth into world radii.
   */
  static void Convert(vtkPolyData* poly, vtkMapper* mapper, const Options& options,
    double radiusScale, Primitives& out);

  /**
   * RGBA8 texture from image scalars: unsigned char with 1 to 4 components directly (luminance,
   * luminance
   * + alpha, RGB, RGBA), anything else through the vtkTexture's lookup table (if texture is given).
   */
  static whitted::Texture ConvertImage(
    vtkImageData* image, vtkDataArray* scalars, vtkTexture* texture);
};

#endif
// VTK-HeaderTest-Exclude: vtkWhittedPolyDataConverter.h
