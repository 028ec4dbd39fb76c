// Scalar colouring exactly as the mapper maps it: left, point scalars (elevation) through the
// default lookup table; middle, the same with InterpolateScalarsBeforeMapping and a 6-colour table
// (sharp bands); right, cell scalars through a custom table with a narrowed scalar range
// (out-of-range values clamp).
#include "WhittedTestUtilities.h"

#include "vtkCamera.h"
#include "vtkCellData.h"
#include "vtkElevationFilter.h"
#include "vtkFloatArray.h"
#include "vtkLight.h"
#include "vtkLookupTable.h"
#include "vtkRegressionTestImage.h"

#include <iostream>

int TestWhittedScalarColors(int argc, char* argv[])
{
  using namespace whittedtest;
  vtkNew<vtkRenderer> ren;
  auto win = MakeWindow(300, 180);
  win->AddRenderer(ren);

  vtkNew<vtkSphereSource> source;
  source->SetThetaResolution(48);
  source->SetPhiResolution(24);
  source->SetRadius(0.9);
  vtkNew<vtkElevationFilter> elevation;
  elevation->SetInputConnection(source->GetOutputPort());
  elevation->SetLowPoint(0, -0.9, 0);
  elevation->SetHighPoint(0, 0.9, 0);

  // Left: point scalars, default lookup table, colours interpolated
  vtkNew<vtkPolyDataMapper> m1;
  m1->SetInputConnection(elevation->GetOutputPort());
  vtkNew<vtkActor> a1;
  a1->SetMapper(m1);
  a1->SetPosition(-2.0, 0, 0);
  a1->GetProperty()->SetSpecular(0.3);
  a1->GetProperty()->SetSpecularPower(20);
  ren->AddActor(a1);

  // Middle: scalars interpolated before mapping through a 6-colour table
  vtkNew<vtkLookupTable> bands;
  bands->SetNumberOfTableValues(6);
  bands->SetHueRange(0.8, 0.1);
  bands->Build();
  vtkNew<vtkPolyDataMapper> m2;
  m2->SetInputConnection(elevation->GetOutputPort());
  m2->SetLookupTable(bands);
  m2->InterpolateScalarsBeforeMappingOn();
  vtkNew<vtkActor> a2;
  a2->SetMapper(m2);
  a2->GetProperty()->SetAmbient(0.1);
  ren->AddActor(a2);

  // Right: cell scalars = cell index, custom table, range narrower than the data
  source->Update();
  vtkNew<vtkPolyData> cells;
  cells->DeepCopy(source->GetOutput());
  vtkNew<vtkFloatArray> cellIds;
  cellIds->SetName("cell");
  for (vtkIdType i = 0; i < cells->GetNumberOfCells(); ++i)
  {
    cellIds->InsertNextValue(static_cast<float>((i * 7) % 50));
  }
  cells->GetCellData()->SetScalars(cellIds);
  vtkNew<vtkLookupTable> custom;
  custom->SetNumberOfTableValues(4);
  custom->SetTableValue(0, 0.1, 0.1, 0.6);
  custom->SetTableValue(1, 0.2, 0.8, 0.8);
  custom->SetTableValue(2, 0.9, 0.9, 0.2);
  custom->SetTableValue(3, 0.9, 0.2, 0.1);
  vtkNew<vtkPolyDataMapper> m3;
  m3->SetInputData(cells);
  m3->SetLookupTable(custom);
  m3->SetScalarModeToUseCellData();
  m3->SetScalarRange(10, 40);
  vtkNew<vtkActor> a3;
  a3->SetMapper(m3);
  a3->SetPosition(2.0, 0, 0);
  ren->AddActor(a3);

  ren->SetBackground(0.25, 0.25, 0.3);
  LookAt(ren, { 0, 1.2, 6.5 }, { 0, 0, 0 }, 40);

  vtkNew<vtkWhittedPass> pass;
  ApplyTestSwitches(pass);
  ren->SetPass(pass);
  win->Render();
  std::cout << pass->GetLastFrameReport();
  const int baseline = CheckBaseline(win, argc, argv);

  // Independent: VTK's raster of the same scene (CheckAgainstRaster); lit by the headlight only: no visible shadow
  RasterOracle raster;
  const bool independent = CheckAgainstRaster("ScalarColors", win, pass, raster);
  return baseline == EXIT_SUCCESS && independent ? EXIT_SUCCESS : EXIT_FAILURE;
}
