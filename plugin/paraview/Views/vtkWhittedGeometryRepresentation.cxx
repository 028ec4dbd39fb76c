#include "vtkWhittedGeometryRepresentation.h"

#include "vtkInformation.h"
#include "vtkInformationDoubleKey.h"
#include "vtkInformationDoubleVectorKey.h"
#include "vtkObjectFactory.h"
#include "vtkPVLODActor.h"
#include "vtkProperty.h"
#include "vtkWhittedPass.h"

vtkStandardNewMacro(vtkWhittedGeometryRepresentation);

namespace
{
vtkInformation* MaterialInformation(vtkProperty* property)
{
  if (!property->GetInformation())
  {
    vtkNew<vtkInformation> info;
    property->SetInformation(info);
  }
  return property->GetInformation();
}

double GetFirst(vtkProperty* property, vtkInformationDoubleVectorKey* key, double fallback)
{
  vtkInformation* info = property->GetInformation();
  return (info && info->Has(key) && info->Length(key) > 0) ? info->Get(key, 0) : fallback;
}
}

//------------------------------------------------------------------------------
vtkWhittedGeometryRepresentation::vtkWhittedGeometryRepresentation() = default;
vtkWhittedGeometryRepresentation::~vtkWhittedGeometryRepresentation() = default;

//------------------------------------------------------------------------------
void vtkWhittedGeometryRepresentation::SetReflectance(double value)
{
  if (value != this->GetReflectance() ||
    !MaterialInformation(this->Property)->Has(vtkWhittedPass::REFLECTANCE()))
  {
    MaterialInformation(this->Property)->Set(vtkWhittedPass::REFLECTANCE(), &value, 1);
    this->Property->Modified();
    this->Modified();
  }
}

double vtkWhittedGeometryRepresentation::GetReflectance()
{
  return GetFirst(this->Property, vtkWhittedPass::REFLECTANCE(), 0.0);
}

//------------------------------------------------------------------------------
void vtkWhittedGeometryRepresentation::SetTransmittance(double value)
{
  vtkInformation* info = MaterialInformation(this->Property);
  const bool had = info->Has(vtkWhittedPass::TRANSMITTANCE());
  if (value > 0.0)
  {
    if (!had || value != this->GetTransmittance())
    {
      info->Set(vtkWhittedPass::TRANSMITTANCE(), &value, 1);
      this->Property->Modified();
      this->Modified();
    }
  }
  else if (had)
  {
    // 0 means "not set": the pass then derives the transmittance from the opacity (1 - Opacity).
    info->Remove(vtkWhittedPass::TRANSMITTANCE());
    this->Property->Modified();
    this->Modified();
  }
}

double vtkWhittedGeometryRepresentation::GetTransmittance()
{
  return GetFirst(this->Property, vtkWhittedPass::TRANSMITTANCE(), 0.0);
}

//------------------------------------------------------------------------------
void vtkWhittedGeometryRepresentation::SetIndexOfRefraction(double value)
{
  vtkInformation* info = MaterialInformation(this->Property);
  if (!info->Has(vtkWhittedPass::INDEX_OF_REFRACTION()) ||
    info->Get(vtkWhittedPass::INDEX_OF_REFRACTION()) != value)
  {
    info->Set(vtkWhittedPass::INDEX_OF_REFRACTION(), value);
    this->Property->Modified();
    this->Modified();
  }
}

double vtkWhittedGeometryRepresentation::GetIndexOfRefraction()
{
  vtkInformation* info = this->Property->GetInformation();
  return (info && info->Has(vtkWhittedPass::INDEX_OF_REFRACTION()))
    ? info->Get(vtkWhittedPass::INDEX_OF_REFRACTION())
    : 1.0;
}

//------------------------------------------------------------------------------
void vtkWhittedGeometryRepresentation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Reflectance: " << this->GetReflectance() << "\n";
  os << indent << "Transmittance: " << this->GetTransmittance() << "\n";
  os << indent << "IndexOfRefraction: " << this->GetIndexOfRefraction() << "\n";
}
