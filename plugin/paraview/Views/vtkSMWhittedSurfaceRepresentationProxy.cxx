#include "vtkSMWhittedSurfaceRepresentationProxy.h"

#include "vtkObjectFactory.h"
#include "vtkSMPropertyHelper.h"
#include "vtkSMVectorProperty.h"
#include "vtkWhittedMaterialLibrary.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

vtkStandardNewMacro(vtkSMWhittedSurfaceRepresentationProxy);

/// The representation's material fields, in the order GetPresetFields gives them
struct vtkSMWhittedSurfaceRepresentationProxy::Fields
{
  double Reflectance = 0.0;
  std::array<double, 3> ReflectanceColor{ 1, 1, 1 };
  double Transmittance = 0.0;
  double IndexOfRefraction = 1.0;
  std::array<double, 3> AttenuationColor{ 1, 1, 1 };
  double AttenuationDistance = 1.0;
};

namespace
{
using Fields = vtkSMWhittedSurfaceRepresentationProxy::Fields;

const char* const FieldNames[] = { "Reflectance", "ReflectanceColor", "Transmittance",
  "IndexOfRefraction", "AttenuationColor", "AttenuationDistance" };

bool PresetFields(vtkSMProxy* proxy, Fields& f)
{
  const int preset = vtkSMPropertyHelper(proxy, "MaterialPreset").GetAsInt();
  return preset > 0 &&
    vtkWhittedMaterialLibrary::GetPresetFields(vtkWhittedMaterialLibrary::GetPresetName(preset),
      f.Reflectance, f.ReflectanceColor.data(), f.Transmittance, f.IndexOfRefraction,
      f.AttenuationColor.data(), f.AttenuationDistance);
}

/// Equal as the panel shows them (the presets' values are exact in double; the tolerance absorbs a
/// value typed back from its printed form)
bool Same(double a, double b)
{
  return std::abs(a - b) <= 1e-9 * std::max(1.0, std::abs(b));
}

}

vtkSMWhittedSurfaceRepresentationProxy::vtkSMWhittedSurfaceRepresentationProxy() = default;
vtkSMWhittedSurfaceRepresentationProxy::~vtkSMWhittedSurfaceRepresentationProxy() = default;

void vtkSMWhittedSurfaceRepresentationProxy::WriteFields(const Fields& f)
{
  const bool was = this->Updating;
  this->Updating = true;
  vtkSMPropertyHelper(this, "Reflectance").Set(f.Reflectance);
  vtkSMPropertyHelper(this, "ReflectanceColor").Set(f.ReflectanceColor.data(), 3);
  vtkSMPropertyHelper(this, "Transmittance").Set(f.Transmittance);
  vtkSMPropertyHelper(this, "IndexOfRefraction").Set(f.IndexOfRefraction);
  vtkSMPropertyHelper(this, "AttenuationColor").Set(f.AttenuationColor.data(), 3);
  vtkSMPropertyHelper(this, "AttenuationDistance").Set(f.AttenuationDistance);
  this->Updating = was;
}

vtkSMWhittedSurfaceRepresentationProxy::Fields vtkSMWhittedSurfaceRepresentationProxy::ReadFields()
{
  Fields f;
  f.Reflectance = vtkSMPropertyHelper(this, "Reflectance").GetAsDouble();
  vtkSMPropertyHelper(this, "ReflectanceColor").Get(f.ReflectanceColor.data(), 3);
  f.Transmittance = vtkSMPropertyHelper(this, "Transmittance").GetAsDouble();
  f.IndexOfRefraction = vtkSMPropertyHelper(this, "IndexOfRefraction").GetAsDouble();
  vtkSMPropertyHelper(this, "AttenuationColor").Get(f.AttenuationColor.data(), 3);
  f.AttenuationDistance = vtkSMPropertyHelper(this, "AttenuationDistance").GetAsDouble();
  return f;
}

void vtkSMWhittedSurfaceRepresentationProxy::FillFieldsFromPreset()
{
  Fields f;
  if (PresetFields(this, f))
  {
    this->WriteFields(f);
  }
}

bool vtkSMWhittedSurfaceRepresentationProxy::FieldsDifferFromPreset()
{
  Fields p;
  if (!PresetFields(this, p))
  {
    return false;
  }
  const Fields f = this->ReadFields();
  auto sameColor = [](const std::array<double, 3>& a, const std::array<double, 3>& b)
  { return Same(a[0], b[0]) && Same(a[1], b[1]) && Same(a[2], b[2]); };
  return !Same(f.Reflectance, p.Reflectance) || !sameColor(f.ReflectanceColor, p.ReflectanceColor) ||
    !Same(f.Transmittance, p.Transmittance) || !Same(f.IndexOfRefraction, p.IndexOfRefraction) ||
    !sameColor(f.AttenuationColor, p.AttenuationColor) ||
    !Same(f.AttenuationDistance, p.AttenuationDistance);
}

bool vtkSMWhittedSurfaceRepresentationProxy::HasFields()
{
  for (const char* field : FieldNames)
  {
    vtkSMVectorProperty* p = vtkSMVectorProperty::SafeDownCast(this->GetProperty(field));
    if (!p || p->GetNumberOfElements() == 0)
    {
      return false;
    }
  }
  vtkSMVectorProperty* preset = vtkSMVectorProperty::SafeDownCast(this->GetProperty("MaterialPreset"));
  return preset && preset->GetNumberOfElements() > 0;
}

void vtkSMWhittedSurfaceRepresentationProxy::SetPropertyModifiedFlag(const char* name, int flag)
{
  this->Superclass::SetPropertyModifiedFlag(name, flag);
  // Not while the proxy is made (its properties get their defaults before its objects exist) or
  // before every field is there
  if (this->Updating || !name || !flag || !this->ObjectsCreated || !this->HasFields())
  {
    return;
  }
  if (std::strcmp(name, "MaterialPreset") == 0)
  {
    if (vtkSMPropertyHelper(this, "MaterialPreset").GetAsInt() > 0)
    {
      // The user's own values are kept for a later None (a preset tried and dropped)
      if (!this->UserFields)
      {
        this->UserFields.reset(new Fields(this->ReadFields()));
      }
      this->FillFieldsFromPreset();
    }
    else if (this->UserFields)
    {
      this->WriteFields(*this->UserFields);
      this->UserFields.reset();
    }
    return;
  }
  for (const char* field : FieldNames)
  {
    if (std::strcmp(name, field) == 0 && this->FieldsDifferFromPreset())
    {
      // A field edited away from the preset: the fields, as the preset left them with this edit,
      // apply from now on
      this->UserFields.reset();
      this->Updating = true;
      vtkSMPropertyHelper(this, "MaterialPreset").Set(0);
      this->Updating = false;
      return;
    }
  }
}

int vtkSMWhittedSurfaceRepresentationProxy::LoadXMLState(
  vtkPVXMLElement* element, vtkSMProxyLocator* locator)
{
  this->Updating = true;
  const int status = this->Superclass::LoadXMLState(element, locator);
  this->Updating = false;
  return status;
}

void vtkSMWhittedSurfaceRepresentationProxy::UpdateVTKObjects()
{
  // While a preset is chosen the fields show it: this also fills them after a state whose fields
  // were saved at other values (before the fields followed presets), once the whole state is loaded
  if (!this->Updating && this->HasFields() && this->FieldsDifferFromPreset())
  {
    this->FillFieldsFromPreset();
  }
  this->Superclass::UpdateVTKObjects();
}

void vtkSMWhittedSurfaceRepresentationProxy::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
}
