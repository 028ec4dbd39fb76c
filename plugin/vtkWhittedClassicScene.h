/**
 * @class   vtkWhittedClassicScene
 * @brief   Whitted's classic scene built from VTK sources
 *
 * A red/yellow checkerboard floor (vtkPlaneSource with direct unsigned-char cell colours), a mirror
 * sphere and a glass sphere (vtkSphereSource, Whitted keys on their properties), one positional
 * light, the background and the camera. Built from the core's one description of the scene
 * (whitted::classicSceneDescription() in core/scenes/scenes.h), which the core's built-in "classic" scene,
 * whitted_render and the benchmark trace too. Used by the demo (whitted.scenes.classic_scene), and
 * by the C++ and Python regression tests, which share one baseline.
 * @code
 *   scene = vtkWhittedClassicScene()
 *   scene.SetResolution(48)
 *   scene.AddToRenderer(renderer)
 *   scene.GetGlass().GetProperty().SetOpacity(0.5)
 * @endcode
 *
 * @sa vtkWhittedPass
 */

#ifndef vtkWhittedClassicScene_h
#define vtkWhittedClassicScene_h

#include "vtkObject.h"
#include "vtkWhittedModule.h" // For export macro

class vtkActor;
class vtkLight;
class vtkPolyData;
class vtkRenderer;

class VTKWHITTED_EXPORT vtkWhittedClassicScene : public vtkObject
{
public:
  static vtkWhittedClassicScene* New();
  vtkTypeMacro(vtkWhittedClassicScene, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Sphere resolution: vtkSphereSource's phi resolution (theta gets twice as many). Default is 48.
   */
  vtkSetClampMacro(Resolution, int, 3, 1024);
  vtkGetMacro(Resolution, int);
  ///@}

  /**
   * Adds the floor, mirror and glass actors (in that order) and the light to the renderer, sets its
   * background and points its active camera at the scene (clipping range reset). The actors and the
   * light are new ones at every call.
   */
  void AddToRenderer(vtkRenderer* renderer);

  ///@{
  /**
   * The actors and the light added by the last AddToRenderer (nullptr before the first).
   */
  vtkActor* GetFloor();
  vtkActor* GetMirror();
  vtkActor* GetGlass();
  vtkLight* GetLight();
  ///@}

  /**
   * Fills output with a plane given as vtkPlaneSource gives it (origin, point1, point2) of nx x ny
   * cells whose direct unsigned-char RGB cell scalars ("checker") alternate between color0 (cell 0)
   * and color1 (colours in [0,1]). The classic floor, and the tests' floors.
   */
  static void MakeCheckerboard(vtkPolyData* output, const double origin[3], const double point1[3],
    const double point2[3], int nx, int ny, const double color0[3], const double color1[3]);

protected:
  vtkWhittedClassicScene();
  ~vtkWhittedClassicScene() override;

  int Resolution = 48;

private:
  vtkWhittedClassicScene(const vtkWhittedClassicScene&) = delete;
  void operator=(const vtkWhittedClassicScene&) = delete;

  struct vtkInternals;
  vtkInternals* Internals;
};

#endif
