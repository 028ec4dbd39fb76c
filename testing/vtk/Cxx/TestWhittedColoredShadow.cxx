// Coloured shadows: light through a red transmissive slab (TRANSMITTANCE (1, 0.25, 0.25)) tints the
// floor red; a default translucent sphere (Opacity 0.4, so transmittance 0.6) casts a grey half
// shadow; an opaque sphere a full one. The slab's TRANSMITTANCE reaches 1 in red, so the energy rule
// leaves its own colour no share: seen through it, the scene is filtered by kt per crossing, plus the
// slab's highlight (weighted by its Opacity 0.25).
#include "WhittedTestUtilities.h"

#include "vtkCamera.h"
#include "vtkCubeSource.h"
#include "vtkLight.h"
#include "vtkRegressionTestImage.h"

#include <iostream>

int TestWhittedColoredShadow(int argc, char* argv[])
{
  using namespace whittedtest;
  vtkNew<vtkRenderer> ren;
  auto win = MakeWindow(300, 240);
  win->AddRenderer(ren);
  ren->AddActor(Floor(3.0, 6));

  vtkNew<vtkCubeSource> slab;
  slab->SetCenter(-1.0, 1.2, 0.0);
  slab->SetXLength(1.4);
  slab->SetYLength(0.1);
  slab->SetZLength(1.4);
  vtkNew<vtkPolyDataMapper> slabMapper;
  slabMapper->SetInputConnection(slab->GetOutputPort());
  vtkNew<vtkActor> glass;
  glass->SetMapper(slabMapper);
  glass->GetProperty()->SetColor(1.0, 0.2, 0.2);
  glass->GetProperty()->SetOpacity(0.25);
  glass->GetProperty()->SetSpecular(0.5);
  SetTransmittance(glass->GetProperty(), 1.0, 0.25, 0.25);
  ren->AddActor(glass);

  auto ghost = Sphere(0.6, 0.9, -0.6, 0.5, 24);
  ghost->GetProperty()->SetColor(0.4, 0.6, 1.0);
  ghost->GetProperty()->SetOpacity(0.4);
  ren->AddActor(ghost);

  auto solid = Sphere(1.2, 0.5, 1.0, 0.4, 24);
  solid->GetProperty()->SetColor(0.9, 0.9, 0.3);
  ren->AddActor(solid);

  AddPointLight(ren, -0.4, 5.0, 0.6);
  ren->SetBackground(0.2, 0.2, 0.25);

  LookAt(ren, { 0.0, 4.0, 5.5 }, { 0.0, 0.3, 0.0 }, 38);

  vtkNew<vtkWhittedPass> pass;
  ApplyTestSwitches(pass);
  ren->SetPass(pass);
  win->Render();
  std::cout << pass->GetLastFrameReport();
  const int baseline = CheckBaseline(win, argc, argv);

  // Independent: VTK's raster of the same scene (CheckAgainstRaster) without the translucent slab and sphere
  RasterOracle raster;
  raster.Excluded = { glass, ghost };
  raster.MinShadowShare = 0.08;
  raster.MinUmbraShare = 0.05;
  const bool independent = CheckAgainstRaster("ColoredShadow", win, pass, raster);
  return baseline == EXIT_SUCCESS && independent ? EXIT_SUCCESS : EXIT_FAILURE;
}
