// Lines as tubes: a helix polyline coloured by a point scalar (RenderLinesAsTubes, LineWidth), and
// a sphere in wireframe representation with tubes; shadows on the floor. A plain-line actor without
// tubes is left to OpenGL and composited by depth.
#include "WhittedTestUtilities.h"

#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkDoubleArray.h"
#include "vtkLight.h"
#include "vtkLineSource.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkRegressionTestImage.h"

#include <cmath>
#include <iostream>

int TestWhittedLinesAsTubes(int argc, char* argv[])
{
  using namespace whittedtest;
  vtkNew<vtkRenderer> ren;
  auto win = MakeWindow(300, 240);
  win->AddRenderer(ren);
  ren->AddActor(Floor(3.0, 6));

  // Helix
  vtkNew<vtkPoints> pts;
  vtkNew<vtkDoubleArray> t;
  t->SetName("t");
  const int n = 120;
  std::vector<vtkIdType> ids;
  for (int i = 0; i < n; ++i)
  {
    const double a = 6.0 * M_PI * i / (n - 1);
    ids.push_back(
      pts->InsertNextPoint(-1.0 + 0.6 * std::cos(a), 0.3 + 1.8 * i / (n - 1), 0.6 * std::sin(a)));
    t->InsertNextValue(i);
  }
  vtkNew<vtkCellArray> lines;
  lines->InsertNextCell(n, ids.data());
  vtkNew<vtkPolyData> helix;
  helix->SetPoints(pts);
  helix->SetLines(lines);
  helix->GetPointData()->SetScalars(t);
  vtkNew<vtkPolyDataMapper> helixMapper;
  helixMapper->SetInputData(helix);
  helixMapper->SetScalarRange(0, n - 1);
  vtkNew<vtkActor> helixActor;
  helixActor->SetMapper(helixMapper);
  helixActor->GetProperty()->SetRenderLinesAsTubes(true);
  helixActor->GetProperty()->SetLineWidth(25);
  helixActor->GetProperty()->SetSpecular(0.5);
  helixActor->GetProperty()->SetSpecularPower(40);
  ren->AddActor(helixActor);

  // Wireframe sphere with tubes
  auto cage = Sphere(1.1, 0.9, 0.0, 0.8, 8);
  cage->GetProperty()->SetRepresentationToWireframe();
  cage->GetProperty()->SetRenderLinesAsTubes(true);
  cage->GetProperty()->SetLineWidth(20);
  cage->GetProperty()->SetColor(0.9, 0.75, 0.3);
  cage->GetProperty()->SetSpecular(0.6);
  cage->GetProperty()->SetSpecularPower(50);
  ren->AddActor(cage);

  // A plain line (no tubes): drawn by OpenGL
  vtkNew<vtkLineSource> line;
  line->SetPoint1(-2.5, 0.05, 1.5);
  line->SetPoint2(2.5, 0.05, 1.5);
  vtkNew<vtkPolyDataMapper> lineMapper;
  lineMapper->SetInputConnection(line->GetOutputPort());
  vtkNew<vtkActor> plain;
  plain->SetMapper(lineMapper);
  plain->GetProperty()->SetColor(0.1, 0.9, 0.2);
  plain->GetProperty()->SetLineWidth(3);
  ren->AddActor(plain);

  AddPointLight(ren, -1.0, 5.0, 3.0);
  ren->SetBackground(0.2, 0.2, 0.25);
  LookAt(ren, { 0.5, 2.8, 5.5 }, { 0.0, 0.8, 0.0 }, 40);

  vtkNew<vtkWhittedPass> pass;
  ApplyTestSwitches(pass);
  vtkWhittedFrameStatistics* stats = pass->GetLastFrameStatistics();
  ren->SetPass(pass);
  win->Render();
  std::cout << pass->GetLastFrameReport();
  if (stats->GetNumberOfOpenGLProps() != 1 || stats->GetNumberOfTubes() < vtkTypeUInt64(n - 1))
  {
    std::cerr << "expected the plain line drawn by OpenGL and the helix as tubes\n";
    return EXIT_FAILURE;
  }
  const int baseline = CheckBaseline(win, argc, argv);

  // Independent: VTK's raster of the same scene (CheckAgainstRaster) without the tubes (VTK draws them as impostors); the plain line is OpenGL in both
  RasterOracle raster;
  raster.Excluded = { helixActor, cage };
  raster.MinShadowShare = 0.04;
  raster.MinUmbraShare = 0.5;
  const bool independent = CheckAgainstRaster("LinesAsTubes", win, pass, raster);
  return baseline == EXIT_SUCCESS && independent ? EXIT_SUCCESS : EXIT_FAILURE;
}
