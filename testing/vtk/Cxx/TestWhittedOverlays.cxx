// Overlays on top of the traced image: a vtkTextActor, a vtkScalarBarActor and an orientation-axes
// widget (vtkOrientationMarkerWidget with vtkAxesActor, drawn in its own OpenGL renderer) appear
// over a traced, scalar-coloured scene.
#include "WhittedTestUtilities.h"

#include "vtkAxesActor.h"
#include "vtkCamera.h"
#include "vtkElevationFilter.h"
#include "vtkLight.h"
#include "vtkOrientationMarkerWidget.h"
#include "vtkRegressionTestImage.h"
#include "vtkRenderWindowInteractor.h"
#include "vtkScalarBarActor.h"
#include "vtkTextActor.h"
#include "vtkTextProperty.h"

#include <iostream>

int TestWhittedOverlays(int argc, char* argv[])
{
  using namespace whittedtest;
  vtkNew<vtkRenderer> ren;
  auto win = MakeWindow(300, 240);
  win->AddRenderer(ren);
  vtkNew<vtkRenderWindowInteractor> iren;
  iren->SetRenderWindow(win);

  ren->AddActor(Floor(3.0, 6));
  vtkNew<vtkSphereSource> source;
  source->SetCenter(0, 1, 0);
  source->SetThetaResolution(48);
  source->SetPhiResolution(24);
  vtkNew<vtkElevationFilter> elevation;
  elevation->SetInputConnection(source->GetOutputPort());
  elevation->SetLowPoint(0, 0.5, 0);
  elevation->SetHighPoint(0, 1.5, 0);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputConnection(elevation->GetOutputPort());
  vtkNew<vtkActor> ball;
  ball->SetMapper(mapper);
  ball->GetProperty()->SetSpecular(0.4);
  ball->GetProperty()->SetSpecularPower(30);
  ren->AddActor(ball);

  vtkNew<vtkTextActor> text;
  text->SetInput("Whitted");
  text->GetTextProperty()->SetFontSize(28);
  text->GetTextProperty()->SetColor(1.0, 1.0, 0.2);
  text->GetTextProperty()->BoldOn();
  text->SetDisplayPosition(10, 200);
  ren->AddActor2D(text);

  vtkNew<vtkScalarBarActor> bar;
  mapper->Update();
  bar->SetLookupTable(mapper->GetLookupTable());
  bar->SetNumberOfLabels(3);
  bar->SetWidth(0.12);
  bar->SetHeight(0.6);
  bar->SetPosition(0.86, 0.2);
  ren->AddActor2D(bar);

  vtkNew<vtkAxesActor> axes;
  vtkNew<vtkOrientationMarkerWidget> widget;
  widget->SetOrientationMarker(axes);
  widget->SetInteractor(iren);
  widget->SetViewport(0.0, 0.0, 0.3, 0.3);
  widget->SetEnabled(1);
  widget->InteractiveOff();

  AddPointLight(ren, -2.0, 5.0, 3.0);
  ren->SetBackground(0.2, 0.25, 0.3);
  LookAt(ren, { 1.0, 3.0, 5.5 }, { 0.0, 0.7, 0.0 }, 40);

  vtkNew<vtkWhittedPass> pass;
  ApplyTestSwitches(pass);
  ren->SetPass(pass);
  win->Render();
  std::cout << pass->GetLastFrameReport();
  if (pass->GetLastFrameStatistics()->GetNumberOfOpenGLProps() != 2)
  {
    std::cerr << "expected the text and the scalar bar drawn by OpenGL\n";
    return EXIT_FAILURE;
  }
  const int baseline = CheckBaseline(win, argc, argv);

  // Independent: VTK's raster of the same scene (CheckAgainstRaster); the overlays are OpenGL in both
  RasterOracle raster;
  raster.MinShadowShare = 0.02;
  raster.MinUmbraShare = 0.5;
  const bool independent = CheckAgainstRaster("Overlays", win, pass, raster);
  return baseline == EXIT_SUCCESS && independent ? EXIT_SUCCESS : EXIT_FAILURE;
}
