/**
 * @class   vtkWhittedPassInternals
 * @brief   private to vtkWhittedPass: the render pass's chain, caches, frame and statistics
 *
 * Shared by the pass's sources, one concept each: vtkWhittedPass.cxx (construction, settings,
 * entry points), vtkWhittedPassFrame.cxx (one frame: convert, commit, trace, composite; a failed
 * frame), vtkWhittedPassStatistics.cxx (what the last frame leaves: statistics, report, images).
 */

#ifndef vtkWhittedPassInternals_h
#define vtkWhittedPassInternals_h

#include "vtkWhittedCompositor.h"
#include "vtkWhittedFrameStatistics.h"
#include "vtkWhittedPass.h"
#include "vtkWhittedSceneConverter.h"

#include "vtkCameraPass.h"
#include "vtkLightsPass.h"
#include "vtkNew.h"
#include "vtkOpaquePass.h"
#include "vtkOverlayPass.h"
#include "vtkRenderPass.h"
#include "vtkRenderer.h" // for vtkWeakPointer<vtkRenderer>
#include "vtkSequencePass.h"
#include "vtkTranslucentPass.h"
#include "vtkVolumetricPass.h"
#include "vtkWeakPointer.h"

#include "image/renderer.h"
#include "scene/scene.h"
#include "shading/camera.h"

#include <array>
#include <map>
#include <memory>
#include <string>

class vtkCamera;
class vtkMatrix4x4;
class vtkOpenGLRenderWindow;

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

#endif
// VTK-HeaderTest-Exclude: vtkWhittedPassInternals.h
