// Points as spheres: a lattice of vertices coloured by a point scalar through a lookup table, drawn
// with RenderPointsAsSpheres, and a sphere source in points representation; both cast shadows and
// show in a mirror.
#include "WhittedTestUtilities.h"

#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkDoubleArray.h"
#include "vtkLight.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkRegressionTestImage.h"

#include <iostream>

int TestWhittedPointsAsSpheres(int argc, char* argv[])
{
  using namespace whittedtest;
  vtkNew<vtkRenderer> ren;
  auto win = MakeWindow(300, 240);
  win->AddRenderer(ren);
  ren->AddActor(Floor(3.0, 6));

  // 5 x 3 x 3 lattice of vertex cells with a scalar = height
  vtkNew<vtkPoints> pts;
  vtkNew<vtkCellArray> verts;
  vtkNew<vtkDoubleArray> height;
  height->SetName("height");
  for (int k = 0; k < 3; ++k)
  {
    for (int j = 0; j < 3; ++j)
    {
      for (int i = 0; i < 5; ++i)
      {
        const double p[3] = { -2.2 + 0.45 * i, 0.3 + 0.45 * j, -0.2 + 0.45 * k };
        const vtkIdType id = pts->InsertNextPoint(p);
        verts->InsertNextCell(1, &id);
        height->InsertNextValue(p[1] + 0.1 * i);
      }
    }
  }
  vtkNew<vtkPolyData> lattice;
  lattice->SetPoints(pts);
  lattice->SetVerts(verts);
  lattice->GetPointData()->SetScalars(height);
  vtkNew<vtkPolyDataMapper> latticeMapper;
  latticeMapper->SetInputData(lattice);
  latticeMapper->SetScalarRange(0.3, 1.6);
  vtkNew<vtkActor> points;
  points->SetMapper(latticeMapper);
  points->GetProperty()->SetRenderPointsAsSpheres(true);
  points->GetProperty()->SetPointSize(60);
  points->GetProperty()->SetSpecular(0.4);
  points->GetProperty()->SetSpecularPower(30);
  ren->AddActor(points);

  // A sphere source drawn as points (each mesh vertex a small sphere)
  auto dots = Sphere(1.3, 0.9, 0.2, 0.7, 10);
  dots->GetProperty()->SetRepresentationToPoints();
  dots->GetProperty()->SetRenderPointsAsSpheres(true);
  dots->GetProperty()->SetPointSize(60);
  dots->GetProperty()->SetColor(0.95, 0.8, 0.3);
  ren->AddActor(dots);

  // A mirror wall at the back
  const double o[3] = { -3, 0, -1.5 }, p1[3] = { 3, 0, -1.5 }, p2[3] = { -3, 2.5, -1.5 };
  const double c[3] = { 0.8, 0.8, 0.85 };
  vtkNew<vtkPolyDataMapper> mirrorMapper;
  mirrorMapper->SetInputData(Checkerboard(o, p1, p2, 1, 1, c, c));
  mirrorMapper->ScalarVisibilityOff();
  vtkNew<vtkActor> mirror;
  mirror->SetMapper(mirrorMapper);
  mirror->GetProperty()->SetColor(0.1, 0.1, 0.12);
  SetWhitted(mirror->GetProperty(), 0.85);
  ren->AddActor(mirror);

  AddPointLight(ren, 1.0, 5.0, 3.0);
  ren->SetBackground(0.2, 0.2, 0.25);
  LookAt(ren, { 0.8, 2.6, 5.5 }, { -0.2, 0.7, 0.0 }, 40);

  vtkNew<vtkWhittedPass> pass;
  ApplyTestSwitches(pass);
  vtkWhittedFrameStatistics* stats = pass->GetLastFrameStatistics();
  ren->SetPass(pass);
  win->Render();
  std::cout << pass->GetLastFrameReport();
  if (stats->GetNumberOfSpheres() != 45 + dots->GetMapper()->GetInput()->GetNumberOfPoints())
  {
    std::cerr << "expected one sphere per lattice point and per sphere-source point, got "
              << stats->GetNumberOfSpheres() << "\n";
    return EXIT_FAILURE;
  }
  const int baseline = CheckBaseline(win, argc, argv);

  // Independent: VTK's raster of the same scene (CheckAgainstRaster) without the spheres (VTK draws them as impostors) and the
  // mirror; their shadows fall under the spheres seen from here, so none is compared
  RasterOracle raster;
  raster.Excluded = { points, dots, mirror };
  const bool independent = CheckAgainstRaster("PointsAsSpheres", win, pass, raster);
  return baseline == EXIT_SUCCESS && independent ? EXIT_SUCCESS : EXIT_FAILURE;
}
