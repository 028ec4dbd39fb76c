#include "vtkPVWhittedView.h"

#include "vtkCommand.h"
#include "vtkMultiProcessController.h"
#include "vtkMultiProcessStream.h"
#include "vtkPVSession.h"
#include "vtkPVWhittedPass.h"
#include "vtkProcessModule.h"
#include "vtkRenderWindowInteractor.h"
#include "vtkTextActor.h"
#include "vtkWhittedFrameStatistics.h"

#include <algorithm>
#include <cstdio>

// The view's display of refinement (see vtkPVWhittedView.h): progressive display (rendering again
// until a still frame's refinement is over) and the error annotation, relayed from a server to its
// client. Construction, settings and the frame itself: vtkPVWhittedView.cxx.

//------------------------------------------------------------------------------
// Progressive display
//------------------------------------------------------------------------------
int vtkPVWhittedView::ProgressiveRoundsForFrame(bool interactive)
{
  if (interactive || !this->ProgressiveDisplay || this->GetInCaptureScreenshot())
  {
    return 0; // screenshots are refined fully
  }
  if (this->RefinementRoundsPerRender > 0)
  {
    return this->RefinementRoundsPerRender;
  }
  // Automatic: one round per frame where the view can render again by itself: the GUI, whose Qt
  // interactor runs timers in the application's event loop (pvbatch and pvpython have interactors
  // too, but nothing runs their timers); scripts get the whole refinement in one render
  vtkRenderWindowInteractor* iren = this->GetInteractor();
  return iren && iren->IsA("QVTKInteractor") ? 1 : 0;
}

//------------------------------------------------------------------------------
void vtkPVWhittedView::AfterTracedFrame(bool interactive, int vtkNotUsed(reduction))
{
  vtkWhittedFrameStatistics* stats = this->WhittedPass->GetLastFrameStatistics();
  this->RefinementUnfinished =
    !interactive && !stats->GetFailed() && !stats->GetRefinementFinished();
  // In the GUI: render again soon (ParaView's interactor helper turns the interactor's render
  // into a still render of this view's proxy), unless an earlier timer is still pending
  vtkRenderWindowInteractor* iren = this->GetInteractor();
  if (this->RefinementUnfinished && this->RefinementRoundsPerRender == 0 &&
    this->ProgressiveRoundsForFrame(false) > 0 && this->ProgressiveTimerId < 0)
  {
    this->ProgressiveTimerId = iren->CreateOneShotTimer(1);
  }
}

//------------------------------------------------------------------------------
void vtkPVWhittedView::SetupInteractor(vtkRenderWindowInteractor* iren)
{
  this->DetachInteractor();
  this->Superclass::SetupInteractor(iren);
  if (iren)
  {
    this->InteractorObservers[0] =
      iren->AddObserver(vtkCommand::TimerEvent, this, &vtkPVWhittedView::OnInteractorEvent);
    this->InteractorObservers[1] = iren->AddObserver(
      vtkCommand::StartInteractionEvent, this, &vtkPVWhittedView::OnInteractorEvent);
  }
}

//------------------------------------------------------------------------------
void vtkPVWhittedView::DetachInteractor()
{
  if (vtkRenderWindowInteractor* iren = this->GetInteractor())
  {
    if (this->ProgressiveTimerId >= 0)
    {
      iren->DestroyTimer(this->ProgressiveTimerId);
    }
    for (unsigned long tag : this->InteractorObservers)
    {
      iren->RemoveObserver(tag);
    }
  }
  this->ProgressiveTimerId = -1;
  this->InteractorObservers[0] = this->InteractorObservers[1] = 0;
}

//------------------------------------------------------------------------------
void vtkPVWhittedView::OnInteractorEvent(vtkObject*, unsigned long event, void* callData)
{
  vtkRenderWindowInteractor* iren = this->GetInteractor();
  if (!iren || this->ProgressiveTimerId < 0)
  {
    return;
  }
  if (event == vtkCommand::StartInteractionEvent)
  {
    // Interaction interrupts progressive display at once (its frames start over anyway)
    iren->DestroyTimer(this->ProgressiveTimerId);
    this->ProgressiveTimerId = -1;
    return;
  }
  if (!callData || *static_cast<int*>(callData) != this->ProgressiveTimerId)
  {
    return; // another timer (e.g. ParaView's delayed still render)
  }
  this->ProgressiveTimerId = -1;
  if (this->RefinementUnfinished && this->ProgressiveDisplay)
  {
    iren->Render();
  }
}

//------------------------------------------------------------------------------
// Error annotation
//------------------------------------------------------------------------------
void vtkPVWhittedView::SetShowErrorAnnotation(bool value)
{
  if (this->ShowErrorAnnotation != value)
  {
    this->ShowErrorAnnotation = value;
    this->ErrorAnnotation->SetVisibility(value);
    this->Modified();
  }
}

//------------------------------------------------------------------------------
const char* vtkPVWhittedView::GetErrorAnnotationText()
{
  return this->ErrorAnnotationText.c_str();
}

//------------------------------------------------------------------------------
void vtkPVWhittedView::UpdateErrorAnnotation(bool interactive, int reduction)
{
  vtkWhittedFrameStatistics* stats = this->WhittedPass->GetLastFrameStatistics();
  char text[256];
  if (stats->GetFailed())
  {
    std::snprintf(text, sizeof text, "Whitted: frame failed");
  }
  else if (interactive)
  {
    std::snprintf(text, sizeof text, "Whitted: interactive frame %.0f ms at 1/%d resolution",
      stats->GetTotalTime() * 1e3, reduction);
  }
  else
  {
    const int* size = stats->GetSize();
    const double pixels = std::max(1.0, static_cast<double>(size[0]) * size[1]);
    const double spp = static_cast<double>(stats->GetNumberOfSamples()) / pixels;
    const double target = this->WhittedPass->GetTargetError();
    char status[96];
    if (target > 0.0)
    {
      std::snprintf(status, sizeof status, "target %.4g %s", target,
        stats->GetTargetErrorMet() ? "met" : "not met");
    }
    else
    {
      std::snprintf(status, sizeof status, "no target");
    }
    // With a budget: how much of it the frame has taken so far (over all its progressive renders)
    char budget[64] = "";
    if (this->WhittedPass->GetTimeBudget() > 0.0)
    {
      std::snprintf(budget, sizeof budget, ", %.1f of %g s", stats->GetRefinementSeconds(),
        this->WhittedPass->GetTimeBudget());
    }
    // How the refinement stands: going on, or over because nothing is left to refine (before the budget
    // is spent, or short of a target); otherwise it ended at the target or the budget, which the text shows
    const char* state = !stats->GetRefinementFinished() ? ", refining"
      : stats->GetRefinementExhausted()                 ? ", nothing left to refine"
                                                        : "";
    std::snprintf(text, sizeof text, "Whitted: %.0f ms, %.2f spp, error %.4f (RMS estimate)\n%s%s%s",
      stats->GetRefinementSeconds() * 1e3, spp, stats->GetRMSError()[0], status, budget, state);
  }
  this->ErrorAnnotationText = text;
  this->ErrorAnnotation->SetInput(text);
}

//------------------------------------------------------------------------------
int vtkPVWhittedView::ErrorAnnotationRelay(bool distributed)
{
  // Only when the server renders for the client (remote rendering), on the two processes that
  // exchange the image: the client and the server's root (satellites have no client controller).
  // Both take this decision from the same synchronized state, so a send always meets its receive.
  vtkPVSession* session = this->GetSession();
  vtkProcessModule* pm = vtkProcessModule::GetProcessModule();
  if (!distributed || this->GetMakingSelection() || !session || !pm)
  {
    return RelayNone;
  }
  switch (pm->GetProcessType())
  {
    case vtkProcessModule::PROCESS_CLIENT:
      return session->GetController(vtkPVSession::RENDER_SERVER_ROOT) ? RelayReceive : RelayNone;
    case vtkProcessModule::PROCESS_SERVER:
    case vtkProcessModule::PROCESS_RENDER_SERVER:
      return session->GetController(vtkPVSession::CLIENT) ? RelaySend : RelayNone;
    default:
      return RelayNone;
  }
}

//------------------------------------------------------------------------------
void vtkPVWhittedView::RelayErrorAnnotation(vtkObject*, unsigned long, void*)
{
  // The composited renderer has finished (the server traced and sent its image, the client received
  // it); the client's non-composited renderer, which draws the annotation, comes next
  const int relay = this->AnnotationRelay;
  this->AnnotationRelay = RelayNone;
  vtkPVSession* session = this->GetSession();
  if (relay == RelaySend)
  {
    vtkMultiProcessStream stream;
    stream << this->ErrorAnnotationText;
    session->GetController(vtkPVSession::CLIENT)->Send(stream, 1, ErrorAnnotationTag);
  }
  else if (relay == RelayReceive)
  {
    vtkMultiProcessStream stream;
    session->GetController(vtkPVSession::RENDER_SERVER_ROOT)->Receive(stream, 1, ErrorAnnotationTag);
    stream >> this->ErrorAnnotationText;
    this->ErrorAnnotation->SetInput(this->ErrorAnnotationText.c_str());
  }
}
