// Caching: conversion and per-object BVH builds happen only for what changed. Camera-only and
// light-only changes rebuild nothing; moving an actor rebuilds only the top-level BVH over
// instances; a property change updates the material only; a changed input converts and rebuilds
// that geometry alone.
#include "WhittedTestUtilities.h"

#include "vtkCamera.h"
#include "vtkLight.h"

#include <cstdio>
#include <cstdlib>

namespace
{
bool Check(vtkRenderWindow* win, vtkWhittedPass* pass, const char* what, int converted, int rebuilt,
  bool top, int refit = 0)
{
  vtkWhittedFrameStatistics* stats = pass->GetLastFrameStatistics();
  win->Render();
  const bool ok = stats->GetNumberOfGeometriesConverted() == converted &&
    stats->GetNumberOfObjectsRebuilt() == rebuilt && stats->GetNumberOfObjectsRefit() == refit &&
    stats->GetTopLevelRebuilt() == top;
  std::printf(
    "%-40s converted %d (want %d), object BVHs %d (want %d), refit %d (want %d), top level %s (want %s)%s\n",
    what, stats->GetNumberOfGeometriesConverted(), converted, stats->GetNumberOfObjectsRebuilt(),
    rebuilt, stats->GetNumberOfObjectsRefit(), refit, stats->GetTopLevelRebuilt() ? "rebuilt" : "kept",
    top ? "rebuilt" : "kept", ok ? "" : "   <-- FAIL");
  return ok;
}
}

int TestWhittedCaching(int, char*[])
{
  using namespace whittedtest;
  vtkNew<vtkRenderer> ren;
  auto win = MakeWindow(120, 90);
  win->AddRenderer(ren);
  ren->AddActor(Floor(3.0, 4));

  vtkNew<vtkSphereSource> source;
  source->SetCenter(0, 1, 0);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputConnection(source->GetOutputPort());
  vtkNew<vtkActor> a;
  a->SetMapper(mapper);
  ren->AddActor(a);
  vtkNew<vtkActor> b; // shares the mapper: one geometry, two instances
  b->SetMapper(mapper);
  b->SetPosition(1.5, 0, 0);
  ren->AddActor(b);
  vtkNew<vtkLight> light;
  light->SetPositional(true);
  light->SetPosition(1, 4, 2);
  ren->AddLight(light);
  ren->GetActiveCamera()->SetPosition(0, 3, 6);
  ren->GetActiveCamera()->SetFocalPoint(0, 0.5, 0);

  vtkNew<vtkWhittedPass> pass;
  vtkWhittedFrameStatistics* stats = pass->GetLastFrameStatistics();
  ren->SetPass(pass);

  bool ok = true;
  ok &= Check(win, pass, "first frame", 2, 2, true);
  ok &= Check(win, pass, "nothing changed", 0, 0, false);
  ren->GetActiveCamera()->Azimuth(25);
  ren->GetActiveCamera()->Zoom(1.3);
  ok &= Check(win, pass, "camera moved", 0, 0, false);
  light->SetPosition(-2, 5, 1);
  light->SetIntensity(0.7);
  light->SetColor(1, 0.8, 0.8);
  ok &= Check(win, pass, "light changed", 0, 0, false);
  a->SetPosition(-1.0, 0.2, 0.3);
  a->RotateZ(10);
  ok &= Check(win, pass, "actor moved", 0, 0, true);
  a->GetProperty()->SetColor(1, 0, 0);
  a->GetProperty()->SetSpecular(0.5);
  SetWhitted(a->GetProperty(), 0.5);
  ok &= Check(win, pass, "property / Whitted keys changed", 0, 0, false);
  ren->SetBackground(0.3, 0.1, 0.1);
  ok &= Check(win, pass, "background changed", 0, 0, false);
  source->SetThetaResolution(12);
  ok &= Check(win, pass, "input changed (one shared geometry)", 1, 1, true);
  source->SetCenter(0, 1.1, 0);  // the same triangles, moved: boxes refit, no rebuild
  ok &= Check(win, pass, "points moved (same connectivity)", 1, 0, true, 1);
  vtkNew<vtkActor> c;
  c->SetMapper(mapper);
  c->SetPosition(0, 0, -1.5);
  ren->AddActor(c);
  ok &= Check(win, pass, "actor added (shared mapper)", 0, 0, true);
  ren->RemoveActor(b);
  ok &= Check(win, pass, "actor removed", 0, 0, true);
  c->GetProperty()->SetRepresentationToWireframe();
  c->GetProperty()->SetRenderLinesAsTubes(true);
  ok &= Check(win, pass, "representation changed (new geometry)", 1, 1, true);
  ok &= Check(win, pass, "nothing changed", 0, 0, false);

  // An actor outside the view frustum (VTK's culler drops it from the render state) is still
  // traced: it casts shadows and shows in mirrors
  const int traced = stats->GetNumberOfTracedActors();
  a->SetPosition(0, 0, 40); // behind the camera
  ok &= Check(win, pass, "actor moved out of view", 0, 0, true);
  if (stats->GetNumberOfTracedActors() != traced)
  {
    std::printf("an actor outside the view frustum was dropped (%d traced, want %d)   <-- FAIL\n",
      stats->GetNumberOfTracedActors(), traced);
    ok = false;
  }
  return ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
