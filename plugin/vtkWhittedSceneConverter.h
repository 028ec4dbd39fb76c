/**
 * @class   vtkWhittedSceneConverter
 * @brief   internal: turns a vtkRenderer's props, lights and background into the tracer's scene
 *
 * Private to the Whitted module (not wrapped, not installed). One converter belongs to one
 * vtkWhittedPass and keeps a whitted::Scene alive across frames so that only what changed is
 * converted again:
 *
 * - Geometry is cached per (mapper, input data object or composite block, geometry-relevant
 *   property settings) and converted again only when the mapper, its lookup table or the input
 *   changed (MTime). Actors that share a mapper share one object (instancing). A conversion that
 *   changes only attributes (colours after a lookup-table edit) keeps the object's BVH.
 * - Colour maps (InterpolateScalarsBeforeMapping) and actor textures are replaced in place when
 *   they change and freed when no longer used (texture memory does not grow with edits).
 * - Each traced actor (or block) is an instance of that object with the actor's matrix; moving an
 *   actor changes only the instance transform (the top-level BVH, never an object BVH).
 * - Materials and lights are cheap and are rebuilt every frame from vtkProperty / vtkLight.
 *
 * Props the tracer does not handle are returned so that the pass can draw them with VTK's OpenGL
 * path: 2D actors, volumes, image slices, actors whose mapper is not a vtkPolyDataMapper, and
 * actors drawn as plain points, lines or wireframe (no RenderPointsAsSpheres / RenderLinesAsTubes).
 */

#ifndef vtkWhittedSceneConverter_h
#define vtkWhittedSceneConverter_h

#include <memory> // for std::unique_ptr
#include <vector> // for std::vector

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
    int GeometriesConverted = 0;       ///< Geometries (inputs or blocks) converted in this update.
    int TracedActors = 0;              ///< Leaf actors that became instances.
    bool HeadlightShading = false;     ///< VTK light complexity 1 (one headlight) applies.
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

private:
  struct Internals;
  std::unique_ptr<Internals> Impl;
};

#endif
// VTK-HeaderTest-Exclude: vtkWhittedSceneConverter.h
