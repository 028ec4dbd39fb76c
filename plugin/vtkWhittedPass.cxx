#include "vtkWhittedPass.h"

#include "vtkWhittedFrameStatistics.h"
#include "vtkWhittedMaterialKeys.h"
#include "vtkWhittedPassInternals.h"

#include "vtkInformationDoubleKey.h"
#include "vtkInformationDoubleVectorKey.h"
#include "vtkInformationObjectBaseKey.h"
#include "vtkInformationStringKey.h"
#include "vtkObjectFactory.h"
#include "vtkRenderPassCollection.h"

// The pass's sources (see vtkWhittedPassInternals.h): this one holds its construction, settings
// and entry points.

//------------------------------------------------------------------------------
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
// PrintSelf: the settings (the Pass rows of the table), then the per-frame state
#define VTK_WHITTED_PASS_PRINT(owner, type, name, def, min, max, doc)                              \
  VTK_WHITTED_PASS_PRINT_##owner(name)
#define VTK_WHITTED_PASS_PRINT_Pass(name) VTK_WHITTED_SETTING_PRINT(name)
#define VTK_WHITTED_PASS_PRINT_View(name)
void vtkWhittedPass::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  VTK_WHITTED_SETTINGS(VTK_WHITTED_PASS_PRINT)
  os << indent << "RefinementRoundsPerFrame: " << this->RefinementRoundsPerFrame << "\n";
  os << indent << "RefinementSliceTime: " << this->RefinementSliceTime << "\n";
  os << indent << "Interactive: " << this->Interactive << "\n";
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
