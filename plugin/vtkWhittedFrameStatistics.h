/**
 * @class   vtkWhittedFrameStatistics
 * @brief   what one frame of vtkWhittedPass did: time per phase, rays, scene size, caching
 *
 * The pass keeps one of these and fills it at the end of every frame
 * (vtkWhittedPass::GetLastFrameStatistics()); read it after rendering:
 * @code
 *   stats = whitted_pass.GetLastFrameStatistics()
 *   print(stats.GetTraceTime(), stats.GetPrimaryRays(), stats.GetNumberOfTriangles())
 * @endcode
 * Before the first frame, and after a failed one (GetFailed()), every value is 0.
 *
 * @sa vtkWhittedPass
 */

#ifndef vtkWhittedFrameStatistics_h
#define vtkWhittedFrameStatistics_h

#include "vtkObject.h"
#include "vtkWhittedModule.h" // For export macro

class VTKWHITTED_EXPORT vtkWhittedFrameStatistics : public vtkObject
{
public:
  static vtkWhittedFrameStatistics* New();
  vtkTypeMacro(vtkWhittedFrameStatistics, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Wall-clock seconds: conversion of the renderer's actors to the tracer's scene, BVH builds,
   * tracing, compositing into the framebuffer (including VTK's OpenGL stages for the props the
   * tracer does not draw), and the whole frame.
   */
  vtkGetMacro(ConversionTime, double);
  vtkGetMacro(BuildTime, double);
  vtkGetMacro(TraceTime, double);
  vtkGetMacro(CompositeTime, double);
  vtkGetMacro(TotalTime, double);
  ///@}

  ///@{
  /**
   * Process CPU seconds (every thread of the process, the tracer's and others') during the
   * conversion, the BVH builds, the trace and the compositing.
   */
  vtkGetMacro(ConversionCPUTime, double);
  vtkGetMacro(BuildCPUTime, double);
  vtkGetMacro(TraceCPUTime, double);
  vtkGetMacro(CompositeCPUTime, double);
  ///@}

  ///@{
  /**
   * Which trees the frame traced: new and replaced large geometry is built with the fast (Morton)
   * builder for the frame that shows it, and its SAH tree is built in the background after that
   * frame and swapped in by a later frame once finished (never waited for). NumberOfFastTrees:
   * objects traced with a fast tree in this frame; NumberOfObjectsUpgraded: objects whose SAH tree
   * was swapped in at the start of this frame. Images do not depend on the tree.
   * WaitedForUpgrade: this frame's build phase waited for a background build (frames rendered back to
   * back leave it no idle core; the 16th frame after it started waits, so its BuildTime includes that
   * wait). UpgradeRestarted: this frame stopped a background build kept at idle priority and started it
   * again at normal priority, because the process may not raise a thread's priority (Linux without
   * CAP_SYS_NICE); no frame waits then.
   */
  vtkGetMacro(NumberOfFastTrees, int);
  vtkGetMacro(NumberOfObjectsUpgraded, int);
  vtkGetMacro(WaitedForUpgrade, bool);
  vtkGetMacro(UpgradeRestarted, bool);
  ///@}

  ///@{
  /**
   * Rays by kind, and secondary rays not traced because their contribution was below
   * ContributionThreshold or MaxDepth was reached. BoundRays: of those, the ones traced to their
   * first hit only (no shading recursion, no shadow rays) to bound what they would have returned
   * (the truncation error estimate of still frames; 0 in interactive frames).
   */
  vtkGetMacro(PrimaryRays, vtkTypeUInt64);
  vtkGetMacro(ShadowRays, vtkTypeUInt64);
  vtkGetMacro(ReflectionRays, vtkTypeUInt64);
  vtkGetMacro(RefractionRays, vtkTypeUInt64);
  vtkGetMacro(RaysSavedByThreshold, vtkTypeUInt64);
  vtkGetMacro(RaysSavedByDepth, vtkTypeUInt64);
  vtkGetMacro(BoundRays, vtkTypeUInt64);
  ///@}

  ///@{
  /**
   * The scene: triangles, spheres (points as spheres), tubes (lines as tubes), traced instances
   * (placements of that geometry: one per actor piece and primitive kind, one per glyph), BVH
   * memory in bytes,
   * textures held (actor textures and colour maps of InterpolateScalarsBeforeMapping) and their
   * memory in bytes; the traced image's size in pixels.
   */
  vtkGetMacro(NumberOfTriangles, vtkTypeUInt64);
  vtkGetMacro(NumberOfSpheres, vtkTypeUInt64);
  vtkGetMacro(NumberOfTubes, vtkTypeUInt64);
  vtkGetMacro(NumberOfInstances, vtkTypeUInt64);
  vtkGetMacro(BVHBytes, vtkTypeUInt64);
  vtkGetMacro(NumberOfTextures, vtkTypeUInt64);
  vtkGetMacro(TextureBytes, vtkTypeUInt64);
  vtkGetVector2Macro(Size, int);
  ///@}

  ///@{
  /**
   * Caching: how many geometries (a mapper's input, or one block of a composite input) were
   * converted again, how many object BVHs were built, how many were refit (points moved on the
   * same connectivity, e.g. a deforming mesh's time step: boxes updated, no rebuild), whether the
   * top-level BVH over the instances was rebuilt; how many props were traced and how many were left
   * to OpenGL.
   */
  vtkGetMacro(NumberOfGeometriesConverted, int);
  vtkGetMacro(NumberOfObjectsRebuilt, int);
  vtkGetMacro(NumberOfObjectsRefit, int);
  vtkGetMacro(TopLevelRebuilt, bool);
  vtkGetMacro(NumberOfTracedActors, int);
  vtkGetMacro(NumberOfOpenGLProps, int);
  ///@}

  ///@{
  /**
   * Volumes (vtkVolume): how many were traced (or left undrawn for bad input), how many had their
   * scalars converted in this frame (new or changed image data), how many only had their transfer
   * functions updated (a colour or opacity edit: the converted grid is kept).
   */
  vtkGetMacro(NumberOfTracedVolumes, int);
  vtkGetMacro(NumberOfVolumesConverted, int);
  vtkGetMacro(NumberOfVolumeTransferUpdates, int);
  ///@}

  ///@{
  /**
   * Time series: refits whose tree would trace too slowly (its SAH cost grew beyond 1.4 times the
   * cost of the tree when built: rebuilt instead, and counted in NumberOfObjectsRebuilt), the
   * largest SAH cost ratio (refitted tree / built tree) of this frame's refits (0 without
   * refits); geometries restored from the pass's time cache (converted and built earlier, nothing
   * converted or built now), and what the time cache holds after the frame (geometries, bytes).
   */
  vtkGetMacro(NumberOfRefitsRejected, int);
  vtkGetMacro(RefitCostRatio, double);
  vtkGetMacro(NumberOfTimeCacheHits, int);
  vtkGetMacro(NumberOfTimeCacheEntries, int);
  vtkGetMacro(TimeCacheBytes, vtkTypeUInt64);
  ///@}

  /**
   * Safety nets: camera samples and pixels with a non-finite value that was zeroed, and alpha or
   * depth values outside [0, 1] that were clamped. Zero for valid input, and also for bad input
   * once the scene conversion and commit have rejected or fixed it (with a warning): tests assert
   * it, so a net cannot hide a bug. The frame report lists each net, and the input values fixed at
   * commit (materials, lights) beside them.
   */
  vtkGetMacro(NumberOfSafetyNetCatches, vtkTypeUInt64);

  ///@{
  /**
   * The frame's error estimate, each as { RMS over pixels, 95th percentile, largest pixel }, in
   * colour units (the tracer's colour clamped to [0, 1], largest channel; see
   * vtkWhittedPass::GetLastErrorImage for the per-pixel images):
   * TruncationError, an upper bound on what MaxDepth and ContributionThreshold left out (never
   * below the true difference to a render without threshold at unlimited depth; where some surface
   * has reflectance + transmittance 1 and its own colour, at depth 16);
   * SamplingError, the anti-aliasing estimate (two standard errors of each pixel's mean, about 95%
   * confidence; one-sample pixels: from their neighbours; 0 for interactive frames);
   * EstimatedError, their per-pixel sum (at least 95% per pixel: a bound, not an RMS estimate);
   * SamplingRMSError, the calibrated sampling estimate: an estimate of each pixel's RMS error (1 sigma,
   * about 68%: not a bound), from the difference of the two interleaved halves of its samples,
   * unbiased for stratified samples (one-sample pixels: as SamplingError);
   * RMSError, TruncationError and SamplingRMSError in quadrature per pixel: its RMS (RMSError[0]) is
   * the calibrated estimate of the image's RMS error (largest channel per pixel), what TargetError is
   * compared with.
   */
  vtkGetVector3Macro(TruncationError, double);
  vtkGetVector3Macro(SamplingError, double);
  vtkGetVector3Macro(EstimatedError, double);
  vtkGetVector3Macro(SamplingRMSError, double);
  vtkGetVector3Macro(RMSError, double);
  ///@}

  ///@{
  /**
   * Camera samples taken, progressive refinement rounds run, and whether the frame met the pass's
   * TargetError (false without a target). RefinementFinished: the refinement is over (target met,
   * budget spent, nothing left to refine, or no refinement asked for); false when the frame stopped
   * at the pass's RefinementRoundsPerFrame (progressive display: render again to continue) or was
   * aborted. RefinementExhausted: it is over because nothing was left to refine (every pixel whose
   * estimate is not zero has the most samples a still frame takes): how a refinement without a
   * TargetError ends before its TimeBudget is spent. With progressive display the samples, rounds
   * and RefinementSeconds (tracing seconds, what TimeBudget counts) are those of the whole
   * refinement so far, over all its frames.
   */
  vtkGetMacro(NumberOfSamples, vtkTypeUInt64);
  vtkGetMacro(RefinementRounds, int);
  vtkGetMacro(TargetErrorMet, bool);
  vtkGetMacro(RefinementFinished, bool);
  vtkGetMacro(RefinementExhausted, bool);
  vtkGetMacro(RefinementSeconds, double);
  ///@}

  /**
   * The frame was aborted (the render window's CheckAbortStatus()): part of the image is traced.
   */
  vtkGetMacro(Aborted, bool);

  /**
   * The frame failed: an exception (e.g. std::bad_alloc from the scene conversion, the BVH build or
   * the tracer) was reported with vtkErrorMacro, the frame shows only what vtkCameraPass cleared
   * (the background), and the scene is converted again from scratch at the next render. Every other
   * value is 0.
   */
  vtkGetMacro(Failed, bool);

  /**
   * Sets every value to 0 (false).
   */
  void Reset();

protected:
  vtkWhittedFrameStatistics() = default;
  ~vtkWhittedFrameStatistics() override = default;

  // Filled by vtkWhittedPass (its internals fill a traced frame, the pass a failed one)
  friend class vtkWhittedPass;
  friend class vtkWhittedPassInternals;
  double ConversionTime = 0.0;
  double BuildTime = 0.0;
  double TraceTime = 0.0;
  double CompositeTime = 0.0;
  double TotalTime = 0.0;
  double ConversionCPUTime = 0.0;
  double BuildCPUTime = 0.0;
  double TraceCPUTime = 0.0;
  double CompositeCPUTime = 0.0;
  int NumberOfFastTrees = 0;
  int NumberOfObjectsUpgraded = 0;
  bool WaitedForUpgrade = false;
  bool UpgradeRestarted = false;
  vtkTypeUInt64 PrimaryRays = 0;
  vtkTypeUInt64 ShadowRays = 0;
  vtkTypeUInt64 ReflectionRays = 0;
  vtkTypeUInt64 RefractionRays = 0;
  vtkTypeUInt64 RaysSavedByThreshold = 0;
  vtkTypeUInt64 RaysSavedByDepth = 0;
  vtkTypeUInt64 BoundRays = 0;
  vtkTypeUInt64 NumberOfTriangles = 0;
  vtkTypeUInt64 NumberOfSpheres = 0;
  vtkTypeUInt64 NumberOfTubes = 0;
  vtkTypeUInt64 NumberOfInstances = 0;
  vtkTypeUInt64 BVHBytes = 0;
  vtkTypeUInt64 NumberOfTextures = 0;
  vtkTypeUInt64 TextureBytes = 0;
  int Size[2] = { 0, 0 };
  int NumberOfGeometriesConverted = 0;
  int NumberOfObjectsRebuilt = 0;
  int NumberOfObjectsRefit = 0;
  bool TopLevelRebuilt = false;
  int NumberOfTracedActors = 0;
  int NumberOfTracedVolumes = 0;
  int NumberOfVolumesConverted = 0;
  int NumberOfVolumeTransferUpdates = 0;
  int NumberOfOpenGLProps = 0;
  int NumberOfRefitsRejected = 0;
  double RefitCostRatio = 0.0;
  int NumberOfTimeCacheHits = 0;
  int NumberOfTimeCacheEntries = 0;
  vtkTypeUInt64 TimeCacheBytes = 0;
  vtkTypeUInt64 NumberOfSafetyNetCatches = 0;
  double TruncationError[3] = { 0.0, 0.0, 0.0 };
  double SamplingError[3] = { 0.0, 0.0, 0.0 };
  double EstimatedError[3] = { 0.0, 0.0, 0.0 };
  double SamplingRMSError[3] = { 0.0, 0.0, 0.0 };
  double RMSError[3] = { 0.0, 0.0, 0.0 };
  vtkTypeUInt64 NumberOfSamples = 0;
  int RefinementRounds = 0;
  bool TargetErrorMet = false;
  bool RefinementFinished = true;
  bool RefinementExhausted = false;
  double RefinementSeconds = 0.0;
  bool Aborted = false;
  bool Failed = false;

private:
  vtkWhittedFrameStatistics(const vtkWhittedFrameStatistics&) = delete;
  void operator=(const vtkWhittedFrameStatistics&) = delete;
};

#endif
