#include "vtkWhittedGeometryRepresentation.h"

#include "vtkInformation.h"
#include "vtkInformationDoubleKey.h"
#include "vtkInformationDoubleVectorKey.h"
#include "vtkInformationObjectBaseKey.h"
#include "vtkInformationStringKey.h"
#include "vtkObjectFactory.h"
#include "vtkPVLODActor.h"
#include "vtkPiecewiseFunction.h"
#include "vtkProperty.h"
#include "vtkStringArray.h"
#include "vtkWhittedMaterialKeys.h"
#include "vtkWhittedMaterialLibrary.h"

#include <cstring>
#include <string>

vtkStandardNewMacro(vtkWhittedGeometryRepresentation);

//------------------------------------------------------------------------------
vtkWhittedGeometryRepresentation::vtkWhittedGeometryRepresentation()
  : Library(vtkSmartPointer<vtkWhittedMaterialLibrary>::New())
  , LibraryMaterialNames(vtkSmartPointer<vtkStringArray>::New())
{
}

vtkWhittedGeometryRepresentation::~vtkWhittedGeometryRepresentation()
{
  delete[] this->MaterialLibrary;
  delete[] this->LibraryMaterial;
}

//------------------------------------------------------------------------------
void vtkWhittedGeometryRepresentation::UpdateHighlight()
{
  double specular = this->UserSpecular, power = this->UserSpecularPower;
  double color[3] = { this->UserSpecularColor[0], this->UserSpecularColor[1],
    this->UserSpecularColor[2] };
  vtkWhittedMaterialLibrary::GetPresetHighlight(
    vtkWhittedMaterialLibrary::GetPresetName(this->MaterialPreset), specular, power, color);
  this->Superclass::SetSpecular(specular);
  this->Superclass::SetSpecularPower(power);
  this->Superclass::SetSpecularColor(color[0], color[1], color[2]);
}

void vtkWhittedGeometryRepresentation::SetSpecular(double value)
{
  this->UserSpecular = value;
  this->UpdateHighlight();
}

void vtkWhittedGeometryRepresentation::SetSpecularPower(double value)
{
  this->UserSpecularPower = value;
  this->UpdateHighlight();
}

void vtkWhittedGeometryRepresentation::SetSpecularColor(double r, double g, double b)
{
  this->UserSpecularColor[0] = r;
  this->UserSpecularColor[1] = g;
  this->UserSpecularColor[2] = b;
  this->UpdateHighlight();
}

//------------------------------------------------------------------------------
void vtkWhittedGeometryRepresentation::UpdateMaterialKeys()
{
  this->UpdateHighlight();
  // A preset sets (or removes) every key
  const char* preset = vtkWhittedMaterialLibrary::GetPresetName(this->MaterialPreset);
  if (this->MaterialPreset > 0 && vtkWhittedMaterialLibrary::ApplyPreset(preset, this->Property))
  {
    this->Modified();
    return;
  }

  // A material of the library
  if (this->MaterialPreset == 0 && this->LibraryMaterial && *this->LibraryMaterial &&
    std::strcmp(this->LibraryMaterial, "None") != 0 && // the GUI's "no library material"
    *this->Library->GetMaterialType(this->LibraryMaterial) &&
    this->Library->ApplyMaterial(this->LibraryMaterial, this->Property))
  {
    this->Modified();
    return;
  }

  // The fields; Transmittance 0 and a white AttenuationColor mean "not set"
  vtkWhittedMaterialLibrary::ApplyPreset("None", this->Property);
  vtkInformation* info = this->Property->GetInformation();
  double kr[3];
  for (int i = 0; i < 3; ++i)
  {
    kr[i] = this->Reflectance * this->ReflectanceColor[i];
  }
  info->Set(vtkWhittedMaterialKeys::REFLECTANCE(), kr, 3);
  if (this->Transmittance > 0.0)
  {
    info->Set(vtkWhittedMaterialKeys::TRANSMITTANCE(), &this->Transmittance, 1);
  }
  info->Set(vtkWhittedMaterialKeys::INDEX_OF_REFRACTION(), this->IndexOfRefraction);
  const double* a = this->AttenuationColor;
  if (a[0] != 1.0 || a[1] != 1.0 || a[2] != 1.0)
  {
    info->Set(vtkWhittedMaterialKeys::ATTENUATION_COLOR(), this->AttenuationColor, 3);
    info->Set(vtkWhittedMaterialKeys::ATTENUATION_DISTANCE(), this->AttenuationDistance);
  }
  this->Property->Modified();
  this->Modified();
}

//------------------------------------------------------------------------------
void vtkWhittedGeometryRepresentation::SetMaterialPreset(int preset)
{
  this->Assign(this->MaterialPreset, preset);
}

void vtkWhittedGeometryRepresentation::SetReflectance(double value)
{
  this->Assign(this->Reflectance, value);
}

void vtkWhittedGeometryRepresentation::SetReflectanceColor(double r, double g, double b)
{
  this->AssignColor(this->ReflectanceColor, r, g, b);
}

void vtkWhittedGeometryRepresentation::SetTransmittance(double value)
{
  this->Assign(this->Transmittance, value);
}

void vtkWhittedGeometryRepresentation::SetIndexOfRefraction(double value)
{
  this->Assign(this->IndexOfRefraction, value);
}

void vtkWhittedGeometryRepresentation::SetAttenuationColor(double r, double g, double b)
{
  this->AssignColor(this->AttenuationColor, r, g, b);
}

void vtkWhittedGeometryRepresentation::SetAttenuationDistance(double value)
{
  this->Assign(this->AttenuationDistance, value);
}

template <typename T>
void vtkWhittedGeometryRepresentation::Assign(T& field, T value)
{
  if (field != value)
  {
    field = value;
    this->UpdateMaterialKeys();
  }
}

void vtkWhittedGeometryRepresentation::AssignColor(double* field, double r, double g, double b)
{
  if (r != field[0] || g != field[1] || b != field[2])
  {
    field[0] = r;
    field[1] = g;
    field[2] = b;
    this->UpdateMaterialKeys();
  }
}

void vtkWhittedGeometryRepresentation::SetMaterialLibrary(const char* filename)
{
  const std::string now = this->MaterialLibrary ? this->MaterialLibrary : "";
  if (now == (filename ? filename : ""))
  {
    return;
  }
  delete[] this->MaterialLibrary;
  this->MaterialLibrary = nullptr;
  this->Library = vtkSmartPointer<vtkWhittedMaterialLibrary>::New(); // the previous file's are gone
  if (filename && *filename)
  {
    this->MaterialLibrary = new char[std::strlen(filename) + 1];
    std::strcpy(this->MaterialLibrary, filename);
    this->Library->ReadFile(filename);
  }
  this->LibraryMaterialNames->Initialize();
  for (int i = 0; i < this->Library->GetNumberOfMaterials(); ++i)
  {
    this->LibraryMaterialNames->InsertNextValue(this->Library->GetMaterialName(i));
  }
  this->UpdateMaterialKeys();
}

vtkStringArray* vtkWhittedGeometryRepresentation::GetLibraryMaterialNames()
{
  return this->LibraryMaterialNames;
}

void vtkWhittedGeometryRepresentation::SetLibraryMaterial(const char* name)
{
  const std::string now = this->LibraryMaterial ? this->LibraryMaterial : "";
  if (now == (name ? name : ""))
  {
    return;
  }
  delete[] this->LibraryMaterial;
  this->LibraryMaterial = nullptr;
  if (name)
  {
    this->LibraryMaterial = new char[std::strlen(name) + 1];
    std::strcpy(this->LibraryMaterial, name);
  }
  this->UpdateMaterialKeys();
}

//------------------------------------------------------------------------------
void vtkWhittedGeometryRepresentation::SetEnableScaling(int mode)
{
  this->Superclass::SetEnableScaling(mode);
  this->ScalingMode = mode;
  this->UpdateRadiusKeys();
}

void vtkWhittedGeometryRepresentation::SetScalingArrayName(const char* name)
{
  this->Superclass::SetScalingArrayName(name);
  this->ScalingArray = name ? name : "";
  this->UpdateRadiusKeys();
}

void vtkWhittedGeometryRepresentation::SetScalingFunction(vtkPiecewiseFunction* function)
{
  this->Superclass::SetScalingFunction(function);
  this->ScalingFunction = function;
  this->UpdateRadiusKeys();
}

void vtkWhittedGeometryRepresentation::UpdateRadiusKeys()
{
  // OSPRay's modes: -1 All Exact, 0 All Approximate, 1 Each Scaled, 2 Each Exact
  vtkInformation* info = this->Property->GetInformation();
  if (this->ScalingMode >= 1 && !this->ScalingArray.empty())
  {
    info->Set(vtkWhittedMaterialKeys::RADIUS_ARRAY(), this->ScalingArray.c_str());
  }
  else
  {
    info->Remove(vtkWhittedMaterialKeys::RADIUS_ARRAY());
  }
  if (this->ScalingMode == 1 && this->ScalingFunction)
  {
    info->Set(vtkWhittedMaterialKeys::RADIUS_FUNCTION(), this->ScalingFunction);
  }
  else
  {
    info->Remove(vtkWhittedMaterialKeys::RADIUS_FUNCTION());
  }
  this->Property->Modified();
}

//------------------------------------------------------------------------------
void vtkWhittedGeometryRepresentation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  const double* kr = this->ReflectanceColor;
  const double* a = this->AttenuationColor;
  os << indent << "MaterialPreset: " << this->MaterialPreset << "\n";
  os << indent << "Reflectance: " << this->Reflectance << "\n";
  os << indent << "ReflectanceColor: " << kr[0] << " " << kr[1] << " " << kr[2] << "\n";
  os << indent << "Transmittance: " << this->Transmittance << "\n";
  os << indent << "IndexOfRefraction: " << this->IndexOfRefraction << "\n";
  os << indent << "AttenuationColor: " << a[0] << " " << a[1] << " " << a[2] << "\n";
  os << indent << "AttenuationDistance: " << this->AttenuationDistance << "\n";
  os << indent << "MaterialLibrary: " << (this->MaterialLibrary ? this->MaterialLibrary : "(none)")
     << "\n";
  os << indent << "LibraryMaterial: " << (this->LibraryMaterial ? this->LibraryMaterial : "(none)")
     << "\n";
  os << indent << "ScalingMode: " << this->ScalingMode << "\n";
  os << indent << "ScalingArray: " << this->ScalingArray << "\n";
}
