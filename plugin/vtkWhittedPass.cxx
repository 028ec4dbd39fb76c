#include "vtkWhittedPass.h"

#include "vtkWhittedCompositor.h"
#include "vtkWhittedSceneConverter.h"

#include "vtkCamera.h"
#include "vtkCameraPass.h"
#include "vtkCommand.h"
#include "vtkFloatArray.h"
#include "vtkFrameBufferObjectBase.h"
#include "vtkHardwareSelector.h"
#include "vtkInformationDoubleKey.h"
#include "vtkInformationDoubleVectorKey.h"
#include "vtkLightsPass.h"
#include "vtkMatrix4x4.h"
#include "vtkObjectFactory.h"
#include "vtkOpaquePass.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOverlayPass.h"
#include "vtkRenderPassCollection.h"
#include "vtkRenderState.h"
#include "vtkRenderer.h"
#include "vtkSequencePass.h"
#include "vtkTranslucentPass.h"
#include "vtkVolumetricPass.h"
#include "vtkWeakPointer.h"

#include "camera.h"
#include "renderer.h"
#include "report.h"
#include "scene.h"

#include <chrono>
#include <cstdio>
#include <exception>
#include <map>
#include <memory>

namespace
{
double SecondsSince(std::chrono::steady_clock::time_point t)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
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

protected:
  vtkWhittedPassInternals() = default;
  ~vtkWhittedPassInternals() override = default;
};

vtkStandardNewMacro(vtkWhittedPassInternals);

//------------------------------------------------------------------------------
vtkStandardNewMacro(vtkWhittedPass);
vtkInformationKeyMacro(vtkWhittedPass, REFLECTANCE, DoubleVector);
vtkInformationKeyMacro(vtkWhittedPass, TRANSMITTANCE, DoubleVector);
vtkInformationKeyMacro(vtkWhittedPass, INDEX_OF_REFRACTION, Double);

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
  os << indent << "ContributionThreshold: " << this->ContributionThreshold << "\n";
  os << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
  os << indent << "Fresnel: " << this->Fresnel << "\n";
  os << indent << "ImageSplit: " << this->ImageSplit[0] << " " << this->ImageSplit[1] << "\n";
  os << indent << "ImageReductionFactor: " << this->ImageReductionFactor << "\n";
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

  // Image size: the renderer's (tiled) viewport, or the render state's framebuffer
  int width = 0, height = 0, x = 0, y = 0;
  if (vtkFrameBufferObjectBase* fbo = s->GetFrameBuffer())
  {
    fbo->GetLastSize(width, height);
  }
  else
  {
    ren->GetTiledSizeAndOrigin(&width, &height, &x, &y);
  }
  // Reduced resolution (interactive frames): the same camera, fewer pixels, stretched when drawn
  const int traceWidth = (width + this->ImageReductionFactor - 1) / this->ImageReductionFactor;
  const int traceHeight = (height + this->ImageReductionFactor - 1) / this->ImageReductionFactor;

  // Conversion, BVH builds and tracing may throw (std::bad_alloc for a scene too large for memory,
  // or an exception from an observer of the abort check / progress): the frame then fails cleanly
  vtkWhittedSceneConverter::Result conv;
  vtkWhittedSceneConverter* converter = nullptr;
  whitted::Scene* scenePtr = nullptr;
  whitted::CommitStats commit;
  whitted::FrameStats frame;
  try
  {
    // Scene conversion (cached) and BVH builds of what changed
    converter = &in->ConverterFor(ren);
    converter->Update(ren, s->GetPropArray(), s->GetPropArrayCount(), this, conv);
    scenePtr = &converter->GetScene();
    this->LastConversionTime = SecondsSince(start);
    commit = scenePtr->commit();

    // Camera: rays from the inverse of VTK's composite projection (tiles, IceT viewports)
    vtkCamera* cam = ren->GetActiveCamera();
    vtkMatrix4x4* m = cam->GetCompositeProjectionTransformMatrix(ren->GetTiledAspectRatio(), -1, 1);
    whitted::Mat4 worldToClip(1.0);
    for (int r = 0; r < 4; ++r)
    {
      for (int c = 0; c < 4; ++c)
      {
        worldToClip[c][r] = m->GetElement(r, c);
      }
    }
    const whitted::Camera camera = whitted::Camera::fromViewProjection(worldToClip);

    // Trace. The callbacks run on this thread between tiles while worker threads trace: an
    // exception must not unwind through the tracer, so it aborts the frame and is rethrown after.
    whitted::RenderSettings rs;
    rs.integrator.maxDepth = this->MaxDepth;
    rs.integrator.shadows = this->Shadows;
    rs.integrator.reflections = this->Reflections;
    rs.integrator.refractions = this->Refractions;
    rs.integrator.contributionThreshold = static_cast<float>(this->ContributionThreshold);
    rs.integrator.fresnel = this->Fresnel;
    rs.integrator.headlightShading = conv.HeadlightShading;
    // VTK's specular view vector comes from the camera position, also for parallel projection
    rs.integrator.viewFromEye = cam->GetParallelProjection() != 0;
    double eye[3];
    cam->GetPosition(eye);
    rs.integrator.eye = whitted::Vec3(eye[0], eye[1], eye[2]);
    rs.samplesPerPixel = this->SamplesPerPixel;
    rs.adaptive = this->AdaptiveSampling;
    rs.threads = this->NumberOfThreads;
    rs.tileStride = this->ImageSplit[0];
    rs.tileOffset = this->ImageSplit[1];
    std::exception_ptr callbackError;
    rs.abortCheck = [win, &callbackError]()
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
    rs.progress = [this, &callbackError](double fraction)
    {
      try
      {
        if (!callbackError)
        {
          this->InvokeEvent(vtkCommand::ProgressEvent, &fraction);
        }
      }
      catch (...)
      {
        callbackError = std::current_exception();
      }
    };
    frame = whitted::render(*scenePtr, camera, rs, traceWidth, traceHeight, in->Frame);
    if (callbackError)
    {
      std::rethrow_exception(callbackError);
    }
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
  whitted::Scene& scene = *scenePtr;

  // Composite colour + depth, then VTK's OpenGL stages for the props left to it
  // The tracer's image is premultiplied RGBA at every sample count: drawn as it is, over the
  // environment props (skybox) that OpenGL draws first
  const auto compositeStart = std::chrono::steady_clock::now();
  int rendered = conv.TracedActors;
  if (!conv.BackgroundProps.empty())
  {
    vtkRenderState bgState(ren);
    bgState.SetPropArrayAndCount(
      conv.BackgroundProps.data(), static_cast<int>(conv.BackgroundProps.size()));
    bgState.SetFrameBuffer(s->GetFrameBuffer());
    in->OpaquePass->Render(&bgState);
    rendered += in->OpaquePass->GetNumberOfRenderedProps();
  }
  if (!in->Compositor.Draw(win, in->Frame, x, y, width, height))
  {
    vtkErrorMacro("Could not build the compositing shader.");
  }
  vtkRenderState glState(ren);
  glState.SetPropArrayAndCount(conv.OpenGLProps.empty() ? nullptr : conv.OpenGLProps.data(),
    static_cast<int>(conv.OpenGLProps.size()));
  glState.SetFrameBuffer(s->GetFrameBuffer());
  for (vtkRenderPass* pass :
    { static_cast<vtkRenderPass*>(in->OpaquePass), static_cast<vtkRenderPass*>(in->TranslucentPass),
      static_cast<vtkRenderPass*>(in->VolumetricPass),
      static_cast<vtkRenderPass*>(in->OverlayPass) })
  {
    pass->Render(&glState);
    rendered += pass->GetNumberOfRenderedProps();
  }
  in->Rendered = rendered;
  this->LastCompositeTime = SecondsSince(compositeStart);

  // Statistics
  const whitted::SceneStats sstats = scene.stats();
  this->LastBuildTime = commit.secondsBuild;
  this->LastTraceTime = frame.secondsTrace;
  this->LastTotalTime = SecondsSince(start);
  this->LastPrimaryRays = frame.rays.primary;
  this->LastShadowRays = frame.rays.shadow;
  this->LastReflectionRays = frame.rays.reflection;
  this->LastRefractionRays = frame.rays.refraction;
  this->LastRaysSavedByThreshold = frame.rays.savedByThreshold;
  this->LastRaysSavedByDepth = frame.rays.savedByDepth;
  this->LastNumberOfTriangles = sstats.triangles;
  this->LastNumberOfSpheres = sstats.spheres;
  this->LastNumberOfTubes = sstats.capsules;
  this->LastBVHBytes = sstats.bvhBytes;
  this->LastNumberOfTextures = sstats.textures;
  this->LastTextureBytes = sstats.textureBytes;
  this->LastSize[0] = traceWidth;
  this->LastSize[1] = traceHeight;
  this->LastNumberOfGeometriesConverted = conv.GeometriesConverted;
  this->LastNumberOfObjectsRebuilt = commit.objectsRebuilt;
  this->LastTopLevelRebuilt = commit.topLevelRebuilt;
  this->LastNumberOfTracedActors = conv.TracedActors;
  this->LastNumberOfOpenGLProps = static_cast<int>(conv.OpenGLProps.size());
  this->LastFrameAborted = frame.aborted;
  this->LastFrameFailed = false;
  this->LastNumberOfSafetyNetCatches = frame.rays.safetyNetCatches();

  this->LastFrameReport = whitted::frameReport(
    frame, sstats, commit, traceWidth, traceHeight, this->LastConversionTime, "conversion");
  char line[256];
  std::snprintf(line, sizeof line,
    "  vtk              composite %.2f ms, total %.2f ms; %d actors traced (%d geometries "
    "converted), %d props drawn by OpenGL\n",
    this->LastCompositeTime * 1e3, this->LastTotalTime * 1e3, conv.TracedActors,
    conv.GeometriesConverted, this->LastNumberOfOpenGLProps);
  this->LastFrameReport += line;

  this->InvokeEvent(vtkCommand::EndEvent);
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
  in->Rendered = 0;
  this->LastFrameFailed = true;
  this->LastFrameAborted = false;
  this->LastBuildTime = this->LastTraceTime = this->LastCompositeTime = 0.0;
  this->LastPrimaryRays = this->LastShadowRays = this->LastReflectionRays = 0;
  this->LastRefractionRays = this->LastRaysSavedByThreshold = this->LastRaysSavedByDepth = 0;
  this->LastNumberOfTriangles = this->LastNumberOfSpheres = this->LastNumberOfTubes = 0;
  this->LastBVHBytes = 0;
  this->LastNumberOfTextures = this->LastTextureBytes = 0;
  this->LastSize[0] = this->LastSize[1] = 0;
  this->LastNumberOfGeometriesConverted = this->LastNumberOfObjectsRebuilt = 0;
  this->LastTopLevelRebuilt = false;
  this->LastNumberOfSafetyNetCatches = 0;
  this->LastNumberOfTracedActors = this->LastNumberOfOpenGLProps = 0;
  this->LastFrameReport = std::string("frame failed: ") + what + "\n";
  this->InvokeEvent(vtkCommand::EndEvent);
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
