/**
 * @class   vtkPVWhittedView
 * @brief   ParaView render view that draws through vtkWhittedPass ("Whitted Ray Trace" in the GUI)
 *
 * A vtkPVRenderView whose renderer runs vtkWhittedPass instead of OpenGL rasterisation. Everything
 * a render view does (background, camera, light kit and lights panel, orientation axes,
 * annotations, 2D actors, screenshots, client/server and IceT compositing) keeps working: the pass
 * sits where vtkPVSynchronizedRenderer puts a render pass, i.e. inside IceT's draw callback when
 * compositing.
 *
 * What the view adds to a plain render view:
 * - The pass's settings (MaxDepth, SamplesPerPixel, ...), each forwarded in one line.
 * - Interactive frames: while the camera is dragged the pass traces in its interactive mode (1
 * sample per pixel, at most InteractiveMaxDepth bounces) at a reduced resolution picked from the
 * measured cost of earlier frames so that a frame takes about InteractiveFrameTime. Each frame sets
 * the mode, so the full-quality frame follows when interaction stops (ParaView's still render) and
 * no setting is ever changed and restored.
 * - No level-of-detail geometry: ray tracing cost grows with log(triangles), so ParaView's
 * decimated LOD would save little and cost a scene conversion and a BVH build on every switch. The
 * LOD threshold is pinned to "never" and the full geometry (converted once, cached by the pass) is
 * traced.
 * - Parallel (mpirun pvbatch / pvserver): with ReplicateGeometry on (default) every
 * representation's geometry is delivered to every rank, so shadows and reflections see the whole
 * scene; each rank traces an interleaved share of the pixels (vtkWhittedPass::SetImageSplit) and
 * IceT's depth or ordered-blend compositing assembles the frame. The memory cost is one full copy
 * of the rendered geometry per rank (see README).
 * - Progressive display (ProgressiveDisplay, on by default): a still frame that refines
 * (TargetError or TimeBudget) runs one refinement round per frame in the GUI, for at most
 * InteractiveFrameTime (a longer round is cut short between tiles and finished by the next frame),
 * and the view renders again (a one-shot timer on its interactor, which ParaView turns into a still
 * render) until the refinement is over; the camera or anything else changing starts over, and
 * interaction cancels the timer, so it waits at most about InteractiveFrameTime plus a tile. Scripts
 * set RefinementRoundsPerRender and render again while RefinementUnfinished is 1.
 * - Error display: ShowErrorAnnotation puts the last frame's time, samples, estimated error and
 * target status in the lower left corner (a text actor in the non-composited renderer, like the
 * render view's own annotations); ShowErrorImage shows the per-pixel error instead of the image.
 * With a remote server (client/server, the server rendering) the server's root sends the text to
 * the client after each frame's image, so the client draws it and reports it.
 * - Progress: the pass's ProgressEvent is forwarded to ParaView's progress handler, so long still
 * frames move the GUI's progress bar (and are reported to a remote client).
 * - No work where no geometry is: a process that renders no geometry for this frame (the client
 * while a server renders) runs ParaView's default pass instead of the tracer.
 * - The view's background is what reflected and refracted rays see, also where ParaView composites
 * on black (vtkPVWhittedPass); FXAA is off (see SetUseFXAA).
 *
 * @sa vtkWhittedPass vtkWhittedGeometryRepresentation vtkPVRenderView
 */

#ifndef vtkPVWhittedView_h
#define vtkPVWhittedView_h

#include "WhittedParaViewModule.h" // for export macro
#include "vtkNew.h"                // for vtkNew
#include "vtkPVRenderView.h"
#include "vtkWhittedSettings.h" // for the settings' defaults and ranges

#include <string> // for std::string

class vtkAlgorithm;
class vtkPVWhittedPass;
class vtkRenderPass;
class vtkRenderWindowInteractor;
class vtkTextActor;
class vtkWhittedPass;

// The view's part of the settings table. Pass rows: one-line forwarders to the pass (declared
// here, defined in vtkPVWhittedView.cxx). View rows: members, getters, clamped setters of numbers.
#define VTK_WHITTED_VIEW_FORWARDERS(owner, type, name, def, min, max, doc)                         \
  VTK_WHITTED_VIEW_FORWARDERS_##owner(type, name)
#define VTK_WHITTED_VIEW_FORWARDERS_Pass(type, name)                                               \
  void Set##name(type value);                                                                      \
  type Get##name();
#define VTK_WHITTED_VIEW_FORWARDERS_View(type, name)
#define VTK_WHITTED_VIEW_ACCESSORS(owner, type, name, def, min, max, doc)                          \
  VTK_WHITTED_VIEW_ACCESSORS_##owner(type, name)
#define VTK_WHITTED_VIEW_ACCESSORS_Pass(type, name)
#define VTK_WHITTED_VIEW_ACCESSORS_View(type, name) VTK_WHITTED_VIEW_ACCESSORS_##type(name)
#define VTK_WHITTED_VIEW_ACCESSORS_bool(name) vtkGetMacro(name, bool);
#define VTK_WHITTED_VIEW_ACCESSORS_int(name) VTK_WHITTED_SETTING_ACCESSORS_int(name)
#define VTK_WHITTED_VIEW_ACCESSORS_double(name) VTK_WHITTED_SETTING_ACCESSORS_double(name)
#define VTK_WHITTED_VIEW_MEMBERS(owner, type, name, def, min, max, doc)                            \
  VTK_WHITTED_VIEW_MEMBERS_##owner(type, name)
#define VTK_WHITTED_VIEW_MEMBERS_Pass(type, name)
#define VTK_WHITTED_VIEW_MEMBERS_View(type, name) VTK_WHITTED_SETTING_MEMBER(type, name)

class WHITTEDPARAVIEW_EXPORT vtkPVWhittedView : public vtkPVRenderView
{
public:
  static vtkPVWhittedView* New();
  vtkTypeMacro(vtkPVWhittedView, vtkPVRenderView);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Settings of the pass (SetX, GetX for each Pass row of the settings table, vtkWhittedSettings.h,
   * which holds their meaning, default and range), each forwarded in one line. Shadows and SamplesPerPixel replace the OSPRay settings
   * of the same name of a plain render view. InteractiveMaxDepth and InteractiveShadows apply to
   * the frames traced while the camera moves (see vtkWhittedPass::SetInteractive).
   */
  VTK_WHITTED_SETTINGS(VTK_WHITTED_VIEW_FORWARDERS)
  void SetShadingErrorForTesting(int value); ///< vtkWhittedPass::SetShadingErrorForTesting
  ///@}

  ///@{
  /**
   * The view's own settings (the View rows of the settings table, vtkWhittedSettings.h, which
   * holds their meaning, default and range): GetX for each, SetX clamped to the range for the
   * numbers; the on/off settings have setters of their own below. The settings:
   * - Interactive frames (camera being dragged) are traced at the pass's interactive quality and
   * at 1/f of the resolution, with f = 1..MaximumImageReduction chosen from the measured cost of
   * earlier frames so that a frame takes about InteractiveFrameTime (wall-clock seconds).
   * - ProgressiveDisplay, RefinementRoundsPerRender, ShowErrorAnnotation: progressive display
   * and the on-screen error annotation (see class documentation).
   * - ReplicateGeometry: parallel rendering: deliver every representation's geometry to every
   * rank so that each rank traces the full scene (correct shadows, reflections and refractions
   * across ranks) and split the image between ranks. Off: each rank traces only its own data,
   * like a raster view (secondary rays miss the other ranks' geometry). Has no effect with a
   * single rendering process.
   */
  VTK_WHITTED_SETTINGS(VTK_WHITTED_VIEW_ACCESSORS)
  vtkSetMacro(ProgressiveDisplay, bool);
  void SetShowErrorAnnotation(bool value);
  void SetReplicateGeometry(bool value);
  ///@}

  ///@{
  /**
   * Progressive display state of the last still frame traced on this process (information-only
   * properties): whether its refinement is unfinished (rendering again would improve it), and the
   * annotation text (also when the annotation is hidden; on a client whose server renders, the
   * server's text).
   */
  vtkGetMacro(RefinementUnfinished, bool);
  const char* GetErrorAnnotationText();
  ///@}

  /**
   * Overridden to restart progressive display from the interactor's timer and to stop it when
   * interaction starts.
   */
  void SetupInteractor(vtkRenderWindowInteractor*) override;

  /**
   * Level of detail is never used by this view (see class documentation); the threshold is ignored.
   */
  void SetLODRenderingThreshold(double) override;

  /**
   * FXAA is never used by this view: ParaView applies it after compositing in parallel and
   * client/server modes but not in builtin mode (a renderer with a custom pass skips it), so images
   * would depend on the mode; the ray tracer anti-aliases with SamplesPerPixel instead.
   */
  void SetUseFXAA(bool) override;

  ///@{
  /**
   * Diagnostics of this process (information-only properties; a client reports its own values):
   * frames the tracer ran on this process, the last frame's wall time in seconds (whole
   * render window), the reduction factor of the last interactive frame, the image split of the last
   * frame (stride, offset), what the last frame converted and rebuilt (geometries converted to the
   * tracer's scene, object BVHs built, object BVHs refit; all 0 when nothing changed), what it
   * took from the time cache (geometries restored) and what that holds after it (geometries), and
   * the pass's report of its last frame.
   */
  vtkGetMacro(TracedFrameCount, int);
  int GetLastGeometriesConverted();
  int GetLastObjectsRebuilt();
  int GetLastObjectsRefit();
  int GetLastTimeCacheHits();
  int GetLastTimeCacheEntries();
  vtkGetMacro(LastRenderTime, double);
  vtkGetMacro(LastImageReduction, int);
  vtkGetVector2Macro(LastImageSplit, int);
  const char* GetLastFrameReport();
  ///@}

  ///@{
  /**
   * The error estimate of the last still frame traced on this process (information-only
   * properties): { RMS, 95th percentile, max } of the per-pixel estimated error, truncation bound
   * and sampling estimate (see vtkWhittedFrameStatistics), whether it met TargetError, its camera
   * samples, refinement rounds and refinement seconds (what TimeBudget counts: the tracing seconds of
   * all the renders of a progressively displayed frame so far). Interactive frames leave them as they
   * are. LastRMSError: the calibrated estimate { RMS, 95th percentile, max } (what TargetError is
   * met by and the annotation shows; vtkWhittedFrameStatistics::GetRMSError).
   */
  vtkGetVector3Macro(LastEstimatedError, double);
  vtkGetVector3Macro(LastRMSError, double);
  vtkGetVector3Macro(LastTruncationError, double);
  vtkGetVector3Macro(LastSamplingError, double);
  vtkGetMacro(LastTargetErrorMet, bool);
  vtkGetMacro(LastNumberOfSamples, double);
  vtkGetMacro(LastRefinementRounds, int);
  vtkGetMacro(LastRefinementSeconds, double);
  ///@}

  /**
   * The pass (for C++ callers and tests).
   */
  vtkWhittedPass* GetWhittedPass();

  /**
   * Overridden to replicate geometry to all ranks when rendering in parallel (see
   * ReplicateGeometry).
   */
  void Update() override;

protected:
  vtkPVWhittedView();
  ~vtkPVWhittedView() override;

  /**
   * Configures the pass for the frame (interactive quality, image split between ranks), renders,
   * and records timings for the next interactive frame.
   */
  void Render(bool interactive, bool skip_rendering) override;

  /**
   * Overridden to hand the view's background to the pass as the environment of secondary rays
   * (ParaView replaces the renderer's background by black while compositing).
   */
  void UpdateBackground(vtkRenderer* renderer = nullptr) override;

  vtkNew<vtkPVWhittedPass> WhittedPass;
  vtkNew<vtkAlgorithm> ProgressReporter;
  vtkNew<vtkTextActor> ErrorAnnotation;

  // The view's own settings (the View rows of the table), at their defaults
  VTK_WHITTED_SETTINGS(VTK_WHITTED_VIEW_MEMBERS)
  bool RefinementUnfinished = false;
  std::string ErrorAnnotationText;
  // Progressive display in the GUI: the interactor's one-shot timer that renders again (-1: none)
  int ProgressiveTimerId = -1;
  unsigned long InteractorObservers[2] = { 0, 0 }; // timer, start of interaction

  // The pass installed in the synchronized renderers: the tracer, or null (ParaView's default)
  vtkRenderPass* InstalledPass = nullptr;
  // Decision of the last Update(), identical on all processes
  bool GeometryReplicated = false;
  // Estimated trace seconds of an interactive frame at full size, and seconds of the last frame
  // that do not scale with the traced pixels (compositing, OpenGL stages, IceT)
  double InteractiveFullFrameCost = 0;
  double LastFixedTime = 0;
  bool LastFrameInteractive = false;
  double LastEstimatedError[3] = { 0.0, 0.0, 0.0 };
  double LastRMSError[3] = { 0.0, 0.0, 0.0 };
  double LastTruncationError[3] = { 0.0, 0.0, 0.0 };
  double LastSamplingError[3] = { 0.0, 0.0, 0.0 };
  bool LastTargetErrorMet = false;
  double LastNumberOfSamples = 0.0;
  int LastRefinementRounds = 0;
  double LastRefinementSeconds = 0.0;
  int TracedFrameCount = 0;
  double LastRenderTime = 0;
  int LastImageReduction = 1;
  int LastImageSplit[2] = { 1, 0 };
  std::string LastFrameReport;

private:
  vtkPVWhittedView(const vtkPVWhittedView&) = delete;
  void operator=(const vtkPVWhittedView&) = delete;

  int ChooseImageReduction();
  void ForwardProgress(vtkObject*, unsigned long, void* callData);
  void CountFrame(vtkObject*, unsigned long, void*);
  // Progressive display and annotation (see class documentation)
  int ProgressiveRoundsForFrame(bool interactive);
  void AfterTracedFrame(bool interactive, int reduction);
  void UpdateErrorAnnotation(bool interactive, int reduction);
  void OnInteractorEvent(vtkObject*, unsigned long event, void* callData);
  void DetachInteractor();
  // Client/server: the server's root sends the error annotation's text to the client after each
  // frame it renders for it (see ErrorAnnotationText)
  enum
  {
    RelayNone,
    RelaySend,
    RelayReceive
  };
  static constexpr int ErrorAnnotationTag = 0x57484954; // "WHIT"
  int AnnotationRelay = RelayNone;
  unsigned long AnnotationRelayObserver = 0;
  int ErrorAnnotationRelay(bool distributed);
  void RelayErrorAnnotation(vtkObject*, unsigned long, void*);
};

#endif
