#include "vtkPVWhittedView.h"

#include "vtkAlgorithm.h"
#include "vtkCommand.h"
#include "vtkCommunicator.h"
#include "vtkMultiProcessController.h"
#include "vtkObjectFactory.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLState.h"
#include "vtkMultiProcessStream.h"
#include "vtkPVDataRepresentation.h"
#include "vtkPVProgressHandler.h"
#include "vtkPVRenderViewDataDeliveryManager.h"
#include "vtkPVSession.h"
#include "vtkPVSynchronizedRenderer.h"
#include "vtkPVWhittedPass.h"
#include "vtkProcessModule.h"
#include "vtkRenderWindow.h"
#include "vtkRenderWindowInteractor.h"
#include "vtkRenderer.h"
#include "vtkTextActor.h"
#include "vtkTextProperty.h"
#include "vtkWhittedFrameStatistics.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

vtkStandardNewMacro(vtkPVWhittedView);

//------------------------------------------------------------------------------
vtkPVWhittedView::vtkPVWhittedView()
{
  // vtkPVRenderView's constructor has created SynchronizedRenderers: it installs the pass on the
  // renderer (builtin, client) or inside IceT's composite pass (parallel), where a raster view
  // would rasterise.
  this->SynchronizedRenderers->SetRenderPass(this->WhittedPass);
  this->InstalledPass = this->WhittedPass;

  // Level of detail is never used (see SetLODRenderingThreshold), nor FXAA (see SetUseFXAA).
  this->Superclass::SetLODRenderingThreshold(VTK_DOUBLE_MAX);
  this->Superclass::SetUseFXAA(false);

  // Progress: ParaView's progress handler relays ProgressEvents of registered algorithms to the
  // GUI's progress bar (and from a server to its client). The pass is not an algorithm, so a bare
  // vtkAlgorithm stands in for it.
  this->ProgressReporter->SetProgressText("Whitted ray tracing");
  if (vtkPVSession* session = this->GetSession())
  {
    if (vtkPVProgressHandler* handler = session->GetProgressHandler())
    {
      handler->RegisterProgressEvent(this->ProgressReporter, 0);
    }
  }
  this->WhittedPass->AddObserver(
    vtkCommand::ProgressEvent, this, &vtkPVWhittedView::ForwardProgress);
  // Every frame the tracer runs ends with EndEvent (diagnostics: TracedFrameCount).
  this->WhittedPass->AddObserver(vtkCommand::EndEvent, this, &vtkPVWhittedView::CountFrame);

  // The error annotation: a text actor in the non-composited renderer (drawn over the image, like
  // the render view's own annotations), hidden until ShowErrorAnnotation
  this->ErrorAnnotation->SetVisibility(this->ShowErrorAnnotation);
  this->ErrorAnnotation->SetPickable(false);
  this->ErrorAnnotation->SetDisplayPosition(8, 8);
  vtkTextProperty* text = this->ErrorAnnotation->GetTextProperty();
  text->SetFontSize(14);
  text->SetColor(1.0, 1.0, 1.0);
  text->ShadowOn();
  this->GetNonCompositedRenderer()->AddActor2D(this->ErrorAnnotation);
  // Client/server: the annotation's text travels from the server's root to the client after the
  // image (see RelayErrorAnnotation); priority -1 runs it after the synchronized renderers' own
  // end-of-render observer, which sends and receives the image
  this->AnnotationRelayObserver = this->GetRenderer()->AddObserver(
    vtkCommand::EndEvent, this, &vtkPVWhittedView::RelayErrorAnnotation, -1.0f);
}

//------------------------------------------------------------------------------
vtkPVWhittedView::~vtkPVWhittedView()
{
  this->WhittedPass->RemoveObservers(vtkCommand::ProgressEvent);
  this->WhittedPass->RemoveObservers(vtkCommand::EndEvent);
  this->GetRenderer()->RemoveObserver(this->AnnotationRelayObserver);
  this->DetachInteractor();
  this->GetNonCompositedRenderer()->RemoveActor2D(this->ErrorAnnotation);
  this->SynchronizedRenderers->SetRenderPass(nullptr);
}

//------------------------------------------------------------------------------
// Pass settings: one line each.
void vtkPVWhittedView::SetMaxDepth(int value)
{
  this->WhittedPass->SetMaxDepth(value);
}
int vtkPVWhittedView::GetMaxDepth()
{
  return this->WhittedPass->GetMaxDepth();
}
void vtkPVWhittedView::SetSamplesPerPixel(int value)
{
  this->WhittedPass->SetSamplesPerPixel(value);
}
int vtkPVWhittedView::GetSamplesPerPixel()
{
  return this->WhittedPass->GetSamplesPerPixel();
}
void vtkPVWhittedView::SetAdaptiveSampling(bool value)
{
  this->WhittedPass->SetAdaptiveSampling(value);
}
bool vtkPVWhittedView::GetAdaptiveSampling()
{
  return this->WhittedPass->GetAdaptiveSampling();
}
void vtkPVWhittedView::SetShadows(bool value)
{
  this->WhittedPass->SetShadows(value);
}
bool vtkPVWhittedView::GetShadows()
{
  return this->WhittedPass->GetShadows();
}
void vtkPVWhittedView::SetReflections(bool value)
{
  this->WhittedPass->SetReflections(value);
}
bool vtkPVWhittedView::GetReflections()
{
  return this->WhittedPass->GetReflections();
}
void vtkPVWhittedView::SetRefractions(bool value)
{
  this->WhittedPass->SetRefractions(value);
}
bool vtkPVWhittedView::GetRefractions()
{
  return this->WhittedPass->GetRefractions();
}
void vtkPVWhittedView::SetContributionThreshold(double value)
{
  this->WhittedPass->SetContributionThreshold(value);
}
double vtkPVWhittedView::GetContributionThreshold()
{
  return this->WhittedPass->GetContributionThreshold();
}
void vtkPVWhittedView::SetTargetError(double value)
{
  this->WhittedPass->SetTargetError(value);
}
double vtkPVWhittedView::GetTargetError()
{
  return this->WhittedPass->GetTargetError();
}
void vtkPVWhittedView::SetTimeBudget(double value)
{
  this->WhittedPass->SetTimeBudget(value);
}
double vtkPVWhittedView::GetTimeBudget()
{
  return this->WhittedPass->GetTimeBudget();
}
void vtkPVWhittedView::SetNumberOfThreads(int value)
{
  this->WhittedPass->SetNumberOfThreads(value);
}
int vtkPVWhittedView::GetNumberOfThreads()
{
  return this->WhittedPass->GetNumberOfThreads();
}
void vtkPVWhittedView::SetTimeCacheMemory(int value)
{
  this->WhittedPass->SetTimeCacheMemory(value);
}
int vtkPVWhittedView::GetTimeCacheMemory()
{
  return this->WhittedPass->GetTimeCacheMemory();
}
void vtkPVWhittedView::SetFresnel(bool value)
{
  this->WhittedPass->SetFresnel(value);
}
bool vtkPVWhittedView::GetFresnel()
{
  return this->WhittedPass->GetFresnel();
}
void vtkPVWhittedView::SetShadingErrorForTesting(int value)
{
  this->WhittedPass->SetShadingErrorForTesting(value);
}
void vtkPVWhittedView::SetInteractiveMaxDepth(int value)
{
  this->WhittedPass->SetInteractiveMaxDepth(value);
}
int vtkPVWhittedView::GetInteractiveMaxDepth()
{
  return this->WhittedPass->GetInteractiveMaxDepth();
}
void vtkPVWhittedView::SetInteractiveShadows(bool value)
{
  this->WhittedPass->SetInteractiveShadows(value);
}
bool vtkPVWhittedView::GetInteractiveShadows()
{
  return this->WhittedPass->GetInteractiveShadows();
}

void vtkPVWhittedView::SetShowErrorImage(bool value)
{
  this->WhittedPass->SetShowErrorImage(value);
}
bool vtkPVWhittedView::GetShowErrorImage()
{
  return this->WhittedPass->GetShowErrorImage();
}
void vtkPVWhittedView::SetErrorImageScale(double value)
{
  this->WhittedPass->SetErrorImageScale(value);
}
double vtkPVWhittedView::GetErrorImageScale()
{
  return this->WhittedPass->GetErrorImageScale();
}

vtkWhittedPass* vtkPVWhittedView::GetWhittedPass()
{
  return this->WhittedPass;
}
const char* vtkPVWhittedView::GetLastFrameReport()
{
  return this->LastFrameReport.c_str();
}
int vtkPVWhittedView::GetLastGeometriesConverted()
{
  return this->WhittedPass->GetLastFrameStatistics()->GetNumberOfGeometriesConverted();
}
int vtkPVWhittedView::GetLastObjectsRebuilt()
{
  return this->WhittedPass->GetLastFrameStatistics()->GetNumberOfObjectsRebuilt();
}
int vtkPVWhittedView::GetLastObjectsRefit()
{
  return this->WhittedPass->GetLastFrameStatistics()->GetNumberOfObjectsRefit();
}
int vtkPVWhittedView::GetLastTimeCacheHits()
{
  return this->WhittedPass->GetLastFrameStatistics()->GetNumberOfTimeCacheHits();
}
int vtkPVWhittedView::GetLastTimeCacheEntries()
{
  return this->WhittedPass->GetLastFrameStatistics()->GetNumberOfTimeCacheEntries();
}

//------------------------------------------------------------------------------
void vtkPVWhittedView::SetLODRenderingThreshold(double)
{
  // Tracing the decimated LOD geometry would convert it and build its BVH on every switch between
  // LOD and full geometry; tracing the full geometry (converted once, cached) is cheaper. Pin the
  // threshold.
  this->Superclass::SetLODRenderingThreshold(VTK_DOUBLE_MAX);
}

//------------------------------------------------------------------------------
void vtkPVWhittedView::SetReplicateGeometry(bool value)
{
  if (this->ReplicateGeometry == value)
  {
    return;
  }
  this->ReplicateGeometry = value;
  // What is already delivered was moved in the old mode and is not moved again unless it changes:
  // have every representation produce its geometry again, so the next update delivers it in the new
  // mode.
  for (int i = 0, n = this->GetNumberOfRepresentations(); i < n; ++i)
  {
    if (auto repr = vtkPVDataRepresentation::SafeDownCast(this->GetRepresentation(i)))
    {
      repr->MarkModified();
    }
  }
  this->Modified();
}

//------------------------------------------------------------------------------
void vtkPVWhittedView::SetUseFXAA(bool)
{
  this->Superclass::SetUseFXAA(false);
}

//------------------------------------------------------------------------------
void vtkPVWhittedView::UpdateBackground(vtkRenderer* renderer)
{
  this->Superclass::UpdateBackground(renderer);
  vtkRenderer* ren = renderer ? renderer : this->GetRenderer();
  this->WhittedPass->SetEnvironment(
    ren->GetBackground(), ren->GetBackground2(), ren->GetGradientBackground());
}

//------------------------------------------------------------------------------
void vtkPVWhittedView::Update()
{
  this->Superclass::Update();

  // Decide replication once per update with the same answer on every process (client included): the
  // data movers of all processes must agree on the delivery mode or they deadlock.
  auto controller = vtkMultiProcessController::GetGlobalController();
  const vtkTypeUInt64 localRanks = controller ? controller->GetNumberOfProcesses() : 1;
  vtkTypeUInt64 maxRanks = localRanks;
  this->AllReduce(localRanks, maxRanks, vtkCommunicator::MAX_OP);
  this->GeometryReplicated = this->ReplicateGeometry && maxRanks > 1 &&
    !this->InTileDisplayMode() && !this->InCaveDisplayMode();

  // Every representation that gave the view a piece in REQUEST_UPDATE gets it delivered to all
  // ranks (vtkMPIMoveData CLONE) instead of passed through. This is
  // vtkPVRenderView::SetDeliverToAllProcesses() done by the view for all representations, so stock
  // ones (Surface, Points, ...) are replicated too.
  auto manager = vtkPVRenderViewDataDeliveryManager::SafeDownCast(this->GetDeliveryManager());
  if (!manager)
  {
    return;
  }
  for (int i = 0, n = this->GetNumberOfRepresentations(); i < n; ++i)
  {
    auto repr = vtkPVDataRepresentation::SafeDownCast(this->GetRepresentation(i));
    if (!repr)
    {
      continue;
    }
    for (int port = 0, ports = manager->GetNumberOfPorts(repr); port < ports; ++port)
    {
      if (manager->HasPiece(repr, false, port))
      {
        manager->SetDeliverToAllProcesses(repr, this->GeometryReplicated, false, port);
      }
    }
  }
}

//------------------------------------------------------------------------------
int vtkPVWhittedView::ChooseImageReduction()
{
  // Tracing time scales with the number of pixels, 1/f^2. InteractiveFullFrameCost estimates what
  // an interactive-quality frame would cost at full size; the rest of a frame (compositing,
  // overlays) does not shrink with f, so it is taken out of the budget first.
  if (this->InteractiveFullFrameCost <= 0.0)
  {
    return 1;
  }
  const double budget =
    std::max(this->InteractiveFrameTime - this->LastFixedTime, 0.25 * this->InteractiveFrameTime);
  const double f = std::sqrt(this->InteractiveFullFrameCost / budget);
  return std::max(1, std::min(this->MaximumImageReduction, static_cast<int>(std::ceil(f - 0.05))));
}

//------------------------------------------------------------------------------
void vtkPVWhittedView::Render(bool interactive, bool skip_rendering)
{
  vtkWhittedPass* pass = this->WhittedPass;
  const int framesBefore = this->TracedFrameCount;

  // Image split: every rank holds the whole scene (replicated), traces every N-th tile and writes
  // depth 1 / alpha 0 elsewhere; IceT's depth (or ordered blend) compositing then assembles the
  // frame.
  auto controller = vtkMultiProcessController::GetGlobalController();
  const bool distributed = interactive ? this->GetUseDistributedRenderingForLODRender()
                                       : this->GetUseDistributedRenderingForRender();
  const int ranks = controller ? controller->GetNumberOfProcesses() : 1;
  const bool split = this->GeometryReplicated && distributed && ranks > 1;
  this->LastImageSplit[0] = split ? ranks : 1;
  this->LastImageSplit[1] = split ? controller->GetLocalProcessId() : 0;
  pass->SetImageSplit(this->LastImageSplit[0], this->LastImageSplit[1]);

  // Quality of this frame: interactive frames use the pass's interactive mode at a reduced
  // resolution, still frames full quality. Every frame sets it, and the pass's own settings are
  // never touched, so nothing is restored afterwards.
  int reduction = 1;
  if (interactive)
  {
    reduction = this->ChooseImageReduction();
    if (split)
    {
      // Every rank must trace the same pixel grid, or their tiles do not fit together.
      int agreed = reduction;
      controller->AllReduce(&reduction, &agreed, 1, vtkCommunicator::MAX_OP);
      reduction = agreed;
    }
  }
  pass->SetInteractive(interactive);
  pass->SetInteractiveImageReduction(reduction);
  pass->SetRefinementRoundsPerFrame(this->ProgressiveRoundsForFrame(interactive));
  // In the GUI a still frame refines for at most an interactive frame's time (a longer round is cut
  // short and finished by the next frame), so interaction waits no longer than that
  const bool automatic =
    this->RefinementRoundsPerRender == 0 && this->ProgressiveRoundsForFrame(interactive) > 0;
  pass->SetRefinementSliceTime(automatic ? this->InteractiveFrameTime : 0.0);

  // Which pass this process runs. A process that draws no geometry in this frame (the client while
  // the server renders: ParaView's culler hands the renderer no props) runs ParaView's default
  // pass, not the tracer: no rays, no upload.
  vtkRenderPass* wanted = this->IsProcessRenderingGeometriesForCompositing(distributed)
    ? this->WhittedPass.Get()
    : nullptr;
  if (wanted != this->InstalledPass)
  {
    this->SynchronizedRenderers->SetRenderPass(wanted);
    this->InstalledPass = wanted;
  }

  this->AnnotationRelay = skip_rendering ? RelayNone : this->ErrorAnnotationRelay(distributed);
  const auto start = std::chrono::steady_clock::now();
  this->Superclass::Render(interactive, skip_rendering);
  this->AnnotationRelay = RelayNone;
  const double seconds =
    std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (skip_rendering)
  {
    return;
  }

  // Bookkeeping for the next interactive frame and for diagnostics (only if the tracer ran here).
  if (this->TracedFrameCount > framesBefore)
  {
    vtkWhittedFrameStatistics* stats = pass->GetLastFrameStatistics();
    this->LastRenderTime = seconds;
    // What does not scale with the traced pixels: compositing, OpenGL stages, IceT, swap
    // (conversion and BVH builds happen only when data changes and are left out).
    this->LastFixedTime = std::max(
      0.0, seconds - stats->GetTraceTime() - stats->GetBuildTime() - stats->GetConversionTime());
    const double fullFrameCost = stats->GetTraceTime() * reduction * reduction;
    if (interactive && this->LastFrameInteractive && this->InteractiveFullFrameCost > 0.0)
    {
      // Smooth over frames: the view direction changes what is hit and how often rays bounce.
      this->InteractiveFullFrameCost = 0.5 * (this->InteractiveFullFrameCost + fullFrameCost);
    }
    else
    {
      // A still frame (more samples and bounces) over-estimates an interactive one: a safe start.
      this->InteractiveFullFrameCost = fullFrameCost;
    }
    this->LastFrameReport = pass->GetLastFrameReport();
    if (!interactive)
    {
      stats->GetEstimatedError(this->LastEstimatedError);
      stats->GetTruncationError(this->LastTruncationError);
      stats->GetSamplingError(this->LastSamplingError);
      this->LastTargetErrorMet = stats->GetTargetErrorMet();
      this->LastNumberOfSamples = static_cast<double>(stats->GetNumberOfSamples());
      this->LastRefinementRounds = stats->GetRefinementRounds();
    }
    this->AfterTracedFrame(interactive, reduction);
  }
  this->LastFrameInteractive = interactive;
  this->LastImageReduction = reduction;
}

//------------------------------------------------------------------------------
void vtkPVWhittedView::CountFrame(vtkObject*, unsigned long, void*)
{
  ++this->TracedFrameCount;
  // The annotation is drawn by the non-composited renderer after this one: it shows this frame
  this->UpdateErrorAnnotation(
    this->WhittedPass->GetInteractive(), this->WhittedPass->GetInteractiveImageReduction());
}

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
    std::snprintf(text, sizeof text, "Whitted: %.0f ms, %.2f spp, error %.4f (RMS estimate)\n%s%s",
      stats->GetRefinementSeconds() * 1e3, spp, stats->GetEstimatedError()[0], status,
      stats->GetRefinementFinished() ? "" : ", refining");
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

//------------------------------------------------------------------------------
void vtkPVWhittedView::ForwardProgress(vtkObject*, unsigned long, void* callData)
{
  if (!callData)
  {
    return;
  }
  // In the GUI the progress bar repaints right away, in the middle of this frame: Qt composites the
  // main window with another GL context, and making the view's context current again makes Qt bind
  // its widget framebuffer. Put back the framebuffers VTK is rendering into.
  auto* win = vtkOpenGLRenderWindow::SafeDownCast(this->GetRenderWindow());
  vtkOpenGLState* state = win ? win->GetState() : nullptr;
  if (state)
  {
    state->PushFramebufferBindings();
  }
  this->ProgressReporter->UpdateProgress(*static_cast<double*>(callData));
  if (state)
  {
    win->MakeCurrent();
    state->PopFramebufferBindings();
  }
}

//------------------------------------------------------------------------------
void vtkPVWhittedView::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "InteractiveFrameTime: " << this->InteractiveFrameTime << "\n";
  os << indent << "MaximumImageReduction: " << this->MaximumImageReduction << "\n";
  os << indent << "ReplicateGeometry: " << this->ReplicateGeometry << "\n";
  os << indent << "ProgressiveDisplay: " << this->ProgressiveDisplay << "\n";
  os << indent << "RefinementRoundsPerRender: " << this->RefinementRoundsPerRender << "\n";
  os << indent << "ShowErrorAnnotation: " << this->ShowErrorAnnotation << "\n";
  os << indent << "RefinementUnfinished: " << this->RefinementUnfinished << "\n";
  os << indent << "TracedFrameCount: " << this->TracedFrameCount << "\n";
  os << indent << "LastRenderTime: " << this->LastRenderTime << "\n";
  os << indent << "LastImageReduction: " << this->LastImageReduction << "\n";
  os << indent << "LastImageSplit: " << this->LastImageSplit[0] << " " << this->LastImageSplit[1]
     << "\n";
  os << indent << "WhittedPass:\n";
  this->WhittedPass->PrintSelf(os, indent.GetNextIndent());
}
