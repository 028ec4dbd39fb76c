#include "vtkWhittedFrameStatistics.h"

#include "vtkObjectFactory.h"

vtkStandardNewMacro(vtkWhittedFrameStatistics);

//------------------------------------------------------------------------------
void vtkWhittedFrameStatistics::Reset()
{
  this->ConversionTime = this->BuildTime = this->TraceTime = 0.0;
  this->CompositeTime = this->TotalTime = 0.0;
  this->ConversionCPUTime = this->BuildCPUTime = this->TraceCPUTime = this->CompositeCPUTime = 0.0;
  this->NumberOfFastTrees = this->NumberOfObjectsUpgraded = 0;
  this->WaitedForUpgrade = this->UpgradeRestarted = false;
  this->PrimaryRays = this->ShadowRays = this->ReflectionRays = this->RefractionRays = 0;
  this->RaysSavedByThreshold = this->RaysSavedByDepth = this->BoundRays = 0;
  this->NumberOfTriangles = this->NumberOfSpheres = this->NumberOfTubes = 0;
  this->NumberOfInstances = 0;
  this->BVHBytes = this->NumberOfTextures = this->TextureBytes = 0;
  this->Size[0] = this->Size[1] = 0;
  this->NumberOfGeometriesConverted = this->NumberOfObjectsRebuilt = this->NumberOfObjectsRefit = 0;
  this->TopLevelRebuilt = false;
  this->NumberOfTracedActors = this->NumberOfOpenGLProps = 0;
  this->NumberOfTracedVolumes = this->NumberOfVolumesConverted = 0;
  this->NumberOfVolumeTransferUpdates = 0;
  this->NumberOfRefitsRejected = this->NumberOfTimeCacheHits = this->NumberOfTimeCacheEntries = 0;
  this->RefitCostRatio = 0.0;
  this->TimeCacheBytes = 0;
  this->NumberOfSafetyNetCatches = 0;
  for (int k = 0; k < 3; ++k)
  {
    this->TruncationError[k] = this->SamplingError[k] = this->EstimatedError[k] = 0.0;
    this->SamplingRMSError[k] = this->RMSError[k] = 0.0;
  }
  this->NumberOfSamples = 0;
  this->RefinementRounds = 0;
  this->TargetErrorMet = false;
  this->RefinementFinished = true;
  this->RefinementExhausted = false;
  this->RefinementSeconds = 0.0;
  this->Aborted = this->Failed = false;
  this->Modified();
}

//------------------------------------------------------------------------------
void vtkWhittedFrameStatistics::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ConversionTime: " << this->ConversionTime << "\n";
  os << indent << "BuildTime: " << this->BuildTime << "\n";
  os << indent << "TraceTime: " << this->TraceTime << "\n";
  os << indent << "CompositeTime: " << this->CompositeTime << "\n";
  os << indent << "TotalTime: " << this->TotalTime << "\n";
  os << indent << "PrimaryRays: " << this->PrimaryRays << "\n";
  os << indent << "ShadowRays: " << this->ShadowRays << "\n";
  os << indent << "ReflectionRays: " << this->ReflectionRays << "\n";
  os << indent << "RefractionRays: " << this->RefractionRays << "\n";
  os << indent << "RaysSavedByThreshold: " << this->RaysSavedByThreshold << "\n";
  os << indent << "RaysSavedByDepth: " << this->RaysSavedByDepth << "\n";
  os << indent << "BoundRays: " << this->BoundRays << "\n";
  os << indent << "NumberOfTriangles: " << this->NumberOfTriangles << "\n";
  os << indent << "NumberOfSpheres: " << this->NumberOfSpheres << "\n";
  os << indent << "NumberOfTubes: " << this->NumberOfTubes << "\n";
  os << indent << "NumberOfInstances: " << this->NumberOfInstances << "\n";
  os << indent << "BVHBytes: " << this->BVHBytes << "\n";
  os << indent << "NumberOfTextures: " << this->NumberOfTextures << "\n";
  os << indent << "TextureBytes: " << this->TextureBytes << "\n";
  os << indent << "Size: " << this->Size[0] << " " << this->Size[1] << "\n";
  os << indent << "NumberOfGeometriesConverted: " << this->NumberOfGeometriesConverted << "\n";
  os << indent << "NumberOfObjectsRebuilt: " << this->NumberOfObjectsRebuilt << "\n";
  os << indent << "NumberOfObjectsRefit: " << this->NumberOfObjectsRefit << "\n";
  os << indent << "NumberOfFastTrees: " << this->NumberOfFastTrees << "\n";
  os << indent << "NumberOfObjectsUpgraded: " << this->NumberOfObjectsUpgraded << "\n";
  os << indent << "WaitedForUpgrade: " << this->WaitedForUpgrade << "\n";
  os << indent << "UpgradeRestarted: " << this->UpgradeRestarted << "\n";
  os << indent << "ConversionCPUTime: " << this->ConversionCPUTime << "\n";
  os << indent << "BuildCPUTime: " << this->BuildCPUTime << "\n";
  os << indent << "TraceCPUTime: " << this->TraceCPUTime << "\n";
  os << indent << "CompositeCPUTime: " << this->CompositeCPUTime << "\n";
  os << indent << "TopLevelRebuilt: " << this->TopLevelRebuilt << "\n";
  os << indent << "NumberOfTracedActors: " << this->NumberOfTracedActors << "\n";
  os << indent << "NumberOfTracedVolumes: " << this->NumberOfTracedVolumes << "\n";
  os << indent << "NumberOfVolumesConverted: " << this->NumberOfVolumesConverted << "\n";
  os << indent << "NumberOfVolumeTransferUpdates: " << this->NumberOfVolumeTransferUpdates << "\n";
  os << indent << "NumberOfOpenGLProps: " << this->NumberOfOpenGLProps << "\n";
  os << indent << "NumberOfRefitsRejected: " << this->NumberOfRefitsRejected << "\n";
  os << indent << "RefitCostRatio: " << this->RefitCostRatio << "\n";
  os << indent << "NumberOfTimeCacheHits: " << this->NumberOfTimeCacheHits << "\n";
  os << indent << "NumberOfTimeCacheEntries: " << this->NumberOfTimeCacheEntries << "\n";
  os << indent << "TimeCacheBytes: " << this->TimeCacheBytes << "\n";
  os << indent << "NumberOfSafetyNetCatches: " << this->NumberOfSafetyNetCatches << "\n";
  const double* errors[5] = { this->TruncationError, this->SamplingError, this->EstimatedError,
    this->SamplingRMSError, this->RMSError };
  const char* names[5] = { "TruncationError", "SamplingError", "EstimatedError", "SamplingRMSError",
    "RMSError" };
  for (int k = 0; k < 5; ++k)
  {
    os << indent << names[k] << " (RMS, p95, max): " << errors[k][0] << " " << errors[k][1] << " "
       << errors[k][2] << "\n";
  }
  os << indent << "NumberOfSamples: " << this->NumberOfSamples << "\n";
  os << indent << "RefinementRounds: " << this->RefinementRounds << "\n";
  os << indent << "TargetErrorMet: " << this->TargetErrorMet << "\n";
  os << indent << "RefinementFinished: " << this->RefinementFinished << "\n";
  os << indent << "RefinementExhausted: " << this->RefinementExhausted << "\n";
  os << indent << "RefinementSeconds: " << this->RefinementSeconds << "\n";
  os << indent << "Aborted: " << this->Aborted << "\n";
  os << indent << "Failed: " << this->Failed << "\n";
}
