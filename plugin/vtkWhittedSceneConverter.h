/**
 * @class   vtkWhittedSceneConverter
 * @brief   internal: turns a vtkRenderer's props, lights and background into the tracer's scene
 *
 * Private to the Whitted module (not wrapped, not installed). One converter belongs to one
 * vtkWhittedPass per renderer and keeps a whitted::Scene alive across frames so that only what
 * changed is converted again. This class is the prop walk: which props are traced (every visible
 * actor, also those the frustum culler dropped; assembly parts with their concatenated matrices;
 * the blocks of a composite input) and which are left to OpenGL, and the instances that place
 * converted geometry with each actor's matrix. Each VTK concept has its own file pair:
 *
 * - vtkWhittedActorPieces: the polydata an actor draws (its input, a dataset's surface, the
 *   visible blocks of a composite input), and whether they are only plain points or lines.
 * - vtkWhittedGeometryCache: geometry per (mapper, input or block, geometry-relevant property
 *   settings), converted by vtkWhittedPolyDataConverter only when the mapper, its lookup table or
 *   the input changed (MTime). Actors that share a mapper share one object (instancing).
 * - vtkWhittedTextureCache: actor, background and environment textures and colour maps, replaced
 *   in place when they change and freed when no longer used.
 * - vtkWhittedMaterials (vtkProperty + Whitted keys), vtkWhittedLights (vtkLight),
 *   vtkWhittedEnvironment (background, skybox, environment texture): cheap, rebuilt every frame.
 * - vtkWhittedGlyphConverter: a vtkGlyph3DMapper actor, each glyph an instance of its source
 *   (where it stands: vtkWhittedGlyphPlacement).
 * - vtkWhittedInstanceSlots: the scene's instances and materials, reused across frames (actor
 *   pieces and glyphs).
 * - vtkWhittedWarnings: every warning, said once per prop. vtkWhittedMatrix.h: vtkMatrix4x4 ->
 *   whitted::Mat4.
 *
 * Each traced actor (or block) is an instance of its geometry's objects with the actor's matrix;
 * moving an actor changes only the instance transform (the top-level BVH, never an object BVH).
 * Props the tracer does not handle are returned so that the pass can draw them with VTK's OpenGL
 * path: 2D actors, volumes the tracer does not take (vtkWhittedVolumeConverter), image slices,
 * actors whose mapper is not a vtkPolyDataMapper, and actors drawn as plain points, lines or
 * wireframe (no RenderPointsAsSpheres / RenderLinesAsTubes). Traced volumes:
 * vtkWhittedVolumeConverter.
 */

#ifndef vtkWhittedSceneConverter_h
#define vtkWhittedSceneConverter_h

#include <cstddef> // for std::size_t
#include <memory>  // for std::unique_ptr
#include <vector>  // for std::vector

class vtkObject;
class vtkProp;
class vtkRenderer;

namespace whitted
{
class Scene;
}

class vtkWhittedSceneConverter
{
public:
  vtkWhittedSceneConverter();
  ~vtkWhittedSceneConverter();
  vtkWhittedSceneConverter(const vtkWhittedSceneConverter&) = delete;
  vtkWhittedSceneConverter& operator=(const vtkWhittedSceneConverter&) = delete;

  /// What one Update() did.
  struct Result
  {
    std::vector<vtkProp*> OpenGLProps; ///< Props to draw with VTK's OpenGL stages.
    /// Props that are the environment (vtkSkybox): drawn by OpenGL before the traced image is
    /// composited over them, so translucent pixels show them behind; reflections sample them.
    std::vector<vtkProp*> BackgroundProps;
    int GeometriesConverted = 0;    ///< Geometries (inputs or blocks) converted in this update.
    int TimeCacheHits = 0;          ///< Geometries restored from the time cache in this update.
    int TimeCacheEntries = 0;       ///< Geometries the time cache holds after it.
    std::size_t TimeCacheBytes = 0; ///< Their memory, bytes.
    int TracedActors = 0;           ///< Leaf actors that became instances.
    int TracedVolumes = 0;          ///< Volumes traced (or not drawn for bad input).
    int VolumesConverted = 0;       ///< Volume grids converted (new or changed image data).
    int VolumeTransferUpdates = 0;  ///< Volumes whose transfer functions alone were updated.
    bool HeadlightShading = false;  ///< VTK light complexity 1 (one headlight) applies.
  };

  /**
   * Brings the scene up to date with the renderer: every visible actor of the renderer is traced
   * (also those the frustum culler dropped from the render state: they cast shadows and show in
   * mirrors); of the render state's props (props, count), those the tracer does not draw are
   * returned in Result::OpenGLProps. Lights are read after vtkLightsPass. Warnings go through
   * owner.
   */
  void Update(vtkRenderer* ren, vtkProp** props, int count, vtkObject* owner, Result& result);

  /// The tracer's scene (commit() it before rendering).
  whitted::Scene& GetScene();

  /// Drops every cached conversion (the next Update converts everything).
  void Reset();

  /// Memory the time cache of earlier geometry contents may hold, bytes (0: off); see
  /// vtkWhittedGeometryCache.
  void SetTimeCacheLimit(std::size_t bytes);

  /// Shadows from the brightest light only (vtkWhittedPass ShadowsFromBrightestLightOnly); see
  /// vtkWhittedLights::Convert.
  void SetShadowsFromBrightestLightOnly(bool on);

private:
  struct Internals;
  std::unique_ptr<Internals> Impl;
};

#endif
// VTK-HeaderTest-Exclude: vtkWhittedSceneConverter.h
