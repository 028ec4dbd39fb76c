// Refraction and total internal reflection: a right-angle glass prism (facet normals) used as a
// periscope. A view ray enters its front face, meets the long face at 45 degrees, beyond the
// critical angle of glass (41.8 degrees), is totally reflected downward and leaves through the
// bottom face: the front face shows the floor below the prism instead of the wall behind it. A
// glass sphere beside it refracts (an inverted image).
#include "WhittedTestUtilities.h"

#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkLight.h"
#include "vtkPoints.h"
#include "vtkRegressionTestImage.h"

#include <iostream>

namespace
{
// Prism along x (from -d to d) with right-angle cross-section in y/z: front face z = s (normal +z),
// bottom face y = 0 (normal -y), long face from (y s, z s) to (y 0, z 0) facing up and back;
// outward winding.
vtkSmartPointer<vtkPolyData> Prism(double s, double d)
{
  vtkNew<vtkPoints> pts;
  const double yz[3][2] = { { 0, s }, { s, s }, { 0, 0 } }; // right angle, top front, bottom back
  for (double x : { -d, d })
  {
    for (const auto& p : yz)
    {
      pts->InsertNextPoint(x, p[0], p[1]);
    }
  }
  vtkNew<vtkCellArray> polys;
  const vtkIdType left[3] = { 0, 1, 2 }, right[3] = { 3, 5, 4 };
  const vtkIdType front[4] = { 0, 3, 4, 1 }, bottom[4] = { 0, 2, 5, 3 }, hyp[4] = { 1, 4, 5, 2 };
  polys->InsertNextCell(3, left);
  polys->InsertNextCell(3, right);
  polys->InsertNextCell(4, front);
  polys->InsertNextCell(4, bottom);
  polys->InsertNextCell(4, hyp);
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(pts);
  poly->SetPolys(polys);
  return poly;
}
}

int TestWhittedRefraction(int argc, char* argv[])
{
  using namespace whittedtest;
  vtkNew<vtkRenderer> ren;
  auto win = MakeWindow(300, 220);
  win->AddRenderer(ren);

  // Checkerboard wall behind (plane z = -3) and a floor
  const double o[3] = { -4, -1.5, -3 }, p1[3] = { 4, -1.5, -3 }, p2[3] = { -4, 4, -3 };
  const double c0[3] = { 0.1, 0.2, 0.7 }, c1[3] = { 0.95, 0.95, 0.9 };
  vtkNew<vtkPolyDataMapper> wallMapper;
  wallMapper->SetInputData(Checkerboard(o, p1, p2, 16, 11, c0, c1));
  wallMapper->SetScalarModeToUseCellData();
  vtkNew<vtkActor> wall;
  wall->SetMapper(wallMapper);
  wall->GetProperty()->SetAmbient(0.3);
  wall->GetProperty()->SetDiffuse(0.7);
  ren->AddActor(wall);
  ren->AddActor(Floor(4.0, 8, -1.5));

  // Prism raised above the floor, front face toward the camera
  vtkNew<vtkPolyDataMapper> prismMapper;
  prismMapper->SetInputData(Prism(1.5, 0.9));
  vtkNew<vtkActor> prism;
  prism->SetMapper(prismMapper);
  prism->SetPosition(-1.4, -0.4, -0.8);
  prism->GetProperty()->SetColor(1, 1, 1);
  prism->GetProperty()->SetDiffuse(0.0);
  prism->GetProperty()->SetSpecular(0.6);
  prism->GetProperty()->SetSpecularPower(80);
  SetWhitted(prism->GetProperty(), 0.0, 0.95, 1.5);
  ren->AddActor(prism);

  auto ball = Sphere(1.3, 0.0, 0.0, 0.9, 40);
  ball->GetProperty()->SetDiffuse(0.0);
  ball->GetProperty()->SetSpecular(0.7);
  ball->GetProperty()->SetSpecularPower(100);
  SetWhitted(ball->GetProperty(), 0.05, 0.9, 1.5);
  ren->AddActor(ball);

  vtkNew<vtkLight> light;
  light->SetLightTypeToSceneLight();
  light->SetPosition(2.0, 5.0, 6.0);
  light->SetFocalPoint(0, 0, 0);
  ren->AddLight(light);
  ren->SetBackground(0.3, 0.3, 0.3);

  LookAt(ren, { 0.0, 0.8, 7.0 }, { 0.0, 0.2, 0.0 }, 40);

  vtkNew<vtkWhittedPass> pass;
  ApplyTestSwitches(pass);
  pass->SetMaxDepth(8);
  ren->SetPass(pass);
  win->Render();
  std::cout << pass->GetLastFrameReport();
  const int baseline = CheckBaseline(win, argc, argv);

  // Independent: VTK's raster of the same scene (CheckAgainstRaster) without the prism and the glass ball; their shadows are partial
  RasterOracle raster;
  raster.Excluded = { prism, ball };
  raster.MinShadowShare = 0.02;
  const bool independent = CheckAgainstRaster("Refraction", win, pass, raster);
  return baseline == EXIT_SUCCESS && independent ? EXIT_SUCCESS : EXIT_FAILURE;
}
