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
 * - A geometry whose input is a new data object (ParaView hands each time step's data to the
 *   mapper as a new object) takes over the objects of the mapper's geometry for the same piece that
 *   this frame has not used yet: its BVH is refit when only points moved.
 *
 * Time cache (SetTimeCacheLimit): the converted objects of a geometry's earlier inputs (earlier
 * time steps, earlier contour values) are kept outside the scene, keyed by a fingerprint of the
 * input's contents (points, cells, every point, cell and field array) and of the mapper state the
 * conversion reads (scalar mode, array, colour mode, lookup table and its MTime, range, radius
 * scale). An input whose fingerprint matches a kept entry gets that entry's objects back with
 * their BVHs: nothing is converted or built (a time cache hit). Keyed by contents, not by time, a
 * hit cannot show stale data: an upstream edit changes the fingerprint. Entries are dropped
 * least recently used first to stay within the limit and to leave a tenth of the machine's
 * memory available, and with their mapper.
 * What is kept: contents a user comes back to, not every contents ever shown. When a geometry's
 * contents are replaced, they are kept if they were a time step (the input carried
 * vtkDataObject::DATA_TIME_STEP, as readers' and ParaView's time-varying data do) and the new
 * input is another time step, or if the same contents had been shown and replaced before (a
 * re-shown input: going back to an earlier contour value, replaying a pipeline without time).
 * Dragging a contour slider through new values therefore keeps nothing: the fingerprints of
 * replaced contents are remembered (a few bytes each, the last 4096), not their geometry.
 * Replaying a pipeline without time information converts once more, then hits.
 *
 * @sa vtkWhittedSceneConverter vtkWhittedPolyDataConverter vtkWhittedTextureCache
 * vtkWhittedGeometryTimeCache vtkWhittedGeometryFingerprint
 */

#ifndef vtkWhittedGeometryCache_h
#define vtkWhittedGeometryCache_h

#include "vtkSmartPointer.h"             // for vtkSmartPointer
#include "vtkWhittedPolyDataConverter.h" // for Options, Problems

#include <cstdint>    // for uint64_t
#include <functional> // for std::function
#include <map>        // for std::map
#include <memory>     // for std::unique_ptr
#include <vector>     // for std::vector

class vtkDataObject;
class vtkDataSet;
class vtkDataSetSurfaceFilter;
class vtkMapper;
class vtkPolyData;
class vtkWhittedGeometryTimeCache;
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
    vtkDataObject* Data = nullptr; ///< The input the stamp was taken of.
    int Piece = 0;                 ///< Index of the input among the actor's pieces (blocks).
    unsigned long LastFrame = 0;
    /// Fingerprints of the contents now held (time cache key; valid if Fingerprinted).
    uint64_t ContentPrint = 0, StatePrint = 0;
    bool Fingerprinted = false;
    /// The contents' DATA_TIME_STEP (if HasTime): time steps are kept when the time moves on.
    double Time = 0.0;
    bool HasTime = false;
  };

  /// What the time cache did in this frame and holds.
  struct TimeCacheCounts
  {
    int Hits = 0;          ///< Geometries restored from the time cache in this frame.
    int Entries = 0;       ///< Geometries kept.
    std::size_t Bytes = 0; ///< Their memory (geometry and BVHs).
  };

  vtkWhittedGeometryCache(whitted::Scene& scene, vtkWhittedTextureCache& textures);
  ~vtkWhittedGeometryCache();

  /// Starts a frame: what is not used from here to FreeUnused() is freed then.
  void BeginFrame();

  /**
   * The geometry mapper draws from poly (piece number piece of the actor) with options, converted
   * again if anything it depends on changed (then converted is incremented), or restored from the
   * time cache. radiusScale (called only when converting or fingerprinting spheres and tubes) turns
   * PointSize and LineWidth into object-space radii.
   */
  const Geometry& Get(vtkMapper* mapper, vtkPolyData* poly, int piece,
    const vtkWhittedPolyDataConverter::Options& options, const std::function<double()>& radiusScale,
    int& converted);

  /// Memory the time cache may hold, bytes; 0 turns it off (and frees what it holds).
  void SetTimeCacheLimit(std::size_t bytes);
  TimeCacheCounts GetTimeCacheCounts() const;

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
  // The geometry of key, or the mapper's unused geometry of the same piece and options (adopted
  // under key), or a new one.
  Geometry& Find(const Key& key, int piece);
  // Time cache: moves (or, when next may refit them, copies) the objects g holds into the cache
  // under g's fingerprints, if they are worth keeping (class documentation); next is the
  // conversion about to replace them (null: none), nextHasTime/nextTime the time of what replaces
  // them.
  void Keep(const Key& key, Geometry& g, const vtkWhittedPolyDataConverter::Primitives* next,
    bool nextHasTime, double nextTime);
  // Gives g the kept objects of these fingerprints (what g holds is kept in turn, judged against
  // hasTime/time, the time of the input asking for them); false if none.
  bool Restore(const Key& key, Geometry& g, uint64_t statePrint, uint64_t contentPrint,
    bool hasTime, double time);

  whitted::Scene& Scene;
  vtkWhittedTextureCache& Textures;
  unsigned long Frame = 0;
  std::map<Key, Geometry> Geometries;
  std::map<vtkMapper*, Surface> Surfaces;
  std::vector<uint32_t> FreeObjects;
  std::unique_ptr<vtkWhittedGeometryTimeCache> Kept;
};

#endif
// VTK-HeaderTest-Exclude: vtkWhittedGeometryCache.h
