// Renders a sphere over a plane, lit by one directional light at 45 degrees, through the installed
// vtkWhittedPass, offscreen. Exits 0 only if the image shows the sphere and its shadow: the plane is lit at a
// point beside the sphere and dark at the mirror-image point where the shadow falls. VTK's OpenGL rendering
// draws no shadows (both points would be equally lit), so a pass that did not trace fails.
#include "vtkWhittedPass.h"

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkImageData.h>
#include <vtkLight.h>
#include <vtkNew.h>
#include <vtkPlaneSource.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkSphereSource.h>
#include <vtkWindowToImageFilter.h>

#include <cstdio>

namespace
{
void AddActor(vtkRenderer* renderer, vtkAlgorithm* source)
{
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputConnection(source->GetOutputPort());
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  actor->GetProperty()->SetSpecular(0.0);
  renderer->AddActor(actor);
}

// Mean of the RGB channels (0..255) of the pixel showing a world point
double Brightness(vtkRenderer* renderer, vtkImageData* image, double x, double y, double z)
{
  renderer->SetWorldPoint(x, y, z, 1.0);
  renderer->WorldToDisplay();
  const double* display = renderer->GetDisplayPoint();
  const auto* rgb = static_cast<unsigned char*>(
    image->GetScalarPointer(static_cast<int>(display[0]), static_cast<int>(display[1]), 0));
  return (rgb[0] + rgb[1] + rgb[2]) / 3.0;
}
}

int main()
{
  // Scene: a sphere of radius 0.4 at height 0.5 over the plane z = 0
  vtkNew<vtkSphereSource> sphere;
  sphere->SetCenter(0.0, 0.0, 0.5);
  sphere->SetRadius(0.4);
  sphere->SetThetaResolution(48);
  sphere->SetPhiResolution(24);
  vtkNew<vtkPlaneSource> plane;
  plane->SetOrigin(-2.0, -2.0, 0.0);
  plane->SetPoint1(2.0, -2.0, 0.0);
  plane->SetPoint2(-2.0, 2.0, 0.0);

  vtkNew<vtkRenderer> renderer;
  AddActor(renderer, sphere);
  AddActor(renderer, plane);
  renderer->SetBackground(0.0, 0.0, 0.3);
  // Light from +x at 45 degrees: the shadow's centre is at (-0.5, 0, 0), its half-length along x 0.57
  vtkNew<vtkLight> light;
  light->SetLightTypeToSceneLight();
  light->SetPosition(1.0, 0.0, 1.0);
  light->SetFocalPoint(0.0, 0.0, 0.0);
  renderer->AddLight(light);
  vtkCamera* camera = renderer->GetActiveCamera();
  camera->SetPosition(0.0, 0.0, 8.0);
  camera->SetFocalPoint(0.0, 0.0, 0.0);
  camera->SetViewUp(0.0, 1.0, 0.0);

  vtkNew<vtkWhittedPass> pass;
  renderer->SetPass(pass);

  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(0);
  window->SetSize(240, 240);
  window->AddRenderer(renderer);
  window->Render();

  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->Update();
  vtkImageData* image = grab->GetOutput();

  // Probes: the sphere's top, the plane in the shadow (x = -0.85) and its mirror image (x = +0.85), lit
  const double top = Brightness(renderer, image, 0.0, 0.0, 0.9);
  const double shadow = Brightness(renderer, image, -0.85, 0.0, 0.0);
  const double lit = Brightness(renderer, image, 0.85, 0.0, 0.0);
  std::printf("%s\nbrightness: sphere top %.1f, plane lit %.1f, plane in shadow %.1f\n",
    pass->GetLastFrameReport(), top, lit, shadow);
  if (lit < 60.0 || top < 60.0)
  {
    std::printf("FAIL: the scene is not lit\n");
    return 1;
  }
  if (shadow > 0.5 * lit)
  {
    std::printf("FAIL: no shadow where the sphere casts it\n");
    return 1;
  }
  std::printf("OK\n");
  return 0;
}
