// Progress and abort: a render invokes StartEvent, ProgressEvent (increasing fractions up to 1) and
// EndEvent on the pass; a long trace honours the render window's abort check (AbortCheckEvent ->
// SetAbortRender): the pass calls vtkRenderWindow::CheckAbortStatus between tiles.
#include "WhittedTestUtilities.h"

#include "vtkCallbackCommand.h"
#include "vtkCamera.h"
#include "vtkCommand.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <thread>
#include <vector>

namespace
{
struct Log
{
  int Start = 0, End = 0;
  std::vector<double> Progress;
  int AbortChecks = 0;
  int AbortAfter = -1; // abort at this many checks (-1: never)
};

void OnPassEvent(vtkObject*, unsigned long event, void* clientData, void* callData)
{
  auto* log = static_cast<Log*>(clientData);
  if (event == vtkCommand::StartEvent)
  {
    ++log->Start;
  }
  else if (event == vtkCommand::EndEvent)
  {
    ++log->End;
  }
  else if (event == vtkCommand::ProgressEvent)
  {
    log->Progress.push_back(*static_cast<double*>(callData));
  }
}

void OnAbortCheck(vtkObject* caller, unsigned long, void* clientData, void*)
{
  auto* log = static_cast<Log*>(clientData);
  if (++log->AbortChecks == log->AbortAfter)
  {
    static_cast<vtkRenderWindow*>(caller)->SetAbortRender(1);
  }
}
}

int TestWhittedEvents(int, char*[])
{
  using namespace whittedtest;
  vtkNew<vtkRenderer> ren;
  auto win = MakeWindow(160, 120);
  win->AddRenderer(ren);
  ren->AddActor(Floor(3.0, 4));
  auto ball = Sphere(0, 1, 0, 1, 24);
  SetWhitted(ball->GetProperty(), 0.5);
  ren->AddActor(ball);
  vtkNew<vtkWhittedPass> pass;
  vtkWhittedFrameStatistics* stats = pass->GetLastFrameStatistics();
  pass->SetNumberOfThreads(1);
  ren->SetPass(pass);

  Log log;
  vtkNew<vtkCallbackCommand> passCb;
  passCb->SetCallback(OnPassEvent);
  passCb->SetClientData(&log);
  pass->AddObserver(vtkCommand::StartEvent, passCb);
  pass->AddObserver(vtkCommand::ProgressEvent, passCb);
  pass->AddObserver(vtkCommand::EndEvent, passCb);
  vtkNew<vtkCallbackCommand> abortCb;
  abortCb->SetCallback(OnAbortCheck);
  abortCb->SetClientData(&log);
  win->AddObserver(vtkCommand::AbortCheckEvent, abortCb);

  bool ok = true;
  win->Render();
  const bool monotone = std::is_sorted(log.Progress.begin(), log.Progress.end());
  std::printf("full frame: start %d, end %d, %zu progress events (last %.3f), %d abort checks\n",
    log.Start, log.End, log.Progress.size(), log.Progress.empty() ? -1.0 : log.Progress.back(),
    log.AbortChecks);
  ok &= log.Start == 1 && log.End == 1 && log.Progress.size() > 10 && monotone &&
    !log.Progress.empty() && log.Progress.back() == 1.0 && log.AbortChecks >= 1 &&
    !stats->GetAborted() && stats->GetPrimaryRays() == 160u * 120u;

  // Abort at the first check (vtkRenderWindow runs the check at most 5 times a second, so the first
  // one comes after the first tile): the frame stops early and says so
  log = Log();
  log.AbortAfter = 1;
  std::this_thread::sleep_for(std::chrono::milliseconds(250)); // let the throttle allow a check
  ren->GetActiveCamera()->Azimuth(10);
  win->Render();
  std::printf("aborted frame: aborted %d, primary rays %llu of %d, abort checks %d\n",
    int(stats->GetAborted()), static_cast<unsigned long long>(stats->GetPrimaryRays()), 160 * 120,
    log.AbortChecks);
  ok &= stats->GetAborted() && stats->GetPrimaryRays() < 160u * 120u / 2;
  win->SetAbortRender(0);
  return ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
