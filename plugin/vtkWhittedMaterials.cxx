#include "vtkWhittedMaterials.h"

#include "vtkWhittedMaterialKeys.h"
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
  readColor(vtkWhittedMaterialKeys::REFLECTANCE(), m.reflectance);
  readColor(vtkWhittedMaterialKeys::TRANSMITTANCE(), m.transmittance);
  if (info->Has(vtkWhittedMaterialKeys::INDEX_OF_REFRACTION()))
  {
    m.ior = static_cast<float>(info->Get(vtkWhittedMaterialKeys::INDEX_OF_REFRACTION()));
  }

  // Beer-Lambert: the colour kept after a distance, as the coefficient per unit the core uses
  // (whitted::absorptionFromAttenuation: a colour of 0, or a distance of 0, keeps nothing; a
  // colour above 1, below 0 or NaN, or a negative distance, gives a coefficient that
  // sanitizeMaterial clamps to 0 and warns about).
  Color attenuation(1.0f);
  readColor(vtkWhittedMaterialKeys::ATTENUATION_COLOR(), attenuation);
  const double distance = info->Has(vtkWhittedMaterialKeys::ATTENUATION_DISTANCE())
    ? info->Get(vtkWhittedMaterialKeys::ATTENUATION_DISTANCE())
    : 1.0;
  for (int i = 0; i < 3; ++i)
  {
    m.absorption[i] =
      whitted::absorptionFromAttenuation(static_cast<double>(attenuation[i]), distance);
  }
}
}

//------------------------------------------------------------------------------
namespace
{
// VTK's surface terms of property p (Ambient, Diffuse, Specular, their colours, SpecularPower,
// Opacity).
void ReadSurfaceTerms(vtkProperty* p, whitted::Material& m)
{
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
}

// PBR interpolation as a Whitted material (see plugin/README.md, "PBR interpolation"): base colour
// (Color) -> diffuse colour; Metallic, Roughness and BaseIOR -> reflectance by whitted::metallicReflectance
// (the rule the principled library material uses too); EmissiveFactor -> ambient term, only where VTK shows emission (an
// emissive texture; its texels are not sampled). A REFLECTANCE key wins over the mapping.
void MapPBR(vtkProperty* p, whitted::Material& m)
{
  double base[3];
  p->GetColor(base);
  double reflectance[3];
  whitted::metallicReflectance(base, p->GetMetallic(), p->GetRoughness(), p->GetBaseIOR(), reflectance);
  for (int i = 0; i < 3; ++i)
  {
    m.reflectance[i] = static_cast<float>(reflectance[i]);
  }
  if (p->GetTexture("emissiveTex"))
  {
    double e[3];
    p->GetEmissiveFactor(e);
    m.ambientColor = Color(e[0], e[1], e[2]);
    m.ambient = 1.0f;
  }
}

// The material of property p (the actor's property or a back-face property) for one block;
// lighting, interpolation and edges come from the property front (one shader draws both faces).
whitted::Material ConvertProperty(vtkActor* actor, vtkProperty* p, vtkProperty* front,
  const vtkWhittedMaterials::BlockAttributes& block, bool scalarColors, int texture, bool lightsOn,
  vtkWhittedWarnings& warnings)
{
  whitted::Material m;
  ReadSurfaceTerms(p, m);
  m.lighting = front->GetLighting() && lightsOn;
  m.flatShading = front->GetInterpolation() == VTK_FLAT;

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

  // Whitted terms; the defaults keep VTK's look (from the Opacity sanitizeMaterial will keep: a NaN
  // or out-of-range Opacity is one problem, not two)
  float opacity = m.opacity;
  whitted::sanitizeOpacity(opacity);
  m.transmittance = Color(1.0f - opacity);
  m.ior = 1.0f;
  if (front->GetInterpolation() == VTK_PBR)
  {
    MapPBR(p, m);
    warnings.Warn(actor, vtkWhittedWarnings::PBRInterpolation);
  }
  if (vtkInformation* info = p->GetInformation())
  {
    ReadWhittedKeys(info, m);
  }

  // Surface With Edges (width in pixels), drawn on front and back faces
  if (front->GetEdgeVisibility() && front->GetRepresentation() == VTK_SURFACE)
  {
    double c[3];
    front->GetEdgeColor(c);
    m.edgeColor = Color(c[0], c[1], c[2]);
    m.edgeWidth = static_cast<float>(front->GetLineWidth());
  }

  // Sanitise; the energy warning quotes the largest channel sum of kr + kt as sanitizeMaterial
  // sees it after clamping each to [0,1]
  float energy = 0.0f;
  if (const uint32_t fixed = whitted::sanitizeMaterial(m, &energy))
  {
    warnings.WarnMaterial(actor, fixed, energy);
  }
  return m;
}
}

//------------------------------------------------------------------------------
whitted::Material vtkWhittedMaterials::Convert(vtkActor* actor, const BlockAttributes& block,
  bool scalarColors, int texture, bool lightsOn, vtkWhittedWarnings& warnings)
{
  vtkProperty* p = actor->GetProperty();
  return ConvertProperty(actor, p, p, block, scalarColors, texture, lightsOn, warnings);
}

//------------------------------------------------------------------------------
whitted::Material vtkWhittedMaterials::ConvertBackface(vtkActor* actor, vtkProperty* back,
  vtkProperty* shader, const BlockAttributes& block, bool scalarColors, int texture, bool lightsOn,
  vtkWhittedWarnings& warnings)
{
  return ConvertProperty(actor, back, shader, block, scalarColors, texture, lightsOn, warnings);
}

//------------------------------------------------------------------------------
whitted::Material vtkWhittedMaterials::Culled()
{
  whitted::Material m;
  m.opacity = 0.0f;
  m.transmittance = whitted::Color(1.0f);
  m.ior = 1.0f;
  m.ambient = m.diffuse = m.specular = 0.0f;
  return m;
}
