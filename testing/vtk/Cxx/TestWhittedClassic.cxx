// Whitted's classic scene built from VTK sources: checkerboard floor, mirror sphere, glass sphere,
// one point light. The same scene as plugin/python/scenes.py classic_scene() and the Python test
// (same baseline).
#include "WhittedTestUtilities.h"

#include "vtkCamera.h"
#include "vtkLight.h"
#include "vtkRegressionTestImage.h"

#include <iostream>

int TestWhittedClassic(int argc, char* argv[])
{
  using namespace whittedtest;
  vtkNew<vtkRenderer> ren;
  auto win = MakeWindow(320, 240);
  win->AddRenderer(ren);

  // Floor: 10 x 14 red / yellow checkers in y = 0
  const double o[3] = { -5.0, 0.0, 3.0 }, p1[3] = { 5.0, 0.0, 3.0 }, p2[3] = { -5.0, 0.0, -11.0 };
  const double red[3] = { 0.85, 0.1, 0.1 }, yellow[3] = { 0.95, 0.85, 0.1 };
  vtkNew<vtkPolyDataMapper> floorMapper;
  floorMapper->SetInputData(Checkerboard(o, p1, p2, 10, 14, red, yellow));
  floorMapper->SetScalarModeToUseCellData();
  vtkNew<vtkActor> floor;
  floor->SetMapper(floorMapper);
  floor->GetProperty()->SetAmbient(0.15);
  floor->GetProperty()->SetDiffuse(0.85);
  ren->AddActor(floor);

  // Mirror sphere
  auto mirror = Sphere(0.9, 1.1, -3.6, 1.1, 48);
  mirror->GetProperty()->SetColor(0.7, 0.7, 0.7);
  mirror->GetProperty()->SetAmbient(0.05);
  mirror->GetProperty()->SetDiffuse(0.15);
  mirror->GetProperty()->SetSpecular(0.6);
  mirror->GetProperty()->SetSpecularPower(60);
  SetWhitted(mirror->GetProperty(), 0.8);
  ren->AddActor(mirror);

  // Glass sphere
  auto glass = Sphere(-0.7, 0.8, -1.4, 0.8, 48);
  glass->GetProperty()->SetColor(0.9, 0.9, 0.9);
  glass->GetProperty()->SetAmbient(0.0);
  glass->GetProperty()->SetDiffuse(0.0);
  glass->GetProperty()->SetSpecular(0.8);
  glass->GetProperty()->SetSpecularPower(100);
  SetWhitted(glass->GetProperty(), 0.1, 0.9, 1.5);
  ren->AddActor(glass);

  AddPointLight(ren, 4.0, 7.0, 3.0);
  ren->SetBackground(0.3, 0.5, 0.85);

  LookAt(ren, { 0.0, 1.8, 4.0 }, { 0.0, 0.9, -2.5 }, 40.0);

  vtkNew<vtkWhittedPass> pass;
  ren->SetPass(pass);
  win->Render();
  std::cout << pass->GetLastFrameReport();

  int retVal = vtkRegressionTestImage(win);
  return retVal == vtkTesting::FAILED ? EXIT_FAILURE : EXIT_SUCCESS;
}
