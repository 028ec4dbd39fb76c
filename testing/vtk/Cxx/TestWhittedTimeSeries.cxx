// Time series: each time step converts and builds only what changed. An actor whose input does not
// change keeps its object and BVH; a step that only moves points refits the BVH (also when the
// step's data arrives as a new data object, as ParaView hands it over), and the refitted tree
// gives the image a fresh build gives; a step with new connectivity (a contour of another value)
// is rebuilt. The time cache keeps what a user comes back to: the sphere's steps carry a time
// (DATA_TIME_STEP, as a reader's steps do) and are kept as the time moves on; the contour comes from
// a pipeline without time, so its contents are kept only once they are shown again. Replaying the
// steps restores the sphere from the time cache and converts the contour once more; a second replay
// restores both: nothing converted or built, the same images as the first pass. Dragging the
// contour value through new values keeps nothing. With the time cache off, replaying converts
// again.
#include "WhittedTestUtilities.h"

#include "vtkContourFilter.h"
#include "vtkElevationFilter.h"
#include "vtkRTAnalyticSource.h"
#include "vtkTransform.h"
#include "vtkTransformFilter.h"

#include <cstdio>
#include <cstdlib>

namespace
{
struct Counts
{
  int Converted, Rebuilt, Refit, Hits;
};

bool Check(vtkRenderWindow* win, vtkWhittedPass* pass, const char* what, const Counts& want)
{
  vtkWhittedFrameStatistics* stats = pass->GetLastFrameStatistics();
  win->Render();
  const Counts got{ stats->GetNumberOfGeometriesConverted(), stats->GetNumberOfObjectsRebuilt(),
    stats->GetNumberOfObjectsRefit(), stats->GetNumberOfTimeCacheHits() };
  const bool ok = got.Converted == want.Converted && got.Rebuilt == want.Rebuilt &&
    got.Refit == want.Refit && got.Hits == want.Hits;
  std::printf("%-34s converted %d (want %d), rebuilt %d (want %d), refit %d (want %d), cache hits "
              "%d (want %d); cache holds %d geometries, %.2f MB%s\n",
    what, got.Converted, want.Converted, got.Rebuilt, want.Rebuilt, got.Refit, want.Refit, got.Hits,
    want.Hits, stats->GetNumberOfTimeCacheEntries(),
    static_cast<double>(stats->GetTimeCacheBytes()) / (1 << 20), ok ? "" : "   <-- FAIL");
  return ok;
}

std::vector<float> Image(vtkWhittedPass* pass)
{
  vtkNew<vtkFloatArray> rgba;
  pass->GetLastFrame(rgba, nullptr);
  const float* p = rgba->GetPointer(0);
  return std::vector<float>(p, p + rgba->GetNumberOfValues());
}

bool SameImage(const std::vector<float>& a, const std::vector<float>& b, const char* what)
{
  std::size_t differ = a.size() == b.size() ? 0 : a.size() + b.size();
  for (std::size_t i = 0; differ == 0 && i < a.size(); ++i)
  {
    differ += a[i] != b[i];
  }
  std::printf("%-34s %s (%zu values differ)\n", what,
    differ == 0 ? "identical" : "DIFFERENT   <-- FAIL", differ);
  return differ == 0 && !a.empty();
}
}

int TestWhittedTimeSeries(int, char*[])
{
  using namespace whittedtest;
  vtkNew<vtkRenderer> ren;
  auto win = MakeWindow(160, 120);
  win->AddRenderer(ren);
  ren->AddActor(Floor(3.0, 6)); // never changes
  AddPointLight(ren, 1.0, 5.0, 3.0);

  // A sphere deforming over time (same connectivity), coloured by elevation through a colour map;
  // each step's data is handed to the mapper as a new data object
  vtkNew<vtkSphereSource> sphere;
  sphere->SetThetaResolution(24);
  sphere->SetPhiResolution(16);
  vtkNew<vtkTransform> motion;
  vtkNew<vtkTransformFilter> move;
  move->SetInputConnection(sphere->GetOutputPort());
  move->SetTransform(motion);
  vtkNew<vtkElevationFilter> elevation;
  elevation->SetInputConnection(move->GetOutputPort());
  elevation->SetLowPoint(0, 0, 0);
  elevation->SetHighPoint(0, 2, 0);
  vtkNew<vtkPolyDataMapper> sphereMapper;
  sphereMapper->InterpolateScalarsBeforeMappingOn();
  vtkNew<vtkActor> sphereActor;
  sphereActor->SetMapper(sphereMapper);
  ren->AddActor(sphereActor);

  // An isosurface whose value changes over time (new connectivity every step), fed by a pipeline
  vtkNew<vtkRTAnalyticSource> wavelet;
  wavelet->SetWholeExtent(-8, 8, -8, 8, -8, 8);
  vtkNew<vtkContourFilter> contour;
  contour->SetInputConnection(wavelet->GetOutputPort());
  vtkNew<vtkPolyDataMapper> contourMapper;
  contourMapper->SetInputConnection(contour->GetOutputPort());
  contourMapper->ScalarVisibilityOff();
  vtkNew<vtkActor> contourActor;
  contourActor->SetMapper(contourMapper);
  contourActor->SetScale(0.12);
  contourActor->SetPosition(-1.6, 1.0, 0.0);
  ren->AddActor(contourActor);
  LookAt(ren, { 0.0, 3.0, 6.0 }, { 0.0, 0.6, 0.0 }, 40.0);

  auto setStep = [&](int k)
  {
    motion->Identity();
    motion->Translate(0.6, 0.9 + 0.1 * k, 0.0);
    motion->Scale(1.0 + 0.15 * k, 1.0 - 0.1 * k, 1.0);
    elevation->Update();
    vtkNew<vtkPolyData> step; // a new object per step, as ParaView delivers time steps
    step->DeepCopy(elevation->GetOutput());
    step->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(), 0.5 * k);
    sphereMapper->SetInputData(step);
    contour->SetValue(0, 120.0 + 25.0 * k);
  };

  vtkNew<vtkWhittedPass> pass;
  ren->SetPass(pass);
  const int steps = 4;
  std::vector<std::vector<float>> images;
  bool ok = true;
  char what[64];

  // First pass over the steps: the floor is never converted again, the sphere refits, the contour
  // is rebuilt
  for (int k = 0; k < steps; ++k)
  {
    setStep(k);
    std::snprintf(what, sizeof what, "first pass, step %d", k);
    ok &= Check(win, pass, what, k == 0 ? Counts{ 3, 3, 0, 0 } : Counts{ 2, 1, 1, 0 });
    images.push_back(Image(pass));
  }

  // The refitted sphere traces like a freshly built one: a new pass builds everything again
  {
    vtkNew<vtkWhittedPass> fresh;
    ren->SetPass(fresh);
    ok &= Check(win, fresh, "fresh pass, last step", Counts{ 3, 3, 0, 0 });
    ok &= SameImage(Image(fresh), images.back(), "refit vs fresh build");
    ren->SetPass(pass);
  }

  // Replay: the sphere's steps come back from the time cache (the last one too: it was kept when
  // the first came back), the contour's are converted again (each shown a second time now, so kept
  // when replaced); the second replay restores both. Always the first pass's image.
  for (int replay = 1; replay <= 2; ++replay)
  {
    for (int k = 0; k < steps; ++k)
    {
      setStep(k);
      std::snprintf(what, sizeof what, "replay %d, step %d", replay, k);
      ok &= Check(win, pass, what, replay == 1 ? Counts{ 1, 1, 0, 1 } : Counts{ 0, 0, 0, 2 });
      std::snprintf(what, sizeof what, "replay %d image, step %d", replay, k);
      ok &= SameImage(Image(pass), images[k], what);
    }
  }
  // The same step again (a new data object with the same contents): nothing to do
  setStep(steps - 1);
  ok &= Check(win, pass, "same step again", Counts{ 0, 0, 0, 0 });

  // Dragging the contour value through values never shown: each converts, nothing more is kept
  // (the first new value replaces the last step's contour, which was shown again above and is
  // kept: the cache is compared from there)
  {
    int entries = 0;
    vtkTypeUInt64 bytes = 0;
    vtkWhittedFrameStatistics* stats = pass->GetLastFrameStatistics();
    for (int v = 0; v < 6; ++v)
    {
      contour->SetValue(0, 131.5 + 7.0 * v);
      std::snprintf(what, sizeof what, "contour drag, value %d", v);
      ok &= Check(win, pass, what, Counts{ 1, 1, 0, 0 });
      if (v == 0)
      {
        entries = stats->GetNumberOfTimeCacheEntries();
        bytes = stats->GetTimeCacheBytes();
      }
    }
    if (stats->GetNumberOfTimeCacheEntries() != entries || stats->GetTimeCacheBytes() != bytes)
    {
      std::printf("contour drag: the time cache went from %d entries (%llu bytes) to %d (%llu)   "
                  "<-- FAIL\n",
        entries, static_cast<unsigned long long>(bytes), stats->GetNumberOfTimeCacheEntries(),
        static_cast<unsigned long long>(stats->GetTimeCacheBytes()));
      ok = false;
    }
  }

  // Time cache off: it is emptied, and replaying converts again
  pass->SetTimeCacheMemory(0);
  setStep(0);
  ok &= Check(win, pass, "cache off, step 0", Counts{ 2, 1, 1, 0 });
  if (pass->GetLastFrameStatistics()->GetNumberOfTimeCacheEntries() != 0)
  {
    std::printf("the time cache still holds geometries with TimeCacheMemory 0   <-- FAIL\n");
    ok = false;
  }
  ok &= SameImage(Image(pass), images[0], "cache off image, step 0");
  return ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
