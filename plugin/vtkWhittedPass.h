/**
 * @class   vtkWhittedPass
 * @brief   a render pass that draws a renderer's actors with a Whitted-style ray tracer
 *
 * Put it on a renderer (`renderer->SetPass(pass)`) and the same scene comes out ray traced: VTK's
 * own surface shading (ambient, diffuse, specular, lights, normals, scalar colours, textures) plus
 * shadows, mirror reflection and refraction, composited into the normal VTK view with true OpenGL
 * depth.
 *
 * Data flow of one frame:
 *   vtkCameraPass (clears, viewport) -> vtkLightsPass (light geometry, automatic headlight)
 *   -> scene conversion (vtkWhittedSceneConverter: actors -> core scene, cached by MTime)
 *   -> BVH build of changed objects -> trace (core renderer, all cores)
 *   -> composite colour + depth into the framebuffer (vtkWhittedCompositor)
 *   -> VTK's own OpenGL stages for every prop the tracer does not handle (2D actors, volumes, image
 *      slices, plain points/lines/wireframe), depth-tested against the traced image, then overlays.
 *
 * Whitted materials are set per actor with information keys on its vtkProperty (the keys:
 * vtkWhittedMaterialKeys):
 * @code
 *   vtkInformation* info = prop->GetInformation();
 *   double kr = 0.8;
 *   info->Set(vtkWhittedMaterialKeys::REFLECTANCE(), &kr, 1);         // grey mirror
 *   double kt[3] = { 0.9, 0.9, 0.8 };
 *   info->Set(vtkWhittedMaterialKeys::TRANSMITTANCE(), kt, 3);        // tinted glass
 *   info->Set(vtkWhittedMaterialKeys::INDEX_OF_REFRACTION(), 1.5);
 *   double gold[3] = { 1.0, 0.78, 0.34 };
 *   info->Set(vtkWhittedMaterialKeys::REFLECTANCE(), gold, 3);        // coloured metal
 *   double tint[3] = { 0.6, 0.9, 0.8 };                                // after 2 world units
 *   info->Set(vtkWhittedMaterialKeys::ATTENUATION_COLOR(), tint, 3);  // of glass, light
 *   info->Set(vtkWhittedMaterialKeys::ATTENUATION_DISTANCE(), 2.0);   // keeps this colour
 * @endcode
 * Without keys an actor keeps its VTK look: reflectance 0, transmittance 1 - Opacity, index 1.
 * Energy rule: the body colour (ambient + diffuse) is weighted by min(Opacity, 1 - max over
 * channels of (REFLECTANCE + TRANSMITTANCE)), the specular highlight by Opacity, so that
 * TRANSMITTANCE 1 alone is clear glass and REFLECTANCE 1 alone a mirror, and the default keys keep
 * VTK's translucency exactly. Named materials (Glass, Gold, ...) and OSPRay material libraries:
 * vtkWhittedMaterialLibrary.
 *
 * The settings (MaxDepth, SamplesPerPixel, ...) have their defaults and ranges in one table,
 * vtkWhittedSettings.h. The statistics of the last frame (time per phase, rays by kind, scene size,
 * what was rebuilt) are in GetLastFrameStatistics(), and as text in GetLastFrameReport().
 *
 * @sa vtkRenderPass vtkOSPRayPass vtkWhittedMaterialKeys vtkWhittedFrameStatistics
 * vtkWhittedSettings.h
 */

#ifndef vtkWhittedPass_h
#define vtkWhittedPass_h

#include "vtkRenderPass.h"
#include "vtkWhittedModule.h"   // For export macro
#include "vtkWhittedSettings.h" // For the settings' defaults and ranges

#include <string> // for std::string

class vtkFloatArray;
class vtkImageData;
class vtkInformationDoubleKey;
class vtkInformationDoubleVectorKey;
class vtkInformationObjectBaseKey;
class vtkInformationStringKey;
class vtkWhittedFrameStatistics;
class vtkWhittedPassInternals;
class vtkWhittedSceneConverter;

// The pass's part of the settings table: accessors and members of the Pass rows
#define VTK_WHITTED_PASS_ACCESSORS(owner, type, name, def, min, max, doc)                          \
  VTK_WHITTED_PASS_ACCESSORS_##owner(type, name)
#define VTK_WHITTED_PASS_ACCESSORS_Pass(type, name) VTK_WHITTED_SETTING_ACCESSORS_##type(name)
#define VTK_WHITTED_PASS_ACCESSORS_View(type, name)
#define VTK_WHITTED_PASS_MEMBERS(owner, type, name, def, min, max, doc)                            \
  VTK_WHITTED_PASS_MEMBERS_##owner(type, name)
#define VTK_WHITTED_PASS_MEMBERS_Pass(type, name) VTK_WHITTED_SETTING_MEMBER(type, name)
#define VTK_WHITTED_PASS_MEMBERS_View(type, name)

class VTKWHITTED_EXPORT vtkWhittedPass : public vtkRenderPass
{
public:
  static vtkWhittedPass* New();
  vtkTypeMacro(vtkWhittedPass, vtkRenderPass);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * Perform rendering according to a render state s.
   */
  void Render(const vtkRenderState* s) override;

  /**
   * Release the OpenGL objects of the compositor and of the passes used for
   * props drawn by OpenGL.
   */
  void ReleaseGraphicsResources(vtkWindow* w) override;

  ///@{
  /**
   * The settings: SetX, GetX (numbers: setters clamp to the range, reported by GetXMinValue and
   * GetXMaxValue; booleans also XOn, XOff), generated from the settings table,
   * vtkWhittedSettings.h, which holds the meaning, default and range of each (also
   * plugin/README.md). Full-quality frames:
   * MaxDepth: secondary bounces (reflection, refraction) per camera ray.
   * SamplesPerPixel: stratified, jittered camera rays per pixel.
   * AdaptiveSampling: SamplesPerPixel only where the neighbouring pixels do not predict a pixel.
   * Shadows, Reflections, Refractions: trace shadow, mirror, bent transmitted rays.
   * ShadowsFromBrightestLightOnly: shadow rays toward the brightest light only.
   * Fresnel: exact dielectric Fresnel at refracting surfaces.
   * ContributionThreshold: secondary rays of a smaller path weight are not traced.
   * TargetError, TimeBudget: progressive refinement of still frames, steered by the per-pixel error
   * estimate (GetLastErrorImage): the pixels whose estimate is largest get more samples, or are
   * traced again at a deeper depth and lower threshold where the truncation bound dominates, until
   * the calibrated RMS estimate (vtkWhittedFrameStatistics::GetRMSError) is at most TargetError or
   * TimeBudget seconds of tracing are spent.
   * ShowErrorImage, ErrorImageScale: draw the estimated error (grey = scale x error) instead of
   * the rendering.
   * NumberOfThreads: tracing threads; 0 = every core the process may run on.
   * TimeCacheMemory: megabytes for the converted geometry and BVHs of earlier inputs of the same
   * objects (earlier time steps), kept so that showing them again converts and builds nothing
   * (statistics: GetNumberOfTimeCacheHits); 0 = off. Unlike a cache keyed by time, entries are
   * keyed by a fingerprint of the data's contents and the mapper's colouring state, so an
   * upstream edit never shows stale geometry.
   * InteractiveMaxDepth, InteractiveShadows: the interactive quality (see SetInteractive below).
   */
  VTK_WHITTED_SETTINGS(VTK_WHITTED_PASS_ACCESSORS)
  ///@}

  ///@{
  /**
   * Interactive quality, for frames traced while the camera moves: while Interactive is on, frames
   * use one sample per pixel without adaptive sampling, at most InteractiveMaxDepth bounces, shadow
   * rays only if InteractiveShadows (and Shadows) is on, and are traced at
   * 1/InteractiveImageReduction of the viewport's width and height and stretched over it (nearest
   * neighbour, colour and depth). The full-quality settings above are left as they are, so turning
   * Interactive off is all it takes to get full quality back. vtkPVWhittedView sets Interactive for
   * each of its frames. Interactive default off, InteractiveImageReduction default 1;
   * InteractiveMaxDepth and InteractiveShadows: settings above.
   */
  vtkSetMacro(Interactive, bool);
  vtkGetMacro(Interactive, bool);
  vtkBooleanMacro(Interactive, bool);
  vtkSetClampMacro(
    InteractiveImageReduction, int, 1, vtkWhittedSettings::MaximumImageReduction.Maximum);
  vtkGetMacro(InteractiveImageReduction, int);
  ///@}

  ///@{
  /**
   * Progressive display of still frames that refine (TargetError or TimeBudget): with
   * RefinementRoundsPerFrame N > 0 a still frame runs at most N refinement rounds and keeps its
   * per-pixel sums; the next still Render() with the same camera, size, props, lights and settings
   * continues from them, so rendering again while GetLastFrameStatistics()->GetRefinementFinished()
   * is false shows the image improve round by round (TimeBudget counts the tracing time of all
   * those frames). An interactive frame or any change starts over. 0 (the default): every still
   * frame refines fully.
   */
  vtkSetClampMacro(RefinementRoundsPerFrame, int, 0, 1024);
  vtkGetMacro(RefinementRoundsPerFrame, int);
  ///@}

  ///@{
  /**
   * Progressive display (RefinementRoundsPerFrame > 0): seconds after which a still frame's
   * refinement starts no new tile, so a Render() returns within about this time plus one tile
   * (an abort through the render window's abort check, checked between tiles, cuts it short the
   * same way). A round cut short is finished first by the next Render(), so the frames reached are
   * those of uncut rounds. 0 (the default): a Render() runs its rounds whole.
   */
  vtkSetClampMacro(RefinementSliceTime, double, 0.0, 3600.0);
  vtkGetMacro(RefinementSliceTime, double);
  ///@}

  ///@{
  /**
   * Image split between processes for sort-last compositing (ParaView/IceT with the scene
   * replicated on every process): trace only the 16x16 tiles whose index modulo stride equals
   * offset and leave every other pixel as cleared (depth 1, alpha 0), so that the depth or
   * ordered-blend composite of `stride` processes with offsets 0..stride-1 is the whole image.
   * Default 1, 0 (trace everything).
   */
  void SetImageSplit(int stride, int offset);
  vtkGetVector2Macro(ImageSplit, int);
  ///@}

  ///@{
  /**
   * Kept for compatibility: the Whitted information keys now live on vtkWhittedMaterialKeys,
   * where they are documented. Each of these returns the very same key object as the function of
   * that name there (vtkWhittedPass::REFLECTANCE() == vtkWhittedMaterialKeys::REFLECTANCE()), so
   * code and scripts written against either spelling set and read the same keys.
   */
  static vtkInformationDoubleVectorKey* REFLECTANCE();
  static vtkInformationDoubleVectorKey* TRANSMITTANCE();
  static vtkInformationDoubleKey* INDEX_OF_REFRACTION();
  static vtkInformationDoubleVectorKey* ATTENUATION_COLOR();
  static vtkInformationDoubleKey* ATTENUATION_DISTANCE();
  static vtkInformationStringKey* RADIUS_ARRAY();
  static vtkInformationObjectBaseKey* RADIUS_FUNCTION();
  ///@}

  ///@{
  /**
   * For testing only: the frame aborts, as if the window's AbortRender had been set, when tracing
   * would start its tile number N (16x16 tiles, rows bottom to top, this process's tiles only):
   * exactly the first N tiles are traced, whatever the thread count and scheduling, so a test of
   * an aborted frame does not depend on when a thread runs. -1 (the default): never.
   */
  vtkSetMacro(AbortAfterTilesForTesting, int);
  vtkGetMacro(AbortAfterTilesForTesting, int);
  ///@}

  ///@{
  /**
   * For testing only (negative controls of the image tests): a deliberately wrong image, to prove
   * that the image tests catch a small shading error. N > 0: the displayed colour of every 100th
   * pixel of the traced frame (pixel index i % 100 == 0, rows bottom to top) that the tracer hit
   * with an opaque surface (alpha 1) is moved by N/255 in each channel (down where the channel is
   * above 0.5, else up): up to 1% of the pixels, N/255 each. GetLastFrame() still returns the
   * unperturbed frame. 0 (the default): the image as traced.
   */
  vtkSetClampMacro(ShadingErrorForTesting, int, 0, 255);
  vtkGetMacro(ShadingErrorForTesting, int);
  ///@}

  /**
   * What the last frame did: time per phase, rays by kind, scene size, what was converted and
   * rebuilt, safety nets, whether it was aborted or failed. The same object is updated by every
   * frame.
   */
  vtkWhittedFrameStatistics* GetLastFrameStatistics();

  /**
   * Waits until the background SAH builds of new geometry have finished (see
   * vtkWhittedFrameStatistics::GetNumberOfFastTrees); the next frame swaps them in. Frames never
   * wait for them on their own: the builds use only idle cores. For scripts and benchmarks that
   * want the final tree.
   */
  void WaitForBackgroundBuilds();

  /**
   * Copies the tracer's image of the last frame (before compositing): colour as 4-component linear
   * RGBA floats as the tracer wrote them, and OpenGL window depth (1 component, 1 where nothing
   * was hit), rows bottom to top, GetLastFrameStatistics()->GetSize() pixels. Either array may be
   * null. Empty after a failed frame. For tests and diagnostics (e.g. checking that no pixel is NaN
   * or infinite).
   */
  void GetLastFrame(vtkFloatArray* rgba, vtkFloatArray* depth);

  /**
   * The last frame's per-pixel error estimate as an image of GetLastFrameStatistics()->GetSize()
   * points (rows bottom to top), in colour units (the tracer's colour clamped to [0, 1], largest
   * channel): point arrays "TruncationError" (an upper bound on what MaxDepth and
   * ContributionThreshold left out), "SamplingError" (the anti-aliasing estimate: two standard
   * errors of the pixel's mean with several samples, about 95% confidence; from the neighbours
   * with one sample), "EstimatedError" (their sum, capped at 1; the active scalars), "Samples"
   * (camera samples per pixel), "SamplingRMSError" (the calibrated sampling estimate: the pixel's RMS
   * error, 1 sigma, from the two interleaved halves of its samples) and "RMSError" (TruncationError
   * and SamplingRMSError in quadrature: the RMS over the image is what TargetError is compared
   * with). Interactive frames leave SamplingError 0. Empty after a failed frame.
   */
  void GetLastErrorImage(vtkImageData* image);

  /**
   * The last frame's statistics as a human-readable report (the same text as the core's
   * command-line renderer, plus the VTK phases). Empty before the first frame.
   */
  const char* GetLastFrameReport() { return this->LastFrameReport.c_str(); }

  /**
   * Called by the internal pass: converts, traces and composites. Not meant to be called directly.
   */
  virtual void RenderInternal(const vtkRenderState* s);

protected:
  vtkWhittedPass();
  ~vtkWhittedPass() override;

  // The settings (the Pass rows of the table), at their defaults
  VTK_WHITTED_SETTINGS(VTK_WHITTED_PASS_MEMBERS)
  // Per-frame state, set by the caller (vtkPVWhittedView: for each frame)
  int RefinementRoundsPerFrame = 0;
  double RefinementSliceTime = 0.0;
  bool Interactive = false;
  int InteractiveImageReduction = 1;
  int ImageSplit[2] = { 1, 0 };
  int AbortAfterTilesForTesting = -1;
  int ShadingErrorForTesting = 0;

  std::string LastFrameReport;

  vtkWhittedPassInternals* Internals;

private:
  // Reports a failed frame (exception from conversion, BVH build or tracing): error, caches
  // dropped, statistics cleared, EndEvent.
  void FailFrame(vtkWhittedSceneConverter* converter, const char* what);

  vtkWhittedPass(const vtkWhittedPass&) = delete;
  void operator=(const vtkWhittedPass&) = delete;
};

#endif
