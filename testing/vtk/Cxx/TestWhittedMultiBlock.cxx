// vtkCompositePolyDataMapper2 over a multiblock dataset: every visible leaf block becomes an
// instance; block display attributes apply (a colour override, a colour inherited by a nested
// block, an opacity that lets the block transmit light, a hidden block); a block with scalars keeps
// its scalar colours.
#include "WhittedTestUtilities.h"

#include "vtkCamera.h"
#include "vtkCompositeDataDisplayAttributes.h"
#include "vtkCompositePolyDataMapper2.h"
#include "vtkConeSource.h"
#include "vtkElevationFilter.h"
#include "vtkLight.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkRegressionTestImage.h"

#include <iostream>

namespace
{
vtkSmartPointer<vtkPolyData> SpherePoly(double x, double y, double z, double r)
{
  vtkNew<vtkSphereSource> s;
  s->SetCenter(x, y, z);
  s->SetRadius(r);
  s->SetThetaResolution(32);
  s->SetPhiResolution(16);
  s->Update();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->ShallowCopy(s->GetOutput());
  return out;
}
}

int TestWhittedMultiBlock(int argc, char* argv[])
{
  using namespace whittedtest;
  vtkNew<vtkRenderer> ren;
  auto win = MakeWindow(300, 220);
  win->AddRenderer(ren);
  ren->AddActor(Floor(3.0, 6));

  auto red = SpherePoly(-1.6, 0.5, 0.0, 0.5);
  auto hidden = SpherePoly(0.0, 2.0, 0.0, 0.5);
  vtkNew<vtkConeSource> coneSource;
  coneSource->SetCenter(-0.4, 0.6, 0.6);
  coneSource->SetDirection(0, 1, 0);
  coneSource->SetHeight(1.2);
  coneSource->SetRadius(0.5);
  coneSource->SetResolution(32);
  coneSource->Update();
  vtkNew<vtkElevationFilter> elevation;
  elevation->SetInputData(SpherePoly(0.9, 0.6, -0.3, 0.6));
  elevation->SetLowPoint(0, 0.0, 0);
  elevation->SetHighPoint(0, 1.2, 0);
  elevation->Update();
  auto nestedA = SpherePoly(1.9, 0.35, 0.9, 0.35);
  auto nestedB = SpherePoly(2.1, 0.35, -0.6, 0.35);

  vtkNew<vtkMultiBlockDataSet> nested;
  nested->SetNumberOfBlocks(2);
  nested->SetBlock(0, nestedA);
  nested->SetBlock(1, nestedB);
  vtkNew<vtkMultiBlockDataSet> root;
  root->SetNumberOfBlocks(5);
  root->SetBlock(0, red);
  root->SetBlock(1, hidden);
  root->SetBlock(2, coneSource->GetOutput());
  root->SetBlock(3, elevation->GetOutput());
  root->SetBlock(4, nested);

  vtkNew<vtkCompositePolyDataMapper2> mapper;
  mapper->SetInputDataObject(root);
  vtkNew<vtkCompositeDataDisplayAttributes> attrs;
  mapper->SetCompositeDataDisplayAttributes(attrs);
  attrs->SetBlockColor(red, vtkColor3d(0.9, 0.1, 0.1).GetData());
  attrs->SetBlockVisibility(hidden, false);
  attrs->SetBlockOpacity(coneSource->GetOutput(), 0.35);
  attrs->SetBlockColor(coneSource->GetOutput(), vtkColor3d(0.3, 0.5, 1.0).GetData());
  attrs->SetBlockColor(nested, vtkColor3d(0.95, 0.8, 0.2).GetData());

  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(0.8, 0.8, 0.8);
  actor->GetProperty()->SetSpecular(0.4);
  actor->GetProperty()->SetSpecularPower(30);
  ren->AddActor(actor);

  AddPointLight(ren, -1.0, 5.0, 3.0);
  ren->SetBackground(0.2, 0.2, 0.25);
  LookAt(ren, { 0.0, 3.0, 5.5 }, { 0.0, 0.5, 0.0 }, 40);

  vtkNew<vtkWhittedPass> pass;
  ApplyTestSwitches(pass);
  vtkWhittedFrameStatistics* stats = pass->GetLastFrameStatistics();
  ren->SetPass(pass);
  win->Render();
  std::cout << pass->GetLastFrameReport();
  // Floor + 5 visible leaf blocks
  if (stats->GetNumberOfGeometriesConverted() != 6)
  {
    std::cerr << "expected 6 converted geometries, got " << stats->GetNumberOfGeometriesConverted()
              << "\n";
    return EXIT_FAILURE;
  }
  const int baseline = CheckBaseline(win, argc, argv);

  // Independent: VTK's raster of the same scene (CheckAgainstRaster); the translucent cone block hidden through its block visibility
  RasterOracle raster;
  raster.Hide = [&](bool hide)
  {
    attrs->SetBlockVisibility(coneSource->GetOutput(), !hide);
    mapper->Modified();
  };
  raster.MinShadowShare = 0.02;
  raster.MinUmbraShare = 0.5;
  const bool independent = CheckAgainstRaster("MultiBlock", win, pass, raster);
  return baseline == EXIT_SUCCESS && independent ? EXIT_SUCCESS : EXIT_FAILURE;
}
