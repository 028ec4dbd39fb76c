#include "vtkWhittedPass.h"

#include "vtkWhittedPassInternals.h"

#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkPointData.h"

#include "image/report.h"

#include <cstdio>

// What the last frame of the pass leaves (see vtkWhittedPassInternals.h): its statistics and
// report, its colour and depth, its per-pixel error estimate.

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
  st->NumberOfTracedVolumes = r.Conversion.TracedVolumes;
  st->NumberOfVolumesConverted = r.Conversion.VolumesConverted;
  st->NumberOfVolumeTransferUpdates = r.Conversion.VolumeTransferUpdates;
  st->NumberOfOpenGLProps = static_cast<int>(r.Conversion.OpenGLProps.size());
  st->NumberOfSafetyNetCatches = rays.safetyNetCatches();
  st->Aborted = r.Trace.aborted;
  st->Failed = false;
  const whitted::ErrorSummary* summaries[5] = { &r.Trace.truncation, &r.Trace.sampling,
    &r.Trace.total, &r.Trace.calibratedSampling, &r.Trace.calibrated };
  double* fields[5] = { st->TruncationError, st->SamplingError, st->EstimatedError,
    st->SamplingRMSError, st->RMSError };
  for (int k = 0; k < 5; ++k)
  {
    fields[k][0] = summaries[k]->rms;
    fields[k][1] = summaries[k]->p95;
    fields[k][2] = summaries[k]->max;
  }
  st->NumberOfSamples = r.Trace.samples;
  st->RefinementRounds = r.Trace.refinementRounds;
  st->TargetErrorMet = r.Trace.targetMet;
  st->RefinementFinished = r.Trace.refinementFinished;
  st->RefinementExhausted = r.Trace.refinementExhausted;
  st->RefinementSeconds =
    this->Refinement.pixels.empty() ? r.Trace.secondsTrace : this->Refinement.seconds;
  st->Modified();

  report = whitted::frameReport(r.Trace, scene, r.Commit, this->Frame.width, this->Frame.height,
    r.ConversionTime, "conversion");
  char line[256];
  std::snprintf(line, sizeof line,
    "  vtk              composite %.2f ms, total %.2f ms; %d actors traced (%d geometries "
    "converted), %d volumes traced (%d converted, %d transfer updates), %d props drawn by OpenGL\n",
    r.CompositeTime * 1e3, totalTime * 1e3, r.Conversion.TracedActors,
    r.Conversion.GeometriesConverted, r.Conversion.TracedVolumes, r.Conversion.VolumesConverted,
    r.Conversion.VolumeTransferUpdates, st->NumberOfOpenGLProps);
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
    fb.sampling.size() == static_cast<size_t>(n) && fb.samplingRms.size() == static_cast<size_t>(n) &&
    fb.samples.size() == static_cast<size_t>(n);
  image->Initialize();
  image->SetDimensions(valid ? fb.width : 0, valid ? fb.height : 0, valid ? 1 : 0);
  const char* names[6] = { "TruncationError", "SamplingError", "EstimatedError", "Samples",
    "SamplingRMSError", "RMSError" };
  vtkNew<vtkFloatArray> arrays[6];
  for (int k = 0; k < 6; ++k)
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
    arrays[4]->SetValue(i, fb.samplingRms[i]);
    arrays[5]->SetValue(i, whitted::calibratedTotal(fb.truncation[i], fb.samplingRms[i]));
  }
  for (int k = 0; k < 6; ++k)
  {
    image->GetPointData()->AddArray(arrays[k]);
  }
  image->GetPointData()->SetActiveScalars("EstimatedError");
}
