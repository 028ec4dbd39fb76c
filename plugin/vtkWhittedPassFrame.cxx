#include "vtkWhittedPass.h"

#include "vtkWhittedMatrix.h"
#include "vtkWhittedPassInternals.h"

#include "vtkCamera.h"
#include "vtkCommand.h"
#include "vtkFrameBufferObjectBase.h"
#include "vtkHardwareSelector.h"
#include "vtkLight.h"
#include "vtkLightCollection.h"
#include "vtkMatrix4x4.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkPropCollection.h"
#include "vtkRenderState.h"
#include "vtkRenderer.h"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <exception>

// One frame of the pass (see vtkWhittedPassInternals.h): convert -> commit -> trace -> composite,
// the settings and progressive-display key it is traced with, what it displays, a failed frame.

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
    converter->SetShadowsFromBrightestLightOnly(this->ShadowsFromBrightestLightOnly);
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
  // Likewise the volumes' step estimate (each ray through a volume marches it again at twice the step: 1.5x the
  // volume samples), which lets refinement halve the step
  is.volumeStepEstimate = rs.targetError > 0.0 || rs.timeBudget > 0.0;
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
  int rendered = conv.TracedActors + conv.TracedVolumes;
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
