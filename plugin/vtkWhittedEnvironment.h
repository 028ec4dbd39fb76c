/**
 * @file    vtkWhittedEnvironment.h
 * @brief   internal: what rays that leave the scene see (background, skybox, environment texture)
 *
 * Private to the Whitted module. Camera rays that miss are written with alpha 0 and not composited,
 * so what VTK cleared or drew behind the traced image (background colour or gradient, lower layers,
 * a vtkSkybox) shows through. Reflected and refracted rays that leave the scene see, in VTK's order
 * of precedence: the first visible vtkSkybox with a texture (Sphere or Cube projection), else the
 * renderer's environment texture (equirectangular or cube map), else its textured background seen
 * as a backdrop through the camera, else the background colour or gradient
 * (whitted::EnvironmentMap).
 *
 * @sa vtkWhittedSceneConverter vtkWhittedTextureCache
 */

#ifndef vtkWhittedEnvironment_h
#define vtkWhittedEnvironment_h

class vtkRenderer;
class vtkSkybox;
class vtkWhittedTextureCache;
class vtkWhittedWarnings;

namespace whitted
{
class Scene;
}

namespace vtkWhittedEnvironment
{
/// Sets scene's background and environment map from renderer and skybox (may be null).
void Convert(vtkRenderer* renderer, vtkSkybox* skybox, vtkWhittedTextureCache& textures,
  vtkWhittedWarnings& warnings, whitted::Scene& scene);
}

#endif
// VTK-HeaderTest-Exclude: vtkWhittedEnvironment.h
