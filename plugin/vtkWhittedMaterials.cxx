#include "vtkWhittedMaterials.h"

#include "vtkWhittedPass.h"
#include "vtkWhittedWarnings.h"

#include "vtkActor.h"
#include "vtkInformation.h"
#include "vtkInformationDoubleKey.h"
#include "vtkInformationDoubleVectorKey.h"
#include "vtkProperty.h"

#include <algorithm>
#include <cmath>

using whitted::Color;

namespace
{
// The Whitted terms from the property's information keys over their defaults.
void ReadWhittedKeys(vtkInformation* info, whitted::Material& m)
{
  auto readColor = [&](vtkInformationDoubleVectorKey* key, Color& dst)
  {
    if (info->Has(key))
    {
      const int n = info->Length(key);
      const double* v = info->Get(key);
      if (n >= 3)
      {
        dst = Color(v[0], v[1], v[2]);
      }
      else if (n >= 1)
      {
        dst = Color(static_cast<float>(v[0]));
      }
    }
  };
  readColor(vtkWhittedPass::REFLECTANCE(), m.reflectance);
  readColor(vtkWhittedPass::TRANSMITTANCE(), m.transmittance);
  if (info->Has(vtkWhittedPass::INDEX_OF_REFRACTION()))
  {
    m.ior = static_cast<float>(info->Get(vtkWhittedPass::INDEX_OF_REFRACTION()));
  }

  // Beer-Lambert: the colour kept after a distance, as the coefficient per unit the core uses
  // (-ln(colour) / distance). A colour of 0 (or a distance of 0) keeps nothing: the coefficient
  // is capped at the core's largest (1e30 per unit). A colour above 1, below 0 or NaN, or a
  // negative distance, gives a coefficient that sanitizeMaterial clamps to 0 and warns about.
  Color attenuation(1.0f);
  readColor(vtkWhittedPass::ATTENUATION_COLOR(), attenuation);
  const double distance = info->Has(vtkWhittedPass::ATTENUATION_DISTANCE())
    ? info->Get(vtkWhittedPass::ATTENUATION_DISTANCE())
    : 1.0;
  for (int i = 0; i < 3; ++i)
  {
    if (attenuation[i] != 1.0f)
    {
      const double a = -std::log(static_cast<double>(attenuation[i])) / distance;
      m.absorption[i] = static_cast<float>(std::isnan(a) ? a : std::min(a, 1e30));
    }
  }
}
}

//------------------------------------------------------------------------------
whitted::Material vtkWhittedMaterials::Convert(vtkActor* actor, const BlockAttributes& block,
  bool scalarColors, int texture, bool lightsOn, vtkWhittedWarnings& warnings)
{
  // VTK's surface terms
  vtkProperty* p = actor->GetProperty();
  whitted::Material m;
  double c[3];
  p->GetAmbientColor(c);
  m.ambientColor = Color(c[0], c[1], c[2]);
  p->GetDiffuseColor(c);
  m.diffuseColor = Color(c[0], c[1], c[2]);
  p->GetSpecularColor(c);
  m.specularColor = Color(c[0], c[1], c[2]);
  m.ambient = static_cast<float>(p->GetAmbient());
  m.diffuse = static_cast<float>(p->GetDiffuse());
  m.specular = static_cast<float>(p->GetSpecular());
  m.specularPower = static_cast<float>(p->GetSpecularPower());
  m.opacity = static_cast<float>(p->GetOpacity());
  m.lighting = p->GetLighting() && lightsOn;
  m.flatShading = p->GetInterpolation() == VTK_FLAT;

  // Block overrides of a composite mapper replace the property's colour and opacity
  if (block.HasColor)
  {
    m.ambientColor = m.diffuseColor = Color(block.Color[0], block.Color[1], block.Color[2]);
  }
  if (block.HasOpacity)
  {
    m.opacity = static_cast<float>(block.Opacity);
  }

  // Scalar colours replace ambient and diffuse colours (VTK 9.1); so do colour-map lookups of
  // interpolated scalars (the mesh carries the coordinates and the map)
  if (scalarColors)
  {
    m.colorSource = whitted::ColorSource::ScalarsAmbientAndDiffuse;
  }
  m.texture = texture;

  // Whitted terms; the defaults keep VTK's look (from an Opacity that is in range: a NaN or
  // out-of-range Opacity is one problem, not two)
  const float opacity = std::isfinite(m.opacity) ? std::clamp(m.opacity, 0.0f, 1.0f) : 1.0f;
  m.transmittance = Color(1.0f - opacity);
  m.ior = 1.0f;
  if (vtkInformation* info = p->GetInformation())
  {
    ReadWhittedKeys(info, m);
  }

  // Sanitise; the energy warning quotes the largest channel sum of kr + kt as sanitizeMaterial
  // sees it after clamping each to [0,1]
  float energy = 0.0f;
  for (int i = 0; i < 3; ++i)
  {
    auto clamp01 = [](float v) { return std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f; };
    energy = std::max(energy, clamp01(m.reflectance[i]) + clamp01(m.transmittance[i]));
  }
  if (const uint32_t fixed = whitted::sanitizeMaterial(m))
  {
    warnings.WarnMaterial(actor, fixed, energy);
  }
  return m;
}
