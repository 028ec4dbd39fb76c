#include "vtkWhittedEnvironment.h"

#include "vtkWhittedMatrix.h"
#include "vtkWhittedTextureCache.h"
#include "vtkWhittedWarnings.h"

#include "vtkCamera.h"
#include "vtkRenderer.h"
#include "vtkSkybox.h"
#include "vtkTexture.h"
#include "vtkVersionMacros.h"

#include "scene/scene.h"

#include <cmath>

using whitted::Vec3;
using Projection = whitted::EnvironmentMap::Projection;

namespace
{
Vec3 ToVec3(const double* v)
{
  return Vec3(v[0], v[1], v[2]);
}

Vec3 Unit(const Vec3& v, const Vec3& fallback)
{
  const double l = glm::length(v);
  return std::isfinite(l) && l > 0.0 ? v / l : fallback;
}

// A visible skybox's texture, oriented by its floor plane and FloorRight.
void SkyboxEnvironment(vtkSkybox* skybox, vtkTexture* texture, vtkWhittedTextureCache& textures,
  vtkWhittedWarnings& warnings, whitted::EnvironmentMap& env)
{
  // vtkSkybox's shader: up = floor plane normal, right = FloorRight, front = up x right
  const float* plane = skybox->GetFloorPlane();
  const float* right = skybox->GetFloorRight();
  const Vec3 up = Unit(Vec3(plane[0], plane[1], plane[2]), { 0, 1, 0 });
  const Vec3 r = Unit(Vec3(right[0], right[1], right[2]), { 1, 0, 0 });
  const int projection = skybox->GetProjection();
  if (projection == vtkSkybox::Sphere || projection == vtkSkybox::StereoSphere)
  {
    if (projection == vtkSkybox::StereoSphere)
    {
      warnings.Warn(skybox, vtkWhittedWarnings::StereoSkybox);
    }
    env.projection = Projection::Sphere;
    env.faces[0] = textures.Get(texture);
    env.right = r;
    env.up = up;
    env.front = glm::cross(up, r);
  }
  else if (projection == vtkSkybox::Cube)
  {
    if (textures.GetCubeFaces(texture, env.faces))
    {
      env.projection = Projection::Cube;
#if VTK_MAJOR_VERSION > 9 || (VTK_MAJOR_VERSION == 9 && VTK_MINOR_VERSION >= 2)
      // From VTK 9.2 (ParaView 5.11) the cube lookup is (d.right, d.up, d.front)
      env.right = r;
      env.up = up;
      env.front = -glm::cross(up, r);
#endif
    }
    else
    {
      warnings.Warn(skybox, vtkWhittedWarnings::SkyboxCubeFaces);
    }
  }
  else
  {
    warnings.Warn(skybox, vtkWhittedWarnings::FloorSkybox);
  }
}

// The renderer's environment texture (image-based lighting), oriented by EnvironmentUp/Right.
void TextureEnvironment(vtkRenderer* ren, vtkTexture* texture, vtkWhittedTextureCache& textures,
  whitted::EnvironmentMap& env)
{
  const Vec3 up = Unit(ToVec3(ren->GetEnvironmentUp()), { 0, 1, 0 });
  const Vec3 r = Unit(ToVec3(ren->GetEnvironmentRight()), { 1, 0, 0 });
  if (texture->GetCubeMap())
  {
    if (textures.GetCubeFaces(texture, env.faces))
    {
      env.projection = Projection::Cube;
      env.right = r;
      env.up = up;
      env.front = -glm::cross(r, up);
    }
  }
  else
  {
    // VTK's equirectangular convention: u = atan2(d.z, d.x) / 2pi + 0.5 in the default frame
    env.projection = Projection::Sphere;
    env.faces[0] = textures.Get(texture);
    env.right = glm::cross(r, up);
    env.up = up;
    env.front = r;
  }
}

// The textured background, seen as a backdrop through the camera.
void BackdropEnvironment(
  vtkRenderer* ren, vtkWhittedTextureCache& textures, whitted::EnvironmentMap& env)
{
  env.projection = Projection::Screen;
  env.faces[0] = textures.Get(ren->GetBackgroundTexture());
  vtkCamera* cam = ren->GetActiveCamera();
  env.worldToClip =
    vtkWhittedToMat4(cam->GetCompositeProjectionTransformMatrix(ren->GetTiledAspectRatio(), -1, 1));
  double fp[3], pos[3];
  cam->GetFocalPoint(fp);
  cam->GetPosition(pos);
  env.viewDirection = Unit(ToVec3(fp) - ToVec3(pos), { 0, 0, -1 });
  // The up vector perpendicular to the view direction
  const Vec3 up = Unit(ToVec3(cam->GetViewUp()), { 0, 1, 0 });
  env.viewUp = Unit(up - glm::dot(up, env.viewDirection) * env.viewDirection, { 0, 1, 0 });
}
}

//------------------------------------------------------------------------------
void vtkWhittedEnvironment::Convert(vtkRenderer* ren, vtkSkybox* skybox,
  vtkWhittedTextureCache& textures, vtkWhittedWarnings& warnings, whitted::Scene& scene)
{
  // Background colour or gradient
  double c[3];
  ren->GetBackground(c);
  scene.background = whitted::Color(c[0], c[1], c[2]);
  ren->GetBackground2(c);
  scene.background2 = whitted::Color(c[0], c[1], c[2]);
  scene.gradientBackground = ren->GetGradientBackground();
  // Misses are written with alpha 0 and not composited: what VTK cleared (background, gradient,
  // lower layers, transparent compositing background) stays
  scene.backgroundAlpha = 0.0f;

  // What reflected and bent rays see, in VTK's order of precedence
  whitted::EnvironmentMap env;
  vtkTexture* skyTexture = skybox ? skybox->GetTexture() : nullptr;
  if (skyTexture)
  {
    SkyboxEnvironment(skybox, skyTexture, textures, warnings, env);
  }
  else if (vtkTexture* t = ren->GetEnvironmentTexture())
  {
    TextureEnvironment(ren, t, textures, env);
  }
  else if (ren->GetTexturedBackground() && ren->GetBackgroundTexture())
  {
    BackdropEnvironment(ren, textures, env);
  }
  if (env.projection != Projection::None && env.faces[0] < 0)
  {
    env.projection = Projection::None; // an empty image: the background colour
  }
  scene.environmentMap = env;
}
