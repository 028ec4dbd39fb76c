// Shadows from each VTK light type, one viewport each, all through one shared pass:
// bottom-left a directional scene light, bottom-right a positional light with attenuation, top-left
// a spot light, top-right a camera light plus a (switched-off) headlight.
#include "WhittedTestUtilities.h"

#include "vtkCamera.h"
#include "vtkCubeSource.h"
#include "vtkLight.h"
#include "vtkRegressionTestImage.h"

#include <iostream>

namespace
{
using namespace whittedtest;

vtkSmartPointer<vtkRenderer> MakeViewport(double x0, double y0, vtkLight* light)
{
  auto ren = vtkSmartPointer<vtkRenderer>::New();
  ren->SetViewport(x0, y0, x0 + 0.5, y0 + 0.5);
  ren->AddActor(Floor(2.5, 8));
  auto ball = Sphere(-0.5, 0.8, 0.2, 0.5, 24);
  ball->GetProperty()->SetColor(0.9, 0.5, 0.2);
  ball->GetProperty()->SetSpecular(0.4);
  ball->GetProperty()->SetSpecularPower(30);
  ren->AddActor(ball);
  vtkNew<vtkCubeSource> cube;
  cube->SetCenter(0.7, 0.5, -0.3);
  cube->SetXLength(0.6);
  cube->SetYLength(1.0);
  cube->SetZLength(0.6);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputConnection(cube->GetOutputPort());
  vtkNew<vtkActor> box;
  box->SetMapper(mapper);
  box->GetProperty()->SetColor(0.3, 0.5, 0.9);
  ren->AddActor(box);
  ren->AddLight(light);
  ren->SetBackground(0.15, 0.15, 0.2);
  LookAt(ren, { 0.5, 3.2, 5.0 }, { 0.0, 0.3, 0.0 }, 35);
  return ren;
}
}

int TestWhittedLightTypes(int argc, char* argv[])
{
  auto win = MakeWindow(300, 300);
  vtkNew<vtkWhittedPass> pass;
  ApplyTestSwitches(pass);

  vtkNew<vtkLight> sun; // directional scene light
  sun->SetLightTypeToSceneLight();
  sun->SetPosition(-2.0, 4.0, 1.5);
  sun->SetFocalPoint(0.0, 0.0, 0.0);
  vtkNew<vtkLight> bulb; // positional, attenuated, warm
  bulb->SetLightTypeToSceneLight();
  bulb->SetPositional(true);
  bulb->SetPosition(1.2, 2.2, 1.5);
  bulb->SetConeAngle(180);
  bulb->SetAttenuationValues(1.0, 0.0, 0.12);
  bulb->SetColor(1.0, 0.85, 0.6);
  bulb->SetIntensity(1.6);
  vtkNew<vtkLight> spot; // spot light from above
  spot->SetLightTypeToSceneLight();
  spot->SetPositional(true);
  spot->SetPosition(0.3, 3.5, 0.5);
  spot->SetFocalPoint(0.0, 0.0, 0.0);
  spot->SetConeAngle(28);
  spot->SetExponent(3);
  vtkNew<vtkLight> cameraLight; // camera light: up and to the left of the camera
  cameraLight->SetLightTypeToCameraLight();
  cameraLight->SetPosition(-0.6, 0.8, 1.0);
  cameraLight->SetFocalPoint(0.0, 0.0, 0.0);
  cameraLight->SetColor(0.8, 0.9, 1.0);

  vtkLight* lights[4] = { sun, bulb, spot, cameraLight };
  const double origins[4][2] = { { 0.0, 0.0 }, { 0.5, 0.0 }, { 0.0, 0.5 }, { 0.5, 0.5 } };
  for (int i = 0; i < 4; ++i)
  {
    auto ren = MakeViewport(origins[i][0], origins[i][1], lights[i]);
    if (i == 3)
    {
      vtkNew<vtkLight> off;
      off->SetLightTypeToHeadlight();
      off->SwitchOff();
      ren->AddLight(off);
    }
    ren->SetPass(pass);
    win->AddRenderer(ren);
  }
  win->Render();
  std::cout << pass->GetLastFrameReport();
  const int baseline = CheckBaseline(win, argc, argv);

  // Independent: VTK's raster of the same scene (CheckAgainstRaster); shadows in every viewport
  RasterOracle raster;
  raster.MinShadowShare = 0.03;
  raster.MinUmbraShare = 0.5;
  const bool independent = CheckAgainstRaster("LightTypes", win, pass, raster);
  return baseline == EXIT_SUCCESS && independent ? EXIT_SUCCESS : EXIT_FAILURE;
}
