// Actor matrices as instances: one cone mapper shared by actors placed with Position, Orientation,
// non-uniform Scale with an Origin, a UserMatrix, a UserTransform, and two parts of a rotated
// vtkAssembly. All share one converted geometry (one object BVH); moving an actor afterwards
// rebuilds no object BVH.
#include "WhittedTestUtilities.h"

#include "vtkAssembly.h"
#include "vtkCamera.h"
#include "vtkConeSource.h"
#include "vtkLight.h"
#include "vtkMatrix4x4.h"
#include "vtkRegressionTestImage.h"
#include "vtkTransform.h"

#include <iostream>

int TestWhittedTransforms(int argc, char* argv[])
{
  using namespace whittedtest;
  vtkNew<vtkRenderer> ren;
  auto win = MakeWindow(300, 240);
  win->AddRenderer(ren);
  ren->AddActor(Floor(3.0, 6));

  vtkNew<vtkConeSource> cone;
  cone->SetResolution(32);
  cone->SetHeight(1.0);
  cone->SetRadius(0.35);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputConnection(cone->GetOutputPort());

  auto make = [&](double r, double g, double b)
  {
    vtkNew<vtkActor> a;
    a->SetMapper(mapper);
    a->GetProperty()->SetColor(r, g, b);
    a->GetProperty()->SetSpecular(0.4);
    a->GetProperty()->SetSpecularPower(30);
    return vtkSmartPointer<vtkActor>(a.Get());
  };

  auto positioned = make(0.9, 0.3, 0.3);
  positioned->SetPosition(-2.0, 0.5, 0.5);
  ren->AddActor(positioned);

  auto oriented = make(0.3, 0.9, 0.3);
  oriented->SetPosition(-0.8, 0.6, 0.8);
  oriented->SetOrientation(0, 30, 90); // points up
  ren->AddActor(oriented);

  auto scaled = make(0.3, 0.4, 0.95);
  scaled->SetOrigin(0.5, 0, 0);
  scaled->SetScale(1.6, 0.6, 0.6);
  scaled->SetPosition(0.2, 0.3, 1.2);
  ren->AddActor(scaled);

  vtkNew<vtkMatrix4x4> user;
  user->SetElement(0, 3, 1.5);
  user->SetElement(1, 3, 0.9);
  user->SetElement(2, 3, 0.3);
  user->SetElement(0, 1, 0.5); // shear
  auto userMatrix = make(0.95, 0.8, 0.2);
  userMatrix->SetUserMatrix(user);
  ren->AddActor(userMatrix);

  vtkNew<vtkTransform> t;
  t->Translate(0.6, 0.35, -0.6);
  t->RotateY(60);
  auto userTransform = make(0.8, 0.3, 0.9);
  userTransform->SetUserTransform(t);
  ren->AddActor(userTransform);

  vtkNew<vtkAssembly> assembly;
  auto partA = make(0.2, 0.8, 0.8);
  partA->SetPosition(0.0, 0.0, 0.0);
  auto partB = make(0.9, 0.6, 0.3);
  partB->SetPosition(0.0, 0.0, 0.7);
  partB->SetOrientation(0, 180, 0);
  assembly->AddPart(partA);
  assembly->AddPart(partB);
  assembly->SetPosition(-1.6, 0.4, -1.2);
  assembly->RotateY(35);
  ren->AddActor(assembly);

  AddPointLight(ren, -1.0, 5.0, 4.0);
  ren->SetBackground(0.2, 0.2, 0.25);
  LookAt(ren, { 0.0, 3.5, 5.5 }, { -0.2, 0.4, 0.0 }, 40);

  vtkNew<vtkWhittedPass> pass;
  ApplyTestSwitches(pass);
  vtkWhittedFrameStatistics* stats = pass->GetLastFrameStatistics();
  ren->SetPass(pass);
  win->Render();
  std::cout << pass->GetLastFrameReport();
  // One geometry for the floor, one for all seven cones
  if (stats->GetNumberOfGeometriesConverted() != 2 || stats->GetNumberOfTracedActors() != 8)
  {
    std::cerr << "expected 2 converted geometries and 8 traced actors\n";
    return EXIT_FAILURE;
  }
  const int baseline = CheckBaseline(win, argc, argv);

  // Independent: VTK's raster of the same scene (CheckAgainstRaster)
  RasterOracle raster;
  raster.MinShadowShare = 0.03;
  raster.MinUmbraShare = 0.5;
  const bool independent = CheckAgainstRaster("Transforms", win, pass, raster);
  return baseline == EXIT_SUCCESS && independent ? EXIT_SUCCESS : EXIT_FAILURE;
}
