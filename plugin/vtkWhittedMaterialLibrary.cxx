#include "vtkWhittedMaterialLibrary.h"

#include "vtkWhittedMaterialKeys.h"

#include "vtkInformation.h"
#include "vtkInformationDoubleKey.h"
#include "vtkInformationDoubleVectorKey.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkProperty.h"
#include "vtk_jsoncpp.h"

#include "scene/material.h" // for whitted::metallicReflectance

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <vector>

vtkStandardNewMacro(vtkWhittedMaterialLibrary);

namespace
{
using RGB = std::array<double, 3>;

/// Every Whitted key of a material; what a preset or a library material sets.
struct WhittedKeys
{
  bool HasReflectance = false;
  RGB Reflectance{ 0, 0, 0 };
  bool HasTransmittance = false;
  RGB Transmittance{ 0, 0, 0 };
  double IndexOfRefraction = 1.0;
  RGB AttenuationColor{ 1, 1, 1 };
  double AttenuationDistance = 1.0;
};

/// The Phong highlight a preset gives: the mirror image of the point lights (the light kit), which
/// reflected rays cannot see. Specular 0 (ParaView's and VTK's default) would leave glass and
/// mirrors without one: on a plain background they would not show at all.
struct Highlight
{
  double Specular;
  double Power;
  RGB Color;
};

struct Preset
{
  const char* Name;
  WhittedKeys Keys;
  Highlight Light;
};

const Preset Presets[] = {
  { "None", {}, { 0, 1, { 1, 1, 1 } } },
  { "Glass", { false, {}, true, { 1, 1, 1 }, 1.5 }, { 1.0, 100, { 1, 1, 1 } } },
  { "Water", { false, {}, true, { 1, 1, 1 }, 1.33, { 0.80, 0.93, 0.95 } }, { 1.0, 100, { 1, 1, 1 } } },
  { "Mirror", { true, { 1, 1, 1 } }, { 1.0, 100, { 1, 1, 1 } } },
  { "Chrome", { true, { 0.55, 0.55, 0.55 } }, { 1.0, 100, { 1, 1, 1 } } },
  { "Gold", { true, { 1.0, 0.71, 0.29 } }, { 1.0, 100, { 1.0, 0.71, 0.29 } } },
  { "Copper", { true, { 0.95, 0.64, 0.54 } }, { 1.0, 100, { 0.95, 0.64, 0.54 } } },
  { "Plastic", { true, { 0.04, 0.04, 0.04 } }, { 0.5, 50, { 1, 1, 1 } } },
};

/// Writes every key: a key at its default is removed, so that "None" is exactly no keys.
void ApplyKeys(const WhittedKeys& k, vtkProperty* property)
{
  if (!property->GetInformation())
  {
    vtkNew<vtkInformation> info;
    property->SetInformation(info);
  }
  vtkInformation* info = property->GetInformation();
  auto setColor = [&](vtkInformationDoubleVectorKey* key, bool has, const RGB& c)
  {
    if (has)
    {
      info->Set(key, c.data(), 3);
    }
    else
    {
      info->Remove(key);
    }
  };
  setColor(vtkWhittedMaterialKeys::REFLECTANCE(), k.HasReflectance, k.Reflectance);
  setColor(vtkWhittedMaterialKeys::TRANSMITTANCE(), k.HasTransmittance, k.Transmittance);
  setColor(vtkWhittedMaterialKeys::ATTENUATION_COLOR(), k.AttenuationColor != RGB{ 1, 1, 1 },
    k.AttenuationColor);
  auto setScalar = [&](vtkInformationDoubleKey* key, double value, double fallback)
  {
    if (value != fallback)
    {
      info->Set(key, value);
    }
    else
    {
      info->Remove(key);
    }
  };
  setScalar(vtkWhittedMaterialKeys::INDEX_OF_REFRACTION(), k.IndexOfRefraction, 1.0);
  setScalar(vtkWhittedMaterialKeys::ATTENUATION_DISTANCE(), k.AttenuationDistance, 1.0);
  property->Modified();
}

/// The fields of one library material, as read.
struct LibraryMaterial
{
  std::string Type;
  std::map<std::string, std::vector<double>> Doubles;
  std::vector<std::string> Textures;
};

/// Reads a library material's fields, remembering which were used.
struct FieldReader
{
  const LibraryMaterial& M;
  std::set<std::string> Used;

  bool Has(const std::string& field) const { return this->M.Doubles.count(field) > 0; }
  double Scalar(const std::string& field, double fallback)
  {
    this->Used.insert(field);
    auto it = this->M.Doubles.find(field);
    return (it != this->M.Doubles.end() && !it->second.empty()) ? it->second[0] : fallback;
  }
  RGB Color(const std::string& field, const RGB& fallback)
  {
    this->Used.insert(field);
    auto it = this->M.Doubles.find(field);
    if (it == this->M.Doubles.end() || it->second.empty())
    {
      return fallback;
    }
    const std::vector<double>& v = it->second;
    return v.size() >= 3 ? RGB{ v[0], v[1], v[2] } : RGB{ v[0], v[0], v[0] };
  }
};

/// Normal-incidence reflectance of a conductor of complex index n + ik.
double ConductorReflectance(double n, double k)
{
  return ((n - 1) * (n - 1) + k * k) / ((n + 1) * (n + 1) + k * k);
}
}

class vtkWhittedMaterialLibraryInternals
{
public:
  std::map<std::string, LibraryMaterial> Materials;
  std::vector<std::string> Names; ///< Keys of Materials, for GetMaterialName.
};

//------------------------------------------------------------------------------
vtkWhittedMaterialLibrary::vtkWhittedMaterialLibrary()
  : Internals(new vtkWhittedMaterialLibraryInternals)
{
}

vtkWhittedMaterialLibrary::~vtkWhittedMaterialLibrary()
{
  delete this->Internals;
}

//------------------------------------------------------------------------------
int vtkWhittedMaterialLibrary::GetNumberOfPresets()
{
  return static_cast<int>(sizeof(Presets) / sizeof(Presets[0]));
}

const char* vtkWhittedMaterialLibrary::GetPresetName(int index)
{
  return (index >= 0 && index < GetNumberOfPresets()) ? Presets[index].Name : nullptr;
}

namespace
{
/// The built-in preset called name, or nullptr (also for a null name).
const Preset* FindPreset(const char* name)
{
  if (!name)
  {
    return nullptr;
  }
  for (const Preset& p : Presets)
  {
    if (std::string(p.Name) == name)
    {
      return &p;
    }
  }
  return nullptr;
}
} // namespace

bool vtkWhittedMaterialLibrary::GetPresetHighlight(
  const char* name, double& specular, double& specularPower, double specularColor[3])
{
  const Preset* p = FindPreset(name);
  if (!p || std::string(p->Name) == "None")
  {
    return false;
  }
  specular = p->Light.Specular;
  specularPower = p->Light.Power;
  for (int i = 0; i < 3; ++i)
  {
    specularColor[i] = p->Light.Color[i];
  }
  return true;
}

bool vtkWhittedMaterialLibrary::GetPresetFields(const char* name, double& reflectance,
  double reflectanceColor[3], double& transmittance, double& indexOfRefraction,
  double attenuationColor[3], double& attenuationDistance)
{
  const Preset* p = FindPreset(name);
  if (!p)
  {
    return false;
  }
  const WhittedKeys& k = p->Keys;
  const RGB kr = k.HasReflectance ? k.Reflectance : RGB{ 0, 0, 0 };
  reflectance = std::max({ kr[0], kr[1], kr[2] });
  transmittance =
    k.HasTransmittance ? std::max({ k.Transmittance[0], k.Transmittance[1], k.Transmittance[2] }) : 0.0;
  for (int i = 0; i < 3; ++i)
  {
    reflectanceColor[i] = reflectance > 0.0 ? kr[i] / reflectance : 1.0;
    attenuationColor[i] = k.AttenuationColor[i];
  }
  indexOfRefraction = k.IndexOfRefraction;
  attenuationDistance = k.AttenuationDistance;
  return true;
}

bool vtkWhittedMaterialLibrary::ApplyPreset(const char* name, vtkProperty* property)
{
  const Preset* p = property ? FindPreset(name) : nullptr;
  if (!p)
  {
    return false;
  }
  ApplyKeys(p->Keys, property);
  return true;
}

//------------------------------------------------------------------------------
bool vtkWhittedMaterialLibrary::ReadFile(const char* filename)
{
  std::ifstream in(filename ? filename : "", std::ios::binary);
  if (!in)
  {
    vtkErrorMacro("Cannot open material library " << (filename ? filename : "(null)"));
    return false;
  }
  std::ostringstream text;
  text << in.rdbuf();
  return this->Parse(text.str(), filename);
}

bool vtkWhittedMaterialLibrary::ReadBuffer(const char* json)
{
  return this->Parse(json ? json : "", "buffer");
}

bool vtkWhittedMaterialLibrary::Parse(const std::string& text, const char* origin)
{
  Json::Value root;
  std::string errors;
  Json::CharReaderBuilder builder;
  std::istringstream stream(text);
  if (!Json::parseFromStream(builder, stream, &root, &errors) || !root.isObject())
  {
    vtkErrorMacro("Material library " << origin << " is not JSON: " << errors);
    return false;
  }
  if (!root.isMember("family") || root["family"].asString() != "OSPRay" ||
    !root.isMember("materials") || !root["materials"].isObject())
  {
    vtkErrorMacro("Material library " << origin
                                      << " is not an OSPRay material library (needs \"family\": "
                                         "\"OSPRay\" and a \"materials\" object)");
    return false;
  }
  const Json::Value& materials = root["materials"];
  for (const std::string& name : materials.getMemberNames())
  {
    const Json::Value& jm = materials[name];
    if (!jm.isObject() || !jm.isMember("type"))
    {
      vtkWarningMacro("Material " << name << " in " << origin << " has no \"type\": skipped");
      continue;
    }
    LibraryMaterial m;
    m.Type = jm["type"].asString();
    if (jm.isMember("doubles") && jm["doubles"].isObject())
    {
      const Json::Value& doubles = jm["doubles"];
      for (const std::string& field : doubles.getMemberNames())
      {
        std::vector<double>& values = m.Doubles[field];
        const Json::Value& jv = doubles[field];
        if (jv.isArray())
        {
          for (const Json::Value& x : jv)
          {
            values.push_back(x.isNumeric() ? x.asDouble() : std::nan(""));
          }
        }
        else if (jv.isNumeric())
        {
          values.push_back(jv.asDouble());
        }
      }
    }
    if (jm.isMember("textures") && jm["textures"].isObject())
    {
      m.Textures = jm["textures"].getMemberNames();
    }
    this->Internals->Materials[name] = std::move(m);
  }
  this->Internals->Names.clear();
  for (const auto& entry : this->Internals->Materials)
  {
    this->Internals->Names.push_back(entry.first);
  }
  this->Modified();
  return true;
}

//------------------------------------------------------------------------------
int vtkWhittedMaterialLibrary::GetNumberOfMaterials()
{
  return static_cast<int>(this->Internals->Names.size());
}

const char* vtkWhittedMaterialLibrary::GetMaterialName(int index)
{
  return (index >= 0 && index < this->GetNumberOfMaterials())
    ? this->Internals->Names[index].c_str()
    : nullptr;
}

const char* vtkWhittedMaterialLibrary::GetMaterialType(const char* name)
{
  auto it = this->Internals->Materials.find(name ? name : "");
  return it != this->Internals->Materials.end() ? it->second.Type.c_str() : "";
}

//------------------------------------------------------------------------------
bool vtkWhittedMaterialLibrary::ApplyMaterial(const char* name, vtkProperty* property)
{
  auto it = this->Internals->Materials.find(name ? name : "");
  if (it == this->Internals->Materials.end() || !property)
  {
    vtkErrorMacro("No material " << (name ? name : "(null)") << " in the library");
    return false;
  }
  const LibraryMaterial& m = it->second;
  FieldReader f{ m, {} };
  WhittedKeys k;
  const std::string& type = m.Type;
  if (type == "glass")
  {
    k.HasTransmittance = true;
    k.Transmittance = { 1, 1, 1 };
    k.IndexOfRefraction = f.Scalar("eta", 1.5);
    k.AttenuationColor = f.Color("attenuationColor", { 1, 1, 1 });
    k.AttenuationDistance = f.Scalar("attenuationDistance", 1.0);
  }
  else if (type == "thinGlass")
  {
    const RGB c = f.Color("attenuationColor", { 1, 1, 1 });
    const double ratio = f.Scalar("thickness", 1.0) / f.Scalar("attenuationDistance", 1.0);
    k.HasTransmittance = true;
    for (int i = 0; i < 3; ++i)
    {
      k.Transmittance[i] = std::pow(c[i], ratio);
    }
    f.Used.insert("eta"); // a thin sheet does not bend rays: its index has no Whitted effect
  }
  else if (type == "metal")
  {
    const RGB eta = f.Color("eta", { 1.5, 0.98, 0.6 });
    const RGB kappa = f.Color("k", { 7.6, 6.6, 5.4 });
    k.HasReflectance = true;
    for (int i = 0; i < 3; ++i)
    {
      k.Reflectance[i] = ConductorReflectance(eta[i], kappa[i]);
    }
  }
  else if (type == "alloy")
  {
    k.HasReflectance = true;
    k.Reflectance = f.Color("color", { 0.9, 0.9, 0.9 });
  }
  else if (type == "principled")
  {
    const RGB base = f.Color("baseColor", { 0.8, 0.8, 0.8 });
    const double transmission = f.Scalar("transmission", 0.0);
    property->SetDiffuseColor(base[0], base[1], base[2]);
    whitted::metallicReflectance(base.data(), f.Scalar("metallic", 0.0), f.Scalar("roughness", 0.0),
      f.Scalar("ior", 1.5), k.Reflectance.data());
    k.HasReflectance = k.Reflectance[0] > 0.0 || k.Reflectance[1] > 0.0 || k.Reflectance[2] > 0.0;
    k.HasTransmittance = transmission > 0.0;
    k.Transmittance = { transmission, transmission, transmission };
    k.IndexOfRefraction = f.Scalar("ior", 1.5);
    if (!k.HasTransmittance)
    {
      k.IndexOfRefraction = 1.0;
    }
    k.AttenuationColor = f.Color("transmissionColor", { 1, 1, 1 });
    k.AttenuationDistance = f.Scalar("transmissionDepth", 1.0);
  }
  else if (type == "obj" || type == "OBJMaterial")
  {
    const RGB kd = f.Color("Kd", { 0.8, 0.8, 0.8 });
    property->SetDiffuseColor(kd[0], kd[1], kd[2]);
    if (f.Has("Ks"))
    {
      const RGB ks = f.Color("Ks", { 0, 0, 0 });
      property->SetSpecularColor(ks[0], ks[1], ks[2]);
      property->SetSpecular(1.0);
    }
    if (f.Has("Ns"))
    {
      property->SetSpecularPower(f.Scalar("Ns", 10.0));
    }
    if (f.Has("d"))
    {
      property->SetOpacity(f.Scalar("d", 1.0));
    }
    if (f.Has("Tf"))
    {
      k.HasTransmittance = true;
      k.Transmittance = f.Color("Tf", { 0, 0, 0 });
    }
  }
  else
  {
    vtkWarningMacro("Material " << it->first << " has OSPRay type " << type
                                << ", which has no Whitted equivalent: not applied");
    return false;
  }
  ApplyKeys(k, property);

  // What the Whitted material does not use
  std::string unused;
  for (const auto& field : m.Doubles)
  {
    if (!f.Used.count(field.first))
    {
      unused += (unused.empty() ? "" : ", ") + field.first;
    }
  }
  for (const std::string& texture : m.Textures)
  {
    unused += (unused.empty() ? "texture " : ", texture ") + texture;
  }
  if (!unused.empty())
  {
    vtkWarningMacro("Material " << it->first << " (" << type
                                << "): fields with no Whitted equivalent are ignored: " << unused);
  }
  return true;
}

//------------------------------------------------------------------------------
void vtkWhittedMaterialLibrary::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Materials: " << this->GetNumberOfMaterials() << "\n";
  for (const auto& entry : this->Internals->Materials)
  {
    os << indent.GetNextIndent() << entry.first << " (" << entry.second.Type << ")\n";
  }
}
