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
 * Whitted materials are set per actor with information keys on its vtkProperty:
 * @code
 *   prop->GetInformation()->Set(vtkWhittedPass::REFLECTANCE(), 0.8);            // grey mirror
 *   double kt[3] = { 0.9, 0.9, 0.8 };
 *   prop->GetInformation()->Set(vtkWhittedPass::TRANSMITTANCE(), kt, 3);        // tinted glass
 *   prop->GetInformation()->Set(vtkWhittedPass::INDEX_OF_REFRACTION(), 1.5);
 * @endcode
 * Without keys an actor keeps its VTK look: reflectance 0, transmittance 1 - Opacity, index 1.
 *
 * The statistics of the last frame (time per phase, rays by kind, scene size, what was rebuilt) are
 * available through the GetLast...() methods and as text through GetLastFrameReport().
 *
 * @sa vtkRenderPass vtkOSPRayPass
 */

#ifndef vtkWhittedPass_h
#define vtkWhittedPass_h

#include "vtkRenderPass.h"
#include "vtkWhittedModule.h" // For export macro

#include <string> // for std::string

class vtkFloatArray;
class vtkInformationDoubleKey;
class vtkInformationDoubleVectorKey;
class vtkWhittedPassInternals;
class vtkWhittedSceneConverter;

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
   * Maximum number of secondary bounces (reflection and refraction) per camera ray; 0 gives local
   * shading (plus shadows) only. Default is 5.
   */
  vtkSetClampMacro(MaxDepth, int, 0, 64);
  vtkGetMacro(MaxDepth, int);
  ///@}

  ///@{
  /**
   * Camera samples per pixel (stratified, jittered); 1 traces the pixel centre, like OpenGL without
   * multisampling. Default is 1.
   */
  vtkSetClampMacro(SamplesPerPixel, int, 1, 256);
  vtkGetMacro(SamplesPerPixel, int);
  ///@}

  ///@{
  /**
   * Adaptive anti-aliasing: trace one sample per pixel first and SamplesPerPixel samples only where
   * the neighbouring pixels do not predict a pixel (edges, silhouettes, highlights, texture detail;
   * not smooth shading, which varies linearly). Has no effect when SamplesPerPixel is 1. Default is
   * off.
   */
  vtkSetMacro(AdaptiveSampling, bool);
  vtkGetMacro(AdaptiveSampling, bool);
  vtkBooleanMacro(AdaptiveSampling, bool);
  ///@}

  ///@{
  /**
   * Trace shadow rays toward every light (transmissive actors cast coloured shadows). Default is
   * on.
   */
  vtkSetMacro(Shadows, bool);
  vtkGetMacro(Shadows, bool);
  vtkBooleanMacro(Shadows, bool);
  ///@}

  ///@{
  /**
   * Trace mirror rays for actors with a REFLECTANCE. Default is on.
   */
  vtkSetMacro(Reflections, bool);
  vtkGetMacro(Reflections, bool);
  vtkBooleanMacro(Reflections, bool);
  ///@}

  ///@{
  /**
   * Bend transmitted rays by the INDEX_OF_REFRACTION (Snell's law, total internal reflection). When
   * off, transmissive actors are see-through without bending. Default is on.
   */
  vtkSetMacro(Refractions, bool);
  vtkGetMacro(Refractions, bool);
  vtkBooleanMacro(Refractions, bool);
  ///@}

  ///@{
  /**
   * A secondary ray whose weight (product of reflectances / transmittances along its path) falls
   * below this value is not traced: it could change the 8-bit pixel by less than one step.
   * Default is 1/255.
   */
  vtkSetClampMacro(ContributionThreshold, double, 0.0, 1.0);
  vtkGetMacro(ContributionThreshold, double);
  ///@}

  ///@{
  /**
   * Number of tracing threads; 0 uses every core the process may run on (its CPU affinity, which
   * mpirun, taskset or a cpuset may restrict). Default is 0.
   */
  vtkSetClampMacro(NumberOfThreads, int, 0, 1024);
  vtkGetMacro(NumberOfThreads, int);
  ///@}

  ///@{
  /**
   * Schlick's Fresnel term: transmissive actors reflect more at grazing angles (part of the
   * transmittance moves to the reflectance). Default is off.
   */
  vtkSetMacro(Fresnel, bool);
  vtkGetMacro(Fresnel, bool);
  vtkBooleanMacro(Fresnel, bool);
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
   * Trace at 1/factor of the viewport's width and height and stretch the result over the viewport
   * (nearest neighbour, colour and depth). For interactive frames. Default is 1 (full resolution).
   */
  vtkSetClampMacro(ImageReductionFactor, int, 1, 16);
  vtkGetMacro(ImageReductionFactor, int);
  ///@}

  ///@{
  /**
   * Whitted material keys, set on an actor's vtkProperty information.
   * REFLECTANCE: weight of the mirror-reflected ray, 1 value (grey) or 3 (RGB) in [0,1]. Default 0.
   * TRANSMITTANCE: weight of the transmitted (refracted) ray and the filter applied to shadow rays
   * crossing the actor, 1 or 3 values in [0,1]. Default 1 - Opacity.
   * Energy: where REFLECTANCE + TRANSMITTANCE exceeds 1 in some channel, both are scaled (all
   * channels) by 1 / the largest channel sum, with one warning per actor.
   * INDEX_OF_REFRACTION: index of the actor's inside (outside is 1). Default 1 (no bending).
   */
  static vtkInformationDoubleVectorKey* REFLECTANCE();
  static vtkInformationDoubleVectorKey* TRANSMITTANCE();
  static vtkInformationDoubleKey* INDEX_OF_REFRACTION();
  ///@}

  ///@{
  /**
   * Statistics of the last frame. Times are wall-clock seconds: conversion of actors to the
   * tracer's scene, BVH builds, tracing, compositing into the framebuffer (including the OpenGL
   * stages for props the tracer does not handle).
   */
  vtkGetMacro(LastConversionTime, double);
  vtkGetMacro(LastBuildTime, double);
  vtkGetMacro(LastTraceTime, double);
  vtkGetMacro(LastCompositeTime, double);
  vtkGetMacro(LastTotalTime, double);
  ///@}

  ///@{
  /**
   * Rays of the last frame by kind, and secondary rays not traced because their contribution was
   * below ContributionThreshold or MaxDepth was reached.
   */
  vtkGetMacro(LastPrimaryRays, vtkTypeUInt64);
  vtkGetMacro(LastShadowRays, vtkTypeUInt64);
  vtkGetMacro(LastReflectionRays, vtkTypeUInt64);
  vtkGetMacro(LastRefractionRays, vtkTypeUInt64);
  vtkGetMacro(LastRaysSavedByThreshold, vtkTypeUInt64);
  vtkGetMacro(LastRaysSavedByDepth, vtkTypeUInt64);
  ///@}

  ///@{
  /**
   * Scene of the last frame: triangles, spheres (points as spheres), tubes (lines as tubes), BVH
   * memory in bytes, textures held (actor textures and colour maps of
   * InterpolateScalarsBeforeMapping) and their memory in bytes, image size.
   */
  vtkGetMacro(LastNumberOfTriangles, vtkTypeUInt64);
  vtkGetMacro(LastNumberOfSpheres, vtkTypeUInt64);
  vtkGetMacro(LastNumberOfTubes, vtkTypeUInt64);
  vtkGetMacro(LastBVHBytes, vtkTypeUInt64);
  vtkGetMacro(LastNumberOfTextures, vtkTypeUInt64);
  vtkGetMacro(LastTextureBytes, vtkTypeUInt64);
  vtkGetVector2Macro(LastSize, int);
  ///@}

  ///@{
  /**
   * Caching of the last frame: how many geometries (a mapper's input, or one block of a composite
   * input) were converted again, how many object BVHs were built, whether the top-level BVH over
   * the instances was rebuilt, how many props were traced and how many were left to OpenGL.
   */
  vtkGetMacro(LastNumberOfGeometriesConverted, int);
  vtkGetMacro(LastNumberOfObjectsRebuilt, int);
  vtkGetMacro(LastTopLevelRebuilt, bool);
  vtkGetMacro(LastNumberOfTracedActors, int);
  vtkGetMacro(LastNumberOfOpenGLProps, int);
  vtkGetMacro(LastFrameAborted, bool);
  ///@}

  /**
   * Safety nets of the last frame: camera samples and pixels with a non-finite value that was
   * zeroed, and alpha or depth values outside [0, 1] that were clamped. Zero for valid input, and
   * also for bad input once the scene conversion and commit have rejected or fixed it (with a
   * warning): tests assert it, so a net cannot hide a bug. The frame report lists each net, and the
   * input values fixed at commit (materials, lights) beside them.
   */
  vtkGetMacro(LastNumberOfSafetyNetCatches, vtkTypeUInt64);

  /**
   * True when the last frame failed: an exception (e.g. std::bad_alloc from the scene
   * conversion, the BVH build or the tracer) was reported with vtkErrorMacro, the frame shows only
   * what vtkCameraPass cleared (the background), and the scene is converted again from scratch at
   * the next render.
   */
  vtkGetMacro(LastFrameFailed, bool);

  /**
   * Copies the tracer's image of the last frame (before compositing): colour as 4-component linear
   * RGBA floats as the tracer wrote them, and OpenGL window depth (1 component, 1 where nothing
   * was hit), rows bottom to top, GetLastSize() pixels. Either array may be null. Empty after a
   * failed frame. For tests and diagnostics (e.g. checking that no pixel is NaN or infinite).
   */
  void GetLastFrame(vtkFloatArray* rgba, vtkFloatArray* depth);

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

  int MaxDepth = 5;
  int SamplesPerPixel = 1;
  bool AdaptiveSampling = false;
  bool Shadows = true;
  bool Reflections = true;
  bool Refractions = true;
  double ContributionThreshold = 1.0 / 255.0;
  int NumberOfThreads = 0;
  bool Fresnel = false;
  int ImageSplit[2] = { 1, 0 };
  int ImageReductionFactor = 1;

  double LastConversionTime = 0.0;
  double LastBuildTime = 0.0;
  double LastTraceTime = 0.0;
  double LastCompositeTime = 0.0;
  double LastTotalTime = 0.0;
  vtkTypeUInt64 LastPrimaryRays = 0;
  vtkTypeUInt64 LastShadowRays = 0;
  vtkTypeUInt64 LastReflectionRays = 0;
  vtkTypeUInt64 LastRefractionRays = 0;
  vtkTypeUInt64 LastRaysSavedByThreshold = 0;
  vtkTypeUInt64 LastRaysSavedByDepth = 0;
  vtkTypeUInt64 LastNumberOfTriangles = 0;
  vtkTypeUInt64 LastNumberOfSpheres = 0;
  vtkTypeUInt64 LastNumberOfTubes = 0;
  vtkTypeUInt64 LastBVHBytes = 0;
  vtkTypeUInt64 LastNumberOfTextures = 0;
  vtkTypeUInt64 LastTextureBytes = 0;
  int LastSize[2] = { 0, 0 };
  int LastNumberOfGeometriesConverted = 0;
  int LastNumberOfObjectsRebuilt = 0;
  bool LastTopLevelRebuilt = false;
  int LastNumberOfTracedActors = 0;
  int LastNumberOfOpenGLProps = 0;
  bool LastFrameAborted = false;
  vtkTypeUInt64 LastNumberOfSafetyNetCatches = 0;
  bool LastFrameFailed = false;
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
