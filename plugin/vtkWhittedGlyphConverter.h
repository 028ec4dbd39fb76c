/**
 * @class   vtkWhittedGlyphConverter
 * @brief   internal: the glyphs of a vtkGlyph3DMapper actor as instances of its sources
 *
 * Private to the Whitted module. One belongs to each vtkWhittedSceneConverter and keeps its glyph
 * actors across frames. Each source of a glyph actor is converted once (cached by
 * vtkWhittedGeometryCache like any geometry, without scalar colours: VTK colours a glyph by its
 * point, never by its source's scalars), and each glyph is an instance of its source's objects
 * (vtkWhittedInstanceSlots) with the glyph's matrix (vtkWhittedGlyphPlacement: where VTK places
 * it) after the actor's, and its point's colour (the mapper's scalars through its lookup table) as
 * the instance colour. So a million glyphs cost instance records, not copies of the geometry, and
 * one material per source and block. The placement is computed again only when the mapper, its
 * lookup table, the points, the actor's matrix or a source's objects changed; the instances are
 * then reused in place, new ones taken from the freed ones, surplus ones hidden and freed.
 *
 * The scene converter calls Collect() (what the actor draws, and whether the tracer draws it),
 * then, for a traced actor, Convert(). VTK's default glyph (a line from (0,0,0) to (1,0,0))
 * stands in when the mapper has no source.
 *
 * @sa vtkWhittedGlyphPlacement vtkWhittedSceneConverter vtkWhittedInstanceSlots vtkGlyph3DMapper
 */

#ifndef vtkWhittedGlyphConverter_h
#define vtkWhittedGlyphConverter_h

#include "vtkSmartPointer.h"         // for vtkSmartPointer
#include "vtkWhittedGeometryCache.h" // for NumberOfKinds, Geometry, Options

#include "util/math.h" // for whitted::Mat4

#include <cstdint> // for uint32_t
#include <map>     // for std::map
#include <utility> // for std::pair
#include <vector>  // for std::vector

class vtkActor;
class vtkDataSet;
class vtkGlyph3DMapper;
class vtkPolyData;
class vtkPolyDataMapper;
class vtkProp;
class vtkUnsignedCharArray;
class vtkWhittedInstanceSlots;
class vtkWhittedTextureCache;
class vtkWhittedWarnings;

class vtkWhittedGlyphConverter
{
public:
  vtkWhittedGlyphConverter(whitted::Scene& scene, vtkWhittedGeometryCache& geometries,
    vtkWhittedTextureCache& textures, vtkWhittedInstanceSlots& slots, vtkWhittedWarnings& warnings);
  ~vtkWhittedGlyphConverter();
  vtkWhittedGlyphConverter(const vtkWhittedGlyphConverter&) = delete;
  vtkWhittedGlyphConverter& operator=(const vtkWhittedGlyphConverter&) = delete;

  /// What a glyph actor draws.
  struct Input
  {
    vtkGlyph3DMapper* Mapper = nullptr;
    std::vector<vtkPolyData*> Sources; ///< The mapper's sources, or VTK's default glyph.
    std::vector<vtkDataSet*> Blocks;   ///< The datasets whose points carry glyphs.
  };

  /// Who draws a glyph actor.
  enum Verdict
  {
    Trace,  ///< The tracer (Input filled).
    OpenGL, ///< VTK's OpenGL path.
    Nothing ///< Nobody: VTK draws nothing either.
  };

  /// Starts a frame: the glyph actors not converted from here to FreeUnused() are freed then.
  void BeginFrame();

  /**
   * Updates mapper (unless it is static) and collects what actor draws with it into input, as VTK's
   * OpenGL glyph mapper does. OpenGL: the mapper uses a source table tree (warned) or a source
   * has only plain points or lines for the actor's property. Nothing: a source is missing, or the
   * input holds no dataset.
   */
  Verdict Collect(vtkActor* actor, vtkGlyph3DMapper* mapper, Input& input);

  /**
   * Places the glyphs of input (from Collect() in this frame) for one occurrence of actor (in
   * assemblies) with its world matrix; the sources are converted with options, each conversion
   * counted in converted; lightsOn as for vtkWhittedMaterials::Convert.
   */
  void Convert(vtkActor* actor, int occurrence, const Input& input, const whitted::Mat4& matrix,
    const vtkWhittedPolyDataConverter::Options& options, bool lightsOn, int& converted);

  /// Frees the glyph actors and helper mappers not used since BeginFrame().
  void FreeUnused();

  /// Forgets every glyph actor (after the scene was replaced).
  void Clear();

private:
  // Helper mappers of one glyph mapper: its sources are converted without scalar colours and its
  // colours are mapped by a copy of its colour settings; the line VTK draws when it has no source.
  struct Helpers
  {
    vtkSmartPointer<vtkPolyDataMapper> Shape;
    vtkSmartPointer<vtkPolyDataMapper> Colors;
    vtkSmartPointer<vtkPolyData> DefaultSource;
    unsigned long LastFrame = 0;
  };

  // The glyphs of one source in one dataset block of a glyph actor: per primitive kind of the
  // source's geometry, its object and one instance per glyph; one material for all of them.
  struct GlyphSource
  {
    int Objects[vtkWhittedGeometryCache::NumberOfKinds] = { -1, -1, -1 };
    whitted::Vec3 Origin{ 0.0 };
    std::vector<uint32_t> Instances[vtkWhittedGeometryCache::NumberOfKinds];
    int Material = -1;
  };

  // A glyph actor (one occurrence of a leaf): its glyph sources (block-major) and what their
  // placement was computed from, so an unchanged actor costs one material update per source.
  struct GlyphActor
  {
    std::vector<GlyphSource> Sources;
    vtkMTimeType Stamp = 0;
    whitted::Mat4 Matrix{ 1.0 };
    bool Colored = false; ///< The glyphs carry colours mapped from scalars.
    unsigned long LastFrame = 0;
  };

  // The helper mappers of a glyph mapper (created on first use).
  Helpers& HelpersOf(vtkGlyph3DMapper* mapper);
  // Places the glyphs of one dataset block: instance j of a source's object is its j-th glyph.
  void Place(vtkActor* actor, vtkGlyph3DMapper* mapper, vtkDataSet* points,
    const whitted::Mat4& matrix,
    const std::vector<const vtkWhittedGeometryCache::Geometry*>& geometries,
    vtkUnsignedCharArray* colors, GlyphSource* sources);
  // Instance j of a glyph source's kind k with matrix: the one it had, or a new one.
  uint32_t Instance(GlyphSource& gs, int k, size_t j, const whitted::Mat4& matrix);
  // Hides a glyph source's instances and frees them and its material for reuse.
  void FreeSource(GlyphSource& gs);

  whitted::Scene& Scene;
  vtkWhittedGeometryCache& Geometries;
  vtkWhittedTextureCache& Textures;
  vtkWhittedInstanceSlots& Slots;
  vtkWhittedWarnings& Warnings;
  unsigned long Frame = 0;
  std::map<vtkGlyph3DMapper*, Helpers> Glyphers;
  std::map<std::pair<vtkProp*, int>, GlyphActor> GlyphActors;
};

#endif
// VTK-HeaderTest-Exclude: vtkWhittedGlyphConverter.h
