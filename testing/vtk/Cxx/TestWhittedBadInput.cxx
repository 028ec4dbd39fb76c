// Bad input does not break a frame: non-finite points are skipped (counted in the frame report,
// one warning for the actor), out-of-range Whitted keys are clamped with one warning per actor (not
// one per frame), and empty inputs or a mapper without input are ignored. The keys are set through
// vtkWhittedPass's compatibility key functions, which must return vtkWhittedMaterialKeys's keys.
// Every kind of bad input, case by case against a clean reference, is in TestWhittedBadInputCases.
#include "WhittedTestUtilities.h"

#include "vtkCallbackCommand.h"
#include "vtkCommand.h"
#include "vtkMath.h"
#include "vtkPoints.h"

#include <cstdio>
#include <cstdlib>
#include <string>

namespace
{
void CountWarning(vtkObject*, unsigned long, void* clientData, void* callData)
{
  ++*static_cast<int*>(clientData);
  std::printf("warning: %s", static_cast<const char*>(callData));
}
}

int TestWhittedBadInput(int, char*[])
{
  using namespace whittedtest;
  vtkNew<vtkRenderer> ren;
  auto win = MakeWindow(100, 80);
  win->AddRenderer(ren);

  // A sphere with a NaN and an infinite point
  vtkNew<vtkSphereSource> source;
  source->Update();
  vtkNew<vtkPolyData> broken;
  broken->DeepCopy(source->GetOutput());
  broken->GetPoints()->SetPoint(5, vtkMath::Nan(), 0.0, 0.0);
  broken->GetPoints()->SetPoint(9, 0.0, vtkMath::Inf(), 0.0);
  vtkNew<vtkPolyDataMapper> brokenMapper;
  brokenMapper->SetInputData(broken);
  vtkNew<vtkActor> a;
  a->SetMapper(brokenMapper);
  ren->AddActor(a);

  // Out-of-range Whitted terms, set through the compatibility spelling vtkWhittedPass::KEY(): the
  // very same key objects as vtkWhittedMaterialKeys::KEY() (checked here), so the pass reads them
  auto b = Sphere(1.5, 0, 0, 0.5, 8);
  double kr = 3.0;
  b->GetProperty()->GetInformation()->Set(vtkWhittedPass::REFLECTANCE(), &kr, 1);
  b->GetProperty()->GetInformation()->Set(vtkWhittedPass::INDEX_OF_REFRACTION(), -2.0);
  ren->AddActor(b);
  const bool sameKeys = vtkWhittedPass::REFLECTANCE() == vtkWhittedMaterialKeys::REFLECTANCE() &&
    vtkWhittedPass::TRANSMITTANCE() == vtkWhittedMaterialKeys::TRANSMITTANCE() &&
    vtkWhittedPass::INDEX_OF_REFRACTION() == vtkWhittedMaterialKeys::INDEX_OF_REFRACTION() &&
    vtkWhittedPass::ATTENUATION_COLOR() == vtkWhittedMaterialKeys::ATTENUATION_COLOR() &&
    vtkWhittedPass::ATTENUATION_DISTANCE() == vtkWhittedMaterialKeys::ATTENUATION_DISTANCE() &&
    vtkWhittedPass::RADIUS_ARRAY() == vtkWhittedMaterialKeys::RADIUS_ARRAY() &&
    vtkWhittedPass::RADIUS_FUNCTION() == vtkWhittedMaterialKeys::RADIUS_FUNCTION();
  std::printf("vtkWhittedPass's key functions return vtkWhittedMaterialKeys's keys: %s\n",
    sameKeys ? "yes" : "NO");

  // Empty input, and a mapper with no input at all
  vtkNew<vtkPolyData> empty;
  vtkNew<vtkPolyDataMapper> emptyMapper;
  emptyMapper->SetInputData(empty);
  vtkNew<vtkActor> c;
  c->SetMapper(emptyMapper);
  ren->AddActor(c);
  vtkNew<vtkPolyDataMapper> noInput;
  vtkNew<vtkActor> d;
  d->SetMapper(noInput);
  ren->AddActor(d);

  vtkNew<vtkWhittedPass> pass;
  ren->SetPass(pass);
  int warnings = 0;
  vtkNew<vtkCallbackCommand> cb;
  cb->SetCallback(CountWarning);
  cb->SetClientData(&warnings);
  pass->AddObserver(vtkCommand::WarningEvent, cb);

  win->Render();
  const std::string report = pass->GetLastFrameReport(); // the first frame built the objects
  std::printf("%s", report.c_str());
  win->Render();
  win->Render();
  // Two warnings over three frames: the NaN/Inf points of a, the Whitted keys of b
  bool ok = warnings == 2 && pass->GetLastFrameStatistics()->GetPrimaryRays() == 100u * 80u;
  ok &=
    report.find(" 0 invalid skipped") == std::string::npos; // the NaN/Inf triangles were counted
  if (!ok)
  {
    std::printf("expected exactly two warnings (got %d) and a complete frame\n", warnings);
  }
  return ok && sameKeys ? EXIT_SUCCESS : EXIT_FAILURE;
}
