#include "vtkPVWhittedView.h"

#include "vtkAlgorithm.h"
#include "vtkCommand.h"
#include "vtkCommunicator.h"
#include "vtkMultiProcessController.h"
#include "vtkObjectFactory.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLState.h"
#include "vtkPVDataRepresentation.h"
#include "vtkPVProgressHandler.h"
#include "vtkPVRenderViewDataDeliveryManager.h"
#include "vtkPVSession.h"
#include "vtkPVSynchronizedRenderer.h"
#include "vtkPVWhittedPass.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkTextActor.h"
#include "vtkTextProperty.h"
#include "vtkWhittedFrameStatistics.h"

#include <algorithm>
#include <chrono>
#include <cmath>

vtkStandardNewMacro(vtkPVWhittedView);

//------------------------------------------------------------------------------
vtkPVWhittedView::vtkPVWhittedView()
{
  // vtkPVRenderView's constructor has created SynchronizedRenderers: it installs the pass on the
  // renderer (builtin, client) or inside IceT's composite pass (parallel), where a raster view
  // would rasterise.
  this->SynchronizedRenderers->SetRenderPass(this->WhittedPass);
  this->InstalledPass = this->WhittedPass;
  // The pass settings whose view default differs from the pass's (see vtkWhittedSettings.h)
#define VTK_WHITTED_VIEW_DEFAULT(name, value) this->WhittedPass->Set##name(value);
  VTK_WHITTED_VIEW_DEFAULTS(VTK_WHITTED_VIEW_DEFAULT)
#undef VTK_WHITTED_VIEW_DEFAULT

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
// Pass settings (the Pass rows of the settings table): one line each.
#define VTK_WHITTED_VIEW_FORWARD(owner, type, name, def, min, max, doc)                            \
  VTK_WHITTED_VIEW_FORWARD_##owner(type, name)
#define VTK_WHITTED_VIEW_FORWARD_Pass(type, name)                                                  \
  void vtkPVWhittedView::Set##name(type value) { this->WhittedPass->Set##name(value); }            \
  type vtkPVWhittedView::Get##name() { return this->WhittedPass->Get##name(); }
#define VTK_WHITTED_VIEW_FORWARD_View(type, name)
VTK_WHITTED_SETTINGS(VTK_WHITTED_VIEW_FORWARD)
void vtkPVWhittedView::SetShadingErrorForTesting(int value)
{
  this->WhittedPass->SetShadingErrorForTesting(value);
}

//------------------------------------------------------------------------------
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
      stats->GetRMSError(this->LastRMSError);
      stats->GetTruncationError(this->LastTruncationError);
      stats->GetSamplingError(this->LastSamplingError);
      this->LastTargetErrorMet = stats->GetTargetErrorMet();
      this->LastNumberOfSamples = static_cast<double>(stats->GetNumberOfSamples());
      this->LastRefinementRounds = stats->GetRefinementRounds();
      this->LastRefinementSeconds = stats->GetRefinementSeconds();
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
// PrintSelf: the view's own settings (the View rows of the table), its state, then the pass
#define VTK_WHITTED_VIEW_PRINT(owner, type, name, def, min, max, doc)                              \
  VTK_WHITTED_VIEW_PRINT_##owner(name)
#define VTK_WHITTED_VIEW_PRINT_Pass(name)
#define VTK_WHITTED_VIEW_PRINT_View(name) VTK_WHITTED_SETTING_PRINT(name)
void vtkPVWhittedView::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  VTK_WHITTED_SETTINGS(VTK_WHITTED_VIEW_PRINT)
  os << indent << "RefinementUnfinished: " << this->RefinementUnfinished << "\n";
  os << indent << "TracedFrameCount: " << this->TracedFrameCount << "\n";
  os << indent << "LastRenderTime: " << this->LastRenderTime << "\n";
  os << indent << "LastImageReduction: " << this->LastImageReduction << "\n";
  os << indent << "LastImageSplit: " << this->LastImageSplit[0] << " " << this->LastImageSplit[1]
     << "\n";
  os << indent << "WhittedPass:\n";
  this->WhittedPass->PrintSelf(os, indent.GetNextIndent());
}
