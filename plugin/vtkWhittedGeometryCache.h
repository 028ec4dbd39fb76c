/**
 * @class   vtkWhittedGeometryCache
 * @brief   internal: converted geometry per (mapper, input or block, options), kept across frames
 *
 * Private to the Whitted module. A geometry is what one mapper draws from one polydata (its input,
 * or one block of a composite input) with one set of geometry-relevant property settings
 * (vtkWhittedPolyDataConverter::Options). It is converted by vtkWhittedPolyDataConverter only when
 * the mapper, its lookup table or the data changed (MTime), and stored as up to one scene object
 * per primitive kind (triangles, spheres, tubes). Actors sharing a mapper share its objects
 * (instancing).
 *
 * - A conversion that changes only attributes (colours after a lookup-table edit) updates the
 *   existing objects in place, which keeps their BVHs.
 * - The colour map of InterpolateScalarsBeforeMapping is stored through the texture cache and
 *   replaced in place when it changes; the mesh looks it up by its colour-map coordinates.
 * - Objects of geometries no frame used since BeginFrame() are freed by FreeUnused(), and their ids
 *   reused by later geometries.
 * - vtkDataSetMapper inputs that are not polydata go through a vtkDataSetSurfaceFilter kept per
 *   mapper (GetSurface), as that mapper does itself.
 *
 * @sa vtkWhittedSceneConverter vtkWhittedPolyDataConverter vtkWhittedTextureCache
 */

#ifndef vtkWhittedGeometryCache_h
#define vtkWhittedGeometryCache_h

#include "vtkSmartPointer.h"             // for vtkSmartPointer
#include "vtkWhittedPolyDataConverter.h" // for Options, Problems

#include <functional> // for std::function
#include <map>        // for std::map
#include <vector>     // for std::vector

class vtkDataObject;
class vtkDataSet;
class vtkDataSetSurfaceFilter;
class vtkMapper;
class vtkPolyData;
class vtkWhittedTextureCache;

namespace whitted
{
class Scene;
}

class vtkWhittedGeometryCache
{
public:
  /// Primitive kinds; a geometry holds up to one scene object of each.
  enum Kind
  {
    Triangles = 0,
    Spheres = 1,
    Tubes = 2,
    NumberOfKinds = 3
  };

  /// The converted form of one geometry.
  struct Geometry
  {
    int Objects[NumberOfKinds] = { -1, -1, -1 }; ///< Scene object per kind, -1 if none.
    bool ScalarColors = false; ///< The primitives carry colours mapped from scalars.
    /// InterpolateScalarsBeforeMapping: scene texture of the colour map, -1 if none.
    int ColorTexture = -1;
    bool ColorCoords = false; ///< The triangles carry coordinates into ColorTexture.
    bool TCoords = false;     ///< The triangles carry texture coordinates (for the actor texture).
    vtkWhittedPolyDataConverter::Problems Issues; ///< Bad input left out.
    whitted::Vec3 Origin{ 0.0 }; ///< The objects' coordinates are relative to this point.

    vtkMTimeType Stamp = 0;
    unsigned long LastFrame = 0;
  };

  vtkWhittedGeometryCache(whitted::Scene& scene, vtkWhittedTextureCache& textures);

  /// Starts a frame: what is not used from here to FreeUnused() is freed then.
  void BeginFrame() { ++this->Frame; }

  /**
   * The geometry mapper draws from poly with options, converted again if anything it depends on
   * changed (then converted is incremented). radiusScale (called only when converting) turns
   * PointSize and LineWidth into object-space radii.
   */
  const Geometry& Get(vtkMapper* mapper, vtkPolyData* poly,
    const vtkWhittedPolyDataConverter::Options& options, const std::function<double()>& radiusScale,
    int& converted);

  /// The outer surface of a dataset drawn by a vtkDataSetMapper (a filter kept per mapper).
  vtkPolyData* GetSurface(vtkMapper* mapper, vtkDataSet* dataset);

  /// Frees the objects, colour maps and surface filters not used since BeginFrame().
  void FreeUnused();

  /// Forgets everything (after the scene was replaced).
  void Clear();

private:
  struct Key
  {
    vtkMapper* Mapper;
    vtkDataObject* Data;
    vtkWhittedPolyDataConverter::Options Options;
    bool operator<(const Key& o) const;
  };
  struct Surface
  {
    vtkSmartPointer<vtkDataSetSurfaceFilter> Filter;
    unsigned long LastFrame = 0;
  };

  // Stores primitives of one kind in the geometry's existing object (in place: its BVH is kept
  // when only attributes changed), a freed one, or a new one; returns the object id.
  uint32_t StoreObject(int existing, int kind, vtkWhittedPolyDataConverter::Primitives& primitives);
  void FreeObject(int& id);

  whitted::Scene& Scene;
  vtkWhittedTextureCache& Textures;
  unsigned long Frame = 0;
  std::map<Key, Geometry> Geometries;
  std::map<vtkMapper*, Surface> Surfaces;
  std::vector<uint32_t> FreeObjects;
};

#endif
// VTK-HeaderTest-Exclude: vtkWhittedGeometryCache.h
