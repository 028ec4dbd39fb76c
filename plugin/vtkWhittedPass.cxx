#include "vtkWhittedPass.h"

#include "vtkWhittedCompositor.h"
#include "vtkWhittedFrameStatistics.h"
#include "vtkWhittedMaterialKeys.h"
#include "vtkWhittedMatrix.h"
#include "vtkWhittedSceneConverter.h"

#include "vtkCamera.h"
#include "vtkMatrix4x4.h"
#include "vtkCameraPass.h"
#include "vtkCommand.h"
#include "vtkFloatArray.h"
#include "vtkFrameBufferObjectBase.h"
#include "vtkHardwareSelector.h"
#include "vtkImageData.h"
#include "vtkLight.h"
#include "vtkLightCollection.h"
#include "vtkLightsPass.h"
#include "vtkMatrix4x4.h"
#include "vtkObjectFactory.h"
#include "vtkOpaquePass.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOverlayPass.h"
#include "vtkPointData.h"
#include "vtkPropCollection.h"
#include "vtkRenderPassCollection.h"
#include "vtkRenderState.h"
#include "vtkRenderer.h"
#include "vtkSequencePass.h"
#include "vtkTranslucentPass.h"
#include "vtkVolumetricPass.h"
#include "vtkWeakPointer.h"

#include "shading/camera.h"
#include "image/renderer.h"
#include "image/report.h"
#include "scene/scene.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <exception>
#include <map>
#include <memory>

namespace
{
// Process CPU seconds (every thread's) since c0 = std::clock()
double CPUSecondsSince(std::clock_t c0)
{
  return static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
}

double SecondsSince(std::chrono::steady_clock::time_point t)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// One viewport pixel's footprint, for edge widths in pixels (IntegratorSettings::pixelAngle and
// pixelSize): the view's half height is 1 / P[1][1] of VTK's projection matrix, at unit distance
// (perspective) or in world units (parallel), over half the traced image's height in pixels.
void SetPixelFootprint(
  whitted::IntegratorSettings& is, vtkCamera* cam, double aspect, int viewportHeight)
{
  const double p11 = cam->GetProjectionTransformMatrix(aspect, -1, 1)->GetElement(1, 1);
  const double pixel = viewportHeight > 0 && p11 > 0.0 ? 2.0 / (p11 * viewportHeight) : 0.0;
  is.pixelAngle = cam->GetParallelProjection() ? 0.0 : pixel;
  is.pixelSize = cam->GetParallelProjection() ? pixel : 0.0;
}
}

//------------------------------------------------------------------------------
// The pass that sits in the sequence after vtkLightsPass; it owns everything that is not a setting.
class vtkWhittedPassInternals : public vtkRenderPass
{
public:
  static vtkWhittedPassInternals* New();
  vtkTypeMacro(vtkWhittedPassInternals, vtkRenderPass);

  void Render(const vtkRenderState* s) override
  {
    this->Rendered = 0;
    this->Parent->RenderInternal(s);
    this->NumberOfRenderedProps = this->Rendered;
  }

  void ReleaseGraphicsResources(vtkWindow* w) override
  {
    this->Compositor.ReleaseGraphicsResources(w);
    this->OpaquePass->ReleaseGraphicsResources(w);
    this->TranslucentPass->ReleaseGraphicsResources(w);
    this->VolumetricPass->ReleaseGraphicsResources(w);
    this->OverlayPass->ReleaseGraphicsResources(w);
  }

  vtkWhittedPass* Parent = nullptr;

  // Pass chain: camera (clear, viewport) -> sequence(lights, this)
  vtkNew<vtkCameraPass> CameraPass;
  vtkNew<vtkSequencePass> SequencePass;
  vtkNew<vtkLightsPass> LightsPass;

  // VTK's OpenGL stages for the props the tracer does not draw
  vtkNew<vtkOpaquePass> OpaquePass;
  vtkNew<vtkTranslucentPass> TranslucentPass;
  vtkNew<vtkVolumetricPass> VolumetricPass;
  vtkNew<vtkOverlayPass> OverlayPass;

  // One scene per renderer, so a pass shared by several renderers keeps every cache warm
  struct RendererScene
  {
    vtkWeakPointer<vtkRenderer> Renderer;
    vtkWhittedSceneConverter Converter;
  };
  std::map<vtkRenderer*, std::unique_ptr<RendererScene>> Scenes;
  vtkWhittedCompositor Compositor;

  vtkWhittedSceneConverter& ConverterFor(vtkRenderer* ren)
  {
    // Forget renderers that were deleted (their address may be reused)
    for (auto it = this->Scenes.begin(); it != this->Scenes.end();)
    {
      it = it->second->Renderer ? std::next(it) : this->Scenes.erase(it);
    }
    std::unique_ptr<RendererScene>& rs = this->Scenes[ren];
    if (!rs)
    {
      rs.reset(new RendererScene);
      rs->Renderer = ren;
    }
    return rs->Converter;
  }
  whitted::FrameBuffer Frame;
  int Rendered = 0;

  // Progressive display: the sums of the still frame being refined, and what it was traced with
  struct FrameKey
  {
    std::array<double, 16> View{};
    std::array<double, 7> Background{};
    int Width = 0, Height = 0;
    vtkMTimeType Pass = 0, Props = 0;
    bool operator==(const FrameKey& o) const
    {
      return View == o.View && Background == o.Background && Width == o.Width &&
        Height == o.Height && Pass == o.Pass && Props == o.Props;
    }
  };
  whitted::RefinementState Refinement;
  FrameKey RefinementKey;
  static FrameKey KeyOf(
    vtkWhittedPass* pass, vtkRenderer* ren, const vtkMatrix4x4* view, int w, int h);

  // Error image display: the traced frame with every traced pixel's colour replaced by its grey
  // level (see vtkWhittedPass::ShowErrorImage)
  whitted::FrameBuffer ErrorDisplay;
  whitted::FrameBuffer Perturbed; // ShadingErrorForTesting only
  const whitted::FrameBuffer& DisplayedFrame(vtkWhittedPass* pass);
  const whitted::FrameBuffer& ErrorDisplayed(vtkWhittedPass* pass);
  vtkNew<vtkWhittedFrameStatistics> Statistics;

  // What one frame computed, for the statistics
  struct FrameResult
  {
    vtkWhittedSceneConverter::Result Conversion;
    whitted::CommitStats Commit;
    whitted::FrameStats Trace;
    double ConversionTime = 0.0;
    double CompositeTime = 0.0;
    // Process CPU seconds (all threads) of conversion, build, trace and composite
    double CPUTime[4] = { 0.0, 0.0, 0.0, 0.0 };
  };

  // The pass's settings for this frame as the tracer's (interactive frames at reduced quality)
  static whitted::RenderSettings FrameSettings(
    vtkWhittedPass* pass, vtkCamera* cam, bool headlightShading);

  // Traces the committed scene into Frame. The callbacks (abort check, progress) run on this
  // thread between tiles while worker threads trace: an exception from them must not unwind
  // through the tracer, so it aborts the frame and is rethrown afterwards.
  whitted::FrameStats Trace(vtkWhittedPass* pass, vtkOpenGLRenderWindow* win,
    const whitted::Scene& scene, const whitted::Camera& camera, whitted::RenderSettings settings,
    int width, int height);

  // Draws the environment props (skybox) with OpenGL, composites the traced image over them, then
  // runs VTK's OpenGL stages for the props the tracer does not draw; returns the props drawn.
  int Composite(const vtkRenderState* s, vtkOpenGLRenderWindow* win,
    const vtkWhittedSceneConverter::Result& conv, const int viewport[4]);

  // Fills Statistics and the report from a traced frame.
  void RecordStatistics(
    const FrameResult& r, const whitted::SceneStats& scene, double totalTime, std::string& report);

protected:
  vtkWhittedPassInternals() = default;
  ~vtkWhittedPassInternals() override = default;
};

vtkStandardNewMacro(vtkWhittedPassInternals);

//------------------------------------------------------------------------------
vtkStandardNewMacro(vtkWhittedPass);

//------------------------------------------------------------------------------
// Kept for compatibility: vtkWhittedPass::NAME() returns vtkWhittedMaterialKeys::NAME(), the very
// same key object (defined once, in vtkWhittedMaterialKeys.cxx)
#define vtkWhittedPassKeyForwarder(NAME, type)                                                     \
  vtkInformation##type##Key* vtkWhittedPass::NAME()                                                \
  {                                                                                                \
    return vtkWhittedMaterialKeys::NAME();                                                         \
  }
vtkWhittedPassKeyForwarder(REFLECTANCE, DoubleVector);
vtkWhittedPassKeyForwarder(TRANSMITTANCE, DoubleVector);
vtkWhittedPassKeyForwarder(INDEX_OF_REFRACTION, Double);
vtkWhittedPassKeyForwarder(ATTENUATION_COLOR, DoubleVector);
vtkWhittedPassKeyForwarder(ATTENUATION_DISTANCE, Double);
vtkWhittedPassKeyForwarder(RADIUS_ARRAY, String);
vtkWhittedPassKeyForwarder(RADIUS_FUNCTION, ObjectBase);
#undef vtkWhittedPassKeyForwarder

//------------------------------------------------------------------------------
vtkWhittedPass::vtkWhittedPass()
{
  this->Internals = vtkWhittedPassInternals::New();
  this->Internals->Parent = this;
  vtkNew<vtkRenderPassCollection> passes;
  passes->AddItem(this->Internals->LightsPass);
  passes->AddItem(this->Internals);
  this->Internals->SequencePass->SetPasses(passes);
  this->Internals->CameraPass->SetDelegatePass(this->Internals->SequencePass);
}

//------------------------------------------------------------------------------
vtkWhittedPass::~vtkWhittedPass()
{
  // Break the cycle sequence -> internals before releasing
  this->Internals->SequencePass->SetPasses(nullptr);
  this->Internals->CameraPass->SetDelegatePass(nullptr);
  this->Internals->Delete();
}

//------------------------------------------------------------------------------
void vtkWhittedPass::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "MaxDepth: " << this->MaxDepth << "\n";
  os << indent << "SamplesPerPixel: " << this->SamplesPerPixel << "\n";
  os << indent << "AdaptiveSampling: " << this->AdaptiveSampling << "\n";
  os << indent << "Shadows: " << this->Shadows << "\n";
  os << indent << "Reflections: " << this->Reflections << "\n";
  os << indent << "Refractions: " << this->Refractions << "\n";
  os << indent << "Fresnel: " << this->Fresnel << "\n";
  os << indent << "ContributionThreshold: " << this->ContributionThreshold << "\n";
  os << indent << "TargetError: " << this->TargetError << "\n";
  os << indent << "TimeBudget: " << this->TimeBudget << "\n";
  os << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
  os << indent << "TimeCacheMemory: " << this->TimeCacheMemory << "\n";
  os << indent << "ShowErrorImage: " << this->ShowErrorImage << "\n";
  os << indent << "ErrorImageScale: " << this->ErrorImageScale << "\n";
  os << indent << "RefinementRoundsPerFrame: " << this->RefinementRoundsPerFrame << "\n";
  os << indent << "RefinementSliceTime: " << this->RefinementSliceTime << "\n";
  os << indent << "Interactive: " << this->Interactive << "\n";
  os << indent << "InteractiveMaxDepth: " << this->InteractiveMaxDepth << "\n";
  os << indent << "InteractiveShadows: " << this->InteractiveShadows << "\n";
  os << indent << "InteractiveImageReduction: " << this->InteractiveImageReduction << "\n";
  os << indent << "ImageSplit: " << this->ImageSplit[0] << " " << this->ImageSplit[1] << "\n";
  os << indent << "LastFrameStatistics:\n";
  this->Internals->Statistics->PrintSelf(os, indent.GetNextIndent());
  os << indent << "LastFrameReport:\n" << this->LastFrameReport;
}

//------------------------------------------------------------------------------
void vtkWhittedPass::SetImageSplit(int stride, int offset)
{
  stride = stride < 1 ? 1 : stride;
  offset = offset < 0 ? 0 : (offset >= stride ? stride - 1 : offset);
  if (this->ImageSplit[0] != stride || this->ImageSplit[1] != offset)
  {
    this->ImageSplit[0] = stride;
    this->ImageSplit[1] = offset;
    this->Modified();
  }
}

//------------------------------------------------------------------------------
void vtkWhittedPass::ReleaseGraphicsResources(vtkWindow* w)
{
  this->Internals->ReleaseGraphicsResources(w);
  this->Internals->CameraPass->ReleaseGraphicsResources(w);
}

//------------------------------------------------------------------------------
void vtkWhittedPass::WaitForBackgroundBuilds()
{
  for (auto& rs : this->Internals->Scenes)
  {
    rs.second->Converter.GetScene().waitForUpgrades();
  }
}

//------------------------------------------------------------------------------
void vtkWhittedPass::Render(const vtkRenderState* s)
{
  this->NumberOfRenderedProps = 0;
  this->Internals->CameraPass->Render(s);
  this->NumberOfRenderedProps = this->Internals->CameraPass->GetNumberOfRenderedProps();
}

//------------------------------------------------------------------------------
void vtkWhittedPass::RenderInternal(const vtkRenderState* s)
{
  const auto start = std::chrono::steady_clock::now();
  vtkWhittedPassInternals* in = this->Internals;
  vtkRenderer* ren = s->GetRenderer();
  auto* win = vtkOpenGLRenderWindow::SafeDownCast(ren->GetRenderWindow());
  if (!win)
  {
    vtkErrorMacro("vtkWhittedPass needs an OpenGL render window.");
    return;
  }
  // Hardware picking (vtkHardwareSelector) renders ids, not colours: let the selector draw every
  // prop with OpenGL, as vtkRenderer::UpdateGeometry does without a pass
  if (vtkHardwareSelector* selector = ren->GetSelector())
  {
    in->Rendered = selector->Render(ren, s->GetPropArray(), s->GetPropArrayCount());
    return;
  }
  this->InvokeEvent(vtkCommand::StartEvent);

  // Image size: the renderer's (tiled) viewport, or the render state's framebuffer; interactive
  // frames trace fewer pixels with the same camera, stretched when drawn
  int viewport[4] = { 0, 0, 0, 0 }; // x, y, width, height
  if (vtkFrameBufferObjectBase* fbo = s->GetFrameBuffer())
  {
    fbo->GetLastSize(viewport[2], viewport[3]);
  }
  else
  {
    ren->GetTiledSizeAndOrigin(&viewport[2], &viewport[3], &viewport[0], &viewport[1]);
  }
  const int reduction = this->Interactive ? this->InteractiveImageReduction : 1;
  const int traceWidth = (viewport[2] + reduction - 1) / reduction;
  const int traceHeight = (viewport[3] + reduction - 1) / reduction;

  // Convert -> commit -> trace. Each may throw (std::bad_alloc for a scene too large for memory,
  // or an exception from an observer of the abort check / progress): the frame then fails cleanly
  vtkWhittedPassInternals::FrameResult r;
  vtkWhittedSceneConverter* converter = nullptr;
  try
  {
    // Scene conversion (cached)
    converter = &in->ConverterFor(ren);
    converter->SetTimeCacheLimit(static_cast<std::size_t>(this->TimeCacheMemory) << 20);
    std::clock_t cpu = std::clock();
    converter->Update(ren, s->GetPropArray(), s->GetPropArrayCount(), this, r.Conversion);
    r.ConversionTime = SecondsSince(start);
    r.CPUTime[0] = CPUSecondsSince(cpu);

    // BVH builds of what changed: new and replaced large geometry with the fast builder, upgraded
    // to the SAH tree in the background after the frame (Scene::setBackgroundUpgrade)
    cpu = std::clock();
    converter->GetScene().setBackgroundUpgrade(true);
    r.Commit = converter->GetScene().commit();
    r.CPUTime[1] = CPUSecondsSince(cpu);

    // Trace; rays from the inverse of VTK's composite projection (tiles, IceT viewports)
    vtkCamera* cam = ren->GetActiveCamera();
    vtkMatrix4x4* viewProjection =
      cam->GetCompositeProjectionTransformMatrix(ren->GetTiledAspectRatio(), -1, 1);
    const whitted::Camera camera =
      whitted::Camera::fromViewProjection(vtkWhittedToMat4(viewProjection));
    whitted::RenderSettings settings =
      vtkWhittedPassInternals::FrameSettings(this, cam, r.Conversion.HeadlightShading);
    // Progressive display: continue the still frame being refined if nothing changed since
    const vtkWhittedPassInternals::FrameKey key =
      vtkWhittedPassInternals::KeyOf(this, ren, viewProjection, traceWidth, traceHeight);
    if (this->Interactive || this->RefinementRoundsPerFrame == 0 || !(key == in->RefinementKey))
    {
      in->Refinement.reset();
    }
    in->RefinementKey = key;
    if (!this->Interactive && this->RefinementRoundsPerFrame > 0)
    {
      settings.refinement = &in->Refinement;
      settings.maxRefinementRounds = this->RefinementRoundsPerFrame;
      settings.refinementSlice = this->RefinementSliceTime;
    }
    // Edge widths in traced pixels: interactive frames (fewer, larger pixels) keep their edges
    SetPixelFootprint(settings.integrator, cam, ren->GetTiledAspectRatio(), traceHeight);
    cpu = std::clock();
    r.Trace =
      in->Trace(this, win, converter->GetScene(), camera, settings, traceWidth, traceHeight);
    r.CPUTime[2] = CPUSecondsSince(cpu);
  }
  catch (const std::exception& e)
  {
    this->FailFrame(converter, e.what());
    return;
  }
  catch (...)
  {
    this->FailFrame(converter, "unknown exception");
    return;
  }

  // Composite, then VTK's OpenGL stages for the props left to it (overlays last)
  const auto compositeStart = std::chrono::steady_clock::now();
  const std::clock_t compositeCPU = std::clock();
  in->Rendered = in->Composite(s, win, r.Conversion, viewport);
  r.CompositeTime = SecondsSince(compositeStart);
  r.CPUTime[3] = CPUSecondsSince(compositeCPU);
  // The frame is drawn: fast trees get their SAH build now, between frames
  converter->GetScene().startUpgrades();

  in->RecordStatistics(
    r, converter->GetScene().stats(), SecondsSince(start), this->LastFrameReport);
  this->InvokeEvent(vtkCommand::EndEvent);
}

//------------------------------------------------------------------------------
vtkWhittedPassInternals::FrameKey vtkWhittedPassInternals::KeyOf(
  vtkWhittedPass* pass, vtkRenderer* ren, const vtkMatrix4x4* view, int w, int h)
{
  FrameKey key;
  for (int i = 0; i < 16; ++i)
  {
    key.View[static_cast<size_t>(i)] = view->GetElement(i / 4, i % 4);
  }
  const double* bg = ren->GetBackground();
  const double* bg2 = ren->GetBackground2();
  key.Background = { bg[0], bg[1], bg[2], bg2[0], bg2[1], bg2[2],
    ren->GetGradientBackground() ? 1.0 : 0.0 };
  key.Width = w;
  key.Height = h;
  key.Pass = pass->GetMTime();
  // What the tracer sees of the props and lights: their MTimes (a prop's redraw time includes its
  // mapper, input, property and texture)
  vtkPropCollection* props = ren->GetViewProps();
  vtkCollectionSimpleIterator pit;
  props->InitTraversal(pit);
  while (vtkProp* prop = props->GetNextProp(pit))
  {
    key.Props = std::max({ key.Props, prop->GetMTime(), prop->GetRedrawMTime() });
  }
  vtkLightCollection* lights = ren->GetLights();
  vtkCollectionSimpleIterator lit;
  lights->InitTraversal(lit);
  while (vtkLight* light = lights->GetNextLight(lit))
  {
    key.Props = std::max(key.Props, light->GetMTime());
  }
  return key;
}

//------------------------------------------------------------------------------
const whitted::FrameBuffer& vtkWhittedPassInternals::DisplayedFrame(vtkWhittedPass* pass)
{
  const whitted::FrameBuffer& f = pass->GetShowErrorImage() ? this->ErrorDisplayed(pass) : this->Frame;
  if (pass->GetShadingErrorForTesting() <= 0)
  {
    return f;
  }
  // For testing only (see the setter): every 100th pixel hit by an opaque surface off by N/255
  this->Perturbed = f;
  const float step = static_cast<float>(pass->GetShadingErrorForTesting()) / 255.0f;
  for (size_t i = 0; i < f.color.size(); i += 100)
  {
    whitted::Color4& c = this->Perturbed.color[i];
    if (this->Frame.traced[i] && this->Frame.color[i].a >= 1.0f)
    {
      for (int k = 0; k < 3; ++k)
      {
        c[k] += c[k] > 0.5f ? -step : step;
      }
    }
  }
  return this->Perturbed;
}

//------------------------------------------------------------------------------
const whitted::FrameBuffer& vtkWhittedPassInternals::ErrorDisplayed(vtkWhittedPass* pass)
{
  // Grey = scale x (truncation bound + sampling estimate), opaque; depth as traced, so OpenGL
  // props still sort against the surfaces
  const whitted::FrameBuffer& f = this->Frame;
  this->ErrorDisplay.width = f.width;
  this->ErrorDisplay.height = f.height;
  this->ErrorDisplay.depth = f.depth;
  this->ErrorDisplay.color.resize(f.color.size());
  const float scale = static_cast<float>(pass->GetErrorImageScale());
  for (size_t i = 0; i < f.color.size(); ++i)
  {
    const float e = whitted::totalEstimate(f.truncation[i], f.sampling[i]);
    const float g = std::min(1.0f, scale * e);
    this->ErrorDisplay.color[i] = f.traced[i] ? whitted::Color4(g, g, g, 1.0f) : f.color[i];
  }
  return this->ErrorDisplay;
}

//------------------------------------------------------------------------------
whitted::RenderSettings vtkWhittedPassInternals::FrameSettings(
  vtkWhittedPass* pass, vtkCamera* cam, bool headlightShading)
{
  const bool interactive = pass->GetInteractive();
  whitted::RenderSettings rs;
  whitted::IntegratorSettings& is = rs.integrator;
  is.maxDepth = interactive ? std::min(pass->GetMaxDepth(), pass->GetInteractiveMaxDepth())
                            : pass->GetMaxDepth();
  is.shadows = pass->GetShadows() && (!interactive || pass->GetInteractiveShadows());
  is.reflections = pass->GetReflections();
  is.refractions = pass->GetRefractions();
  is.contributionThreshold = static_cast<float>(pass->GetContributionThreshold());
  is.fresnel = pass->GetFresnel();
  is.beerLambert = true; // only materials with an ATTENUATION_COLOR below 1 absorb
  is.headlightShading = headlightShading;
  // VTK's specular view vector comes from the camera position, also for parallel projection
  is.viewFromEye = cam->GetParallelProjection() != 0;
  double eye[3];
  cam->GetPosition(eye);
  is.eye = whitted::Vec3(eye[0], eye[1], eye[2]);
  rs.samplesPerPixel = interactive ? 1 : pass->GetSamplesPerPixel();
  rs.adaptive = !interactive && pass->GetAdaptiveSampling();
  // The error estimate is side data of still frames; interactive ones skip its extra pass
  rs.errorEstimates = !interactive;
  rs.targetError = interactive ? 0.0 : pass->GetTargetError();
  rs.timeBudget = interactive ? 0.0 : pass->GetTimeBudget();
  // Bound rays (the tight truncation bound) where the estimate steers refinement; a plain still frame reports the
  // scene-wide bound, which costs no ray (bound rays cost glass scenes 5-32% of a frame)
  is.truncationLookahead = rs.targetError > 0.0 || rs.timeBudget > 0.0 ? 1 : 0;
  rs.threads = pass->GetNumberOfThreads();
  rs.tileStride = pass->GetImageSplit()[0];
  rs.tileOffset = pass->GetImageSplit()[1];
  rs.abortAfterTiles = pass->GetAbortAfterTilesForTesting();
  return rs;
}

//------------------------------------------------------------------------------
whitted::FrameStats vtkWhittedPassInternals::Trace(vtkWhittedPass* pass, vtkOpenGLRenderWindow* win,
  const whitted::Scene& scene, const whitted::Camera& camera, whitted::RenderSettings settings,
  int width, int height)
{
  std::exception_ptr callbackError;
  settings.abortCheck = [win, &callbackError]()
  {
    try
    {
      return callbackError || win->CheckAbortStatus() != 0;
    }
    catch (...)
    {
      callbackError = std::current_exception();
      return true;
    }
  };
  settings.progress = [pass, &callbackError](double fraction)
  {
    try
    {
      if (!callbackError)
      {
        pass->InvokeEvent(vtkCommand::ProgressEvent, &fraction);
      }
    }
    catch (...)
    {
      callbackError = std::current_exception();
    }
  };
  const whitted::FrameStats stats =
    whitted::render(scene, camera, settings, width, height, this->Frame);
  if (callbackError)
  {
    std::rethrow_exception(callbackError);
  }
  return stats;
}

//------------------------------------------------------------------------------
int vtkWhittedPassInternals::Composite(const vtkRenderState* s, vtkOpenGLRenderWindow* win,
  const vtkWhittedSceneConverter::Result& conv, const int viewport[4])
{
  // The tracer's image is premultiplied RGBA at every sample count: drawn as it is, over the
  // environment props (skybox) that OpenGL draws first
  vtkRenderer* ren = s->GetRenderer();
  int rendered = conv.TracedActors;
  if (!conv.BackgroundProps.empty())
  {
    vtkRenderState bgState(ren);
    bgState.SetPropArrayAndCount(const_cast<vtkProp**>(conv.BackgroundProps.data()),
      static_cast<int>(conv.BackgroundProps.size()));
    bgState.SetFrameBuffer(s->GetFrameBuffer());
    this->OpaquePass->Render(&bgState);
    rendered += this->OpaquePass->GetNumberOfRenderedProps();
  }
  if (!this->Compositor.Draw(win, this->DisplayedFrame(this->Parent), viewport[0], viewport[1],
        viewport[2], viewport[3]))
  {
    vtkErrorWithObjectMacro(this->Parent, "Could not build the compositing shader.");
  }
  vtkRenderState glState(ren);
  glState.SetPropArrayAndCount(
    conv.OpenGLProps.empty() ? nullptr : const_cast<vtkProp**>(conv.OpenGLProps.data()),
    static_cast<int>(conv.OpenGLProps.size()));
  glState.SetFrameBuffer(s->GetFrameBuffer());
  for (vtkRenderPass* pass : { static_cast<vtkRenderPass*>(this->OpaquePass),
         static_cast<vtkRenderPass*>(this->TranslucentPass),
         static_cast<vtkRenderPass*>(this->VolumetricPass),
         static_cast<vtkRenderPass*>(this->OverlayPass) })
  {
    pass->Render(&glState);
    rendered += pass->GetNumberOfRenderedProps();
  }
  return rendered;
}

//------------------------------------------------------------------------------
void vtkWhittedPassInternals::RecordStatistics(
  const FrameResult& r, const whitted::SceneStats& scene, double totalTime, std::string& report)
{
  vtkWhittedFrameStatistics* st = this->Statistics;
  const whitted::RayStats& rays = r.Trace.rays;
  st->ConversionTime = r.ConversionTime;
  st->BuildTime = r.Commit.secondsBuild;
  st->TraceTime = r.Trace.secondsTrace;
  st->CompositeTime = r.CompositeTime;
  st->TotalTime = totalTime;
  st->PrimaryRays = rays.primary;
  st->ShadowRays = rays.shadow;
  st->ReflectionRays = rays.reflection;
  st->RefractionRays = rays.refraction;
  st->RaysSavedByThreshold = rays.savedByThreshold;
  st->RaysSavedByDepth = rays.savedByDepth;
  st->BoundRays = rays.boundRays;
  st->NumberOfTriangles = scene.triangles;
  st->NumberOfSpheres = scene.spheres;
  st->NumberOfTubes = scene.tubes;
  st->NumberOfInstances = scene.tracedInstances;
  st->BVHBytes = scene.bvhBytes;
  st->NumberOfTextures = scene.textures;
  st->TextureBytes = scene.textureBytes;
  st->Size[0] = this->Frame.width;
  st->Size[1] = this->Frame.height;
  st->NumberOfGeometriesConverted = r.Conversion.GeometriesConverted;
  st->NumberOfObjectsRebuilt = r.Commit.objectsRebuilt;
  st->NumberOfObjectsRefit = r.Commit.objectsRefit;
  st->NumberOfObjectsUpgraded = r.Commit.objectsUpgraded;
  st->WaitedForUpgrade = r.Commit.waitedForUpgrade;
  st->UpgradeRestarted = r.Commit.upgradeRestarted;
  st->NumberOfFastTrees = static_cast<int>(scene.fastTrees);
  st->ConversionCPUTime = r.CPUTime[0];
  st->BuildCPUTime = r.CPUTime[1];
  st->TraceCPUTime = r.CPUTime[2];
  st->CompositeCPUTime = r.CPUTime[3];
  st->NumberOfRefitsRejected = r.Commit.objectsRefitRejected;
  st->RefitCostRatio = r.Commit.refitCostRatio;
  st->NumberOfTimeCacheHits = r.Conversion.TimeCacheHits;
  st->NumberOfTimeCacheEntries = r.Conversion.TimeCacheEntries;
  st->TimeCacheBytes = r.Conversion.TimeCacheBytes;
  st->TopLevelRebuilt = r.Commit.topLevelRebuilt;
  st->NumberOfTracedActors = r.Conversion.TracedActors;
  st->NumberOfOpenGLProps = static_cast<int>(r.Conversion.OpenGLProps.size());
  st->NumberOfSafetyNetCatches = rays.safetyNetCatches();
  st->Aborted = r.Trace.aborted;
  st->Failed = false;
  const whitted::ErrorSummary* summaries[3] = { &r.Trace.truncation, &r.Trace.sampling,
    &r.Trace.total };
  double* fields[3] = { st->TruncationError, st->SamplingError, st->EstimatedError };
  for (int k = 0; k < 3; ++k)
  {
    fields[k][0] = summaries[k]->rms;
    fields[k][1] = summaries[k]->p95;
    fields[k][2] = summaries[k]->max;
  }
  st->NumberOfSamples = r.Trace.samples;
  st->RefinementRounds = r.Trace.refinementRounds;
  st->TargetErrorMet = r.Trace.targetMet;
  st->RefinementFinished = r.Trace.refinementFinished;
  st->RefinementSeconds =
    this->Refinement.pixels.empty() ? r.Trace.secondsTrace : this->Refinement.seconds;
  st->Modified();

  report = whitted::frameReport(r.Trace, scene, r.Commit, this->Frame.width, this->Frame.height,
    r.ConversionTime, "conversion");
  char line[256];
  std::snprintf(line, sizeof line,
    "  vtk              composite %.2f ms, total %.2f ms; %d actors traced (%d geometries "
    "converted), %d props drawn by OpenGL\n",
    r.CompositeTime * 1e3, totalTime * 1e3, r.Conversion.TracedActors,
    r.Conversion.GeometriesConverted, st->NumberOfOpenGLProps);
  report += line;
  std::snprintf(line, sizeof line,
    "  CPU time         conversion %.2f ms, build %.2f ms, trace %.2f ms, composite %.2f ms "
    "(process, all threads)\n"
    "  trees            %d objects traced with the fast tree, %d upgraded to the SAH tree in this "
    "frame%s%s\n",
    r.CPUTime[0] * 1e3, r.CPUTime[1] * 1e3, r.CPUTime[2] * 1e3, r.CPUTime[3] * 1e3,
    st->NumberOfFastTrees, st->NumberOfObjectsUpgraded,
    st->WaitedForUpgrade ? "; the build phase waited for the background build" : "",
    st->UpgradeRestarted ? "; the background build restarted at normal priority (priority not raisable)" : "");
  report += line;
  std::snprintf(line, sizeof line,
    "  time cache       %d hits; holds %d geometries, %.1f MB (limit %d MB)\n",
    r.Conversion.TimeCacheHits, r.Conversion.TimeCacheEntries,
    static_cast<double>(r.Conversion.TimeCacheBytes) / (1 << 20),
    this->Parent->GetTimeCacheMemory());
  report += line;
}

//------------------------------------------------------------------------------
void vtkWhittedPass::FailFrame(vtkWhittedSceneConverter* converter, const char* what)
{
  vtkWhittedPassInternals* in = this->Internals;
  vtkErrorMacro(<< "Ray tracing failed (" << what
                << "): this frame shows only the background; the scene will be converted again "
                   "from scratch at the next render.");
  // A conversion or BVH build interrupted half-way leaves the caches in an unknown state: drop
  // them (and the memory they hold)
  if (converter)
  {
    converter->Reset();
  }
  in->Frame = whitted::FrameBuffer();
  in->Refinement.reset();
  in->Rendered = 0;
  in->Statistics->Reset();
  in->Statistics->Failed = true;
  this->LastFrameReport = std::string("frame failed: ") + what + "\n";
  this->InvokeEvent(vtkCommand::EndEvent);
}

//------------------------------------------------------------------------------
vtkWhittedFrameStatistics* vtkWhittedPass::GetLastFrameStatistics()
{
  return this->Internals->Statistics;
}

//------------------------------------------------------------------------------
void vtkWhittedPass::GetLastFrame(vtkFloatArray* rgba, vtkFloatArray* depth)
{
  const whitted::FrameBuffer& fb = this->Internals->Frame;
  const vtkIdType n = static_cast<vtkIdType>(fb.width) * fb.height;
  const bool valid =
    n > 0 && fb.color.size() == static_cast<size_t>(n) && fb.depth.size() == static_cast<size_t>(n);
  if (rgba)
  {
    rgba->SetNumberOfComponents(4);
    rgba->SetNumberOfTuples(valid ? n : 0);
    for (vtkIdType i = 0; valid && i < n; ++i)
    {
      const whitted::Color4& c = fb.color[i];
      const float v[4] = { c.r, c.g, c.b, c.a };
      rgba->SetTypedTuple(i, v);
    }
  }
  if (depth)
  {
    depth->SetNumberOfComponents(1);
    depth->SetNumberOfTuples(valid ? n : 0);
    for (vtkIdType i = 0; valid && i < n; ++i)
    {
      depth->SetValue(i, fb.depth[i]);
    }
  }
}

//------------------------------------------------------------------------------
void vtkWhittedPass::GetLastErrorImage(vtkImageData* image)
{
  if (!image)
  {
    return;
  }
  const whitted::FrameBuffer& fb = this->Internals->Frame;
  const vtkIdType n = static_cast<vtkIdType>(fb.width) * fb.height;
  const bool valid = n > 0 && fb.truncation.size() == static_cast<size_t>(n) &&
    fb.sampling.size() == static_cast<size_t>(n) && fb.samples.size() == static_cast<size_t>(n);
  image->Initialize();
  image->SetDimensions(valid ? fb.width : 0, valid ? fb.height : 0, valid ? 1 : 0);
  const char* names[4] = { "TruncationError", "SamplingError", "EstimatedError", "Samples" };
  vtkNew<vtkFloatArray> arrays[4];
  for (int k = 0; k < 4; ++k)
  {
    arrays[k]->SetName(names[k]);
    arrays[k]->SetNumberOfTuples(valid ? n : 0);
  }
  for (vtkIdType i = 0; valid && i < n; ++i)
  {
    arrays[0]->SetValue(i, fb.truncation[i]);
    arrays[1]->SetValue(i, fb.sampling[i]);
    arrays[2]->SetValue(i, whitted::totalEstimate(fb.truncation[i], fb.sampling[i]));
    arrays[3]->SetValue(i, static_cast<float>(fb.samples[i]));
  }
  for (int k = 0; k < 4; ++k)
  {
    image->GetPointData()->AddArray(arrays[k]);
  }
  image->GetPointData()->SetActiveScalars("EstimatedError");
}
