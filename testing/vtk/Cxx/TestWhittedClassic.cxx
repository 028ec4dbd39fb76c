// Whitted's classic scene (vtkWhittedClassicScene, from the core's one description of it):
// checkerboard floor, mirror sphere, glass sphere, one point light. The Python test
// TestWhittedPythonClassic renders it through the wrapping against the same baseline.
#include "WhittedTestUtilities.h"

#include "vtkRegressionTestImage.h"
#include "vtkWhittedClassicScene.h"

#include <iostream>

int TestWhittedClassic(int argc, char* argv[])
{
  using namespace whittedtest;
  vtkNew<vtkRenderer> ren;
  auto win = MakeWindow(320, 240);
  win->AddRenderer(ren);

  vtkNew<vtkWhittedClassicScene> scene;
  scene->SetResolution(48);
  scene->AddToRenderer(ren);

  vtkNew<vtkWhittedPass> pass;
  ren->SetPass(pass);
  win->Render();
  std::cout << pass->GetLastFrameReport();

  int retVal = vtkRegressionTestImage(win);
  return retVal == vtkTesting::FAILED ? EXIT_FAILURE : EXIT_SUCCESS;
}
