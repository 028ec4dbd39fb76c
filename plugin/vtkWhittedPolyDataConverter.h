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
 * does; with InterpolateScalarsBeforeMapping the mapper's colour texture and colour-map
 * coordinates.
 * - Vertex cells become spheres, line cells tubes (tubes), of radius PointSize (LineWidth) times
 * the input's diagonal / 1000 (VTK's OSPRay pass makes the same choice), or per point from a
 * radius array (Options::RadiusArray: vtkWhittedMaterialKeys::RADIUS_ARRAY,
 * vtkPointGaussianMapper). In points representation every point used by a cell is a sphere; in
 * wireframe representation every polygon / strip edge (once) is a tube.
 * - Bad input never reaches the tracer unchecked: cells with point ids out of range and malformed
 * cell arrays are skipped, attribute arrays shorter than the points (cells) they describe are
 * ignored, spheres / tubes without a positive radius are left out; non-finite points, normals and
 * colours are left to the core, which skips or sanitises them. Everything found is counted in
 * Primitives::Issues.
 *
 * The implementation is split by primitive (vtkWhittedPolyDataTriangles.cxx,
 * vtkWhittedPolyDataSpheres.cxx, vtkWhittedPolyDataTubes.cxx) and colours
 * (vtkWhittedPolyDataColors.cxx), which share vtkWhittedPolyDataPrimitives.h.
 */

#ifndef vtkWhittedPolyDataConverter_h
#define vtkWhittedPolyDataConverter_h

#include "vtkProperty.h" // for VTK_SURFACE
#include "vtkType.h"     // for vtkIdType

#include "geometry/texture.h" // whitted::Texture
#include "geometry/shapes.h"   // whitted::TriangleMesh, SphereSet, TubeSet

#include <functional> // for std::function
#include <string>     // for std::string
#include <tuple>      // for std::tuple

class vtkDataArray;
class vtkImageData;
class vtkMapper;
class vtkPiecewiseFunction;
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
    /// Per-point radii of spheres and tubes: the point array of this name (its only component, or
    /// its magnitude), through RadiusFunction when set (clamped to its range), times
    /// RadiusFactor, in data units. Empty: PointSize / LineWidth radii. A tube takes the mean of
    /// its two end points' radii.
    std::string RadiusArray;
    vtkPiecewiseFunction* RadiusFunction = nullptr;
    double RadiusFactor = 1.0;
    /// vtkPointGaussianMapper (ScaleFactor not 0): every splat (the vertices of vertex cells, or
    /// every point when there are none) a sphere of radius ScaleFunction(ScaleArray value, or 1)
    /// x ScaleFactor (RadiusArray, RadiusFunction, RadiusFactor, the component below); its
    /// OpacityArray through ScalarOpacityFunction sets the alpha of mapped colours.
    bool Gaussian = false;
    int RadiusComponent = -1; ///< Component of RadiusArray for Gaussian splats (-1: magnitude).
    std::string OpacityArray;
    int OpacityComponent = -1;
    vtkPiecewiseFunction* OpacityFunction = nullptr;
    /// Latest MTime of the functions above, so that editing one converts again.
    vtkMTimeType FunctionsTime = 0;

    auto Tie() const
    {
      return std::make_tuple(this->Representation, this->Flat, this->Spheres, this->Tubes,
        this->PointSize, this->LineWidth, this->TCoords, this->RadiusArray, this->RadiusFunction,
        this->RadiusFactor, this->Gaussian, this->RadiusComponent, this->OpacityArray,
        this->OpacityComponent, this->OpacityFunction, this->FunctionsTime);
    }
  };

  /// What was wrong with the input and left out (the scene converter warns once per actor).
  struct Problems
  {
    /// Points with a NaN or infinite coordinate (the core skips the cells using them).
    vtkIdType NonFinitePoints = 0;
    /// Cells using point ids outside [0, number of points): skipped.
    vtkIdType InvalidCells = 0;
    /// Cell arrays whose offsets do not fit their connectivity: skipped.
    int MalformedCellArrays = 0;
    /// NaN, infinite or zero-length normals (the core uses the facet normal there).
    vtkIdType BadNormals = 0;
    /// A normals array with fewer tuples than points (cells) or not 3 components: ignored.
    bool ShortNormals = false;
    /// Colours mapped from an array shorter than the points (cells) they colour: ignored.
    bool ShortScalars = false;
    /// Scalars used directly as colours from a char array or without 1 to 4 components: ignored.
    bool UnusableColors = false;
    /// Texture coordinates with fewer tuples than points or more than 3 components: ignored.
    bool ShortTCoords = false;
    /// Spheres wanted but PointSize gives no positive finite radius: left out.
    bool NoSphereRadius = false;
    /// Tubes wanted but LineWidth gives no positive finite radius: left out.
    bool NoTubeRadius = false;
    /// Number of points of the input (for the messages).
    vtkIdType NumberOfPoints = 0;
  };

  /// The primitives of one polydata, in the polydata's (object) coordinates.
  struct Primitives
  {
    whitted::TriangleMesh Mesh;
    whitted::SphereSet Spheres;
    whitted::TubeSet Tubes;
    bool ScalarColors = false; ///< Primitives carry colours mapped from scalars.
    /// InterpolateScalarsBeforeMapping: ColorTexture is the mapper's colour map and the triangles
    /// carry coordinates into it (Mesh.colorCoords; Mesh.colorMap is set when it is stored).
    bool HasColorTexture = false;
    whitted::Texture ColorTexture;
    bool TCoords = false; ///< The triangles carry texture coordinates (for the actor's texture).
    Problems Issues;      ///< Bad input found (and left out) while converting.
    /// Positions, centres and end points are relative to this point of the polydata's coordinates
    /// (place the objects with a translation by Origin). Zero unless the data lies far from its
    /// coordinate origin compared to its size (e.g. a model translated by 1e7): the tracer's BVH
    /// bounds are single precision, and would lose their tightness there.
    whitted::Vec3 Origin{ 0.0 };
  };

  /**
   * Converts poly as mapper draws it with the given options. radiusScale turns PointSize and
   * LineWidth into world radii; called only when spheres or tubes come out (it reads every point).
   */
  static void Convert(vtkPolyData* poly, vtkMapper* mapper, const Options& options,
    const std::function<double()>& radiusScale, Primitives& out);

  /**
   * RGBA8 texture from image scalars: unsigned char with 1 to 4 components directly (luminance,
   * luminance
   * + alpha, RGB, RGBA), anything else through the vtkTexture's lookup table (if texture is given).
   */
  static whitted::Texture ConvertImage(
    vtkImageData* image, vtkDataArray* scalars, vtkTexture* texture);

private:
  static void ConvertPrimitives(vtkPolyData* poly, vtkMapper* mapper, const Options& options,
    const std::function<double()>& radiusScale, Primitives& out);
  // Moves the primitives' coordinates to Primitives::Origin when the data lies far from its origin.
  static void Recentre(Primitives& out);
};

#endif
// VTK-HeaderTest-Exclude: vtkWhittedPolyDataConverter.h
