/**
 * @class   vtkWhittedMaterialLibrary
 * @brief   named Whitted materials: built-in presets and OSPRay material library files
 *
 * A material here is a set of Whitted information keys (vtkWhittedMaterialKeys: REFLECTANCE,
 * TRANSMITTANCE, INDEX_OF_REFRACTION, ATTENUATION_COLOR, ATTENUATION_DISTANCE) applied to a
 * vtkProperty. Applying one sets every key, so nothing of a previous material is left over.
 *
 * Built-in presets (ApplyPreset), each defined by its normal-incidence reflectance or its
 * transmittance; the surface's own colour and highlight stay as the vtkProperty sets them and
 * get the share the energy rule leaves (see vtkWhittedPass):
 * - None: removes the keys (VTK's look: kr 0, kt 1 - Opacity).
 * - Glass: kt 1, index 1.5.  Water: kt 1, index 1.33, a blue-green tint (colour kept after 1 world
 *   unit 0.80, 0.93, 0.95).
 * - Mirror: kr 1.  Chrome: kr 0.55.  Gold: kr (1.0, 0.71, 0.29).  Copper: kr (0.95, 0.64, 0.54).
 * - Plastic: kr 0.04 (the normal-incidence Fresnel reflectance of index 1.5), body colour 0.96.
 *
 * OSPRay material libraries (ReadFile / ReadBuffer): the JSON format of vtkOSPRayMaterialLibrary
 * and ParaView's "Load Ray Tracing Materials":
 * @code
 *   { "family": "OSPRay", "version": "0.0",
 *     "materials": { "<name>": { "type": "<OSPRay type>", "doubles": { "<field>": [ ... ] } } } }
 * @endcode
 * Fields used, per type (anything else, textures included, is ignored with a warning when the
 * material is applied; types not listed are not applied):
 * - glass: eta -> INDEX_OF_REFRACTION (default 1.5), attenuationColor, attenuationDistance ->
 *   ATTENUATION_COLOR, ATTENUATION_DISTANCE; TRANSMITTANCE 1.
 * - thinGlass: TRANSMITTANCE = attenuationColor ^ (thickness / attenuationDistance) (defaults 1,
 *   1, 1), index 1 (a thin sheet does not bend rays).
 * - metal: eta, k (RGB complex index, default aluminium (1.5, 0.98, 0.6), (7.6, 6.6, 5.4)) ->
 *   REFLECTANCE = the normal-incidence reflectance ((n-1)^2 + k^2) / ((n+1)^2 + k^2).
 * - alloy: color -> REFLECTANCE (default 0.9).
 * - principled: baseColor -> DiffuseColor; metallic m, roughness r, ior -> REFLECTANCE =
 *   (1 - r) x (m x baseColor + (1 - m) x F0(ior)), the rule of VTK's PBR interpolation
 *   (whitted::metallicReflectance),
 *   transmission -> TRANSMITTANCE, ior -> INDEX_OF_REFRACTION, transmissionColor,
 *   transmissionDepth -> ATTENUATION_COLOR, ATTENUATION_DISTANCE.
 * - obj (OBJMaterial): Kd -> DiffuseColor, Ks -> SpecularColor (and Specular 1), Ns ->
 *   SpecularPower, d -> Opacity, Tf -> TRANSMITTANCE.
 * Other roughness fields and those of a layered model have no Whitted equivalent.
 *
 * @sa vtkWhittedMaterialKeys vtkWhittedPass vtkOSPRayMaterialLibrary
 */

#ifndef vtkWhittedMaterialLibrary_h
#define vtkWhittedMaterialLibrary_h

#include "vtkObject.h"
#include "vtkWhittedModule.h" // For export macro

#include <string> // for std::string

class vtkProperty;
class vtkWhittedMaterialLibraryInternals;

class VTKWHITTED_EXPORT vtkWhittedMaterialLibrary : public vtkObject
{
public:
  static vtkWhittedMaterialLibrary* New();
  vtkTypeMacro(vtkWhittedMaterialLibrary, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Built-in presets, in the order of ParaView's MaterialPreset list: None, Glass, Water, Mirror,
   * Chrome, Gold, Copper, Plastic. GetPresetName returns nullptr out of range.
   */
  static int GetNumberOfPresets();
  static const char* GetPresetName(int index);
  ///@}

  /**
   * Sets every Whitted key of property to the named preset (case-sensitive; "None" removes them)
   * and marks it modified. Returns false, leaving property unchanged, for an unknown name.
   */
  static bool ApplyPreset(const char* name, vtkProperty* property);

  /**
   * The specular highlight of a preset (the mirror image of the lights, which the Whitted keys
   * cannot give): Specular, SpecularPower, SpecularColor. Glass, Water, Mirror, Chrome: 1, 100,
   * white; Gold, Copper: 1, 100, their reflectance colour; Plastic: 0.5, 50, white. Returns false
   * for None and unknown names. ApplyPreset does not set them (a vtkProperty's highlight is the
   * program's); ParaView's "Whitted Surface" representation does (vtkWhittedGeometryRepresentation).
   */
  static bool GetPresetHighlight(
    const char* name, double& specular, double& specularPower, double specularColor[3]);

  /**
   * A preset as the fields of ParaView's "Whitted Surface" representation, which its panel shows
   * when the preset is chosen: Reflectance (the largest component of the preset's reflectance)
   * times ReflectanceColor (the reflectance over that, white for none), Transmittance (the largest
   * component), IndexOfRefraction, AttenuationColor, AttenuationDistance. "None" gives the fields'
   * defaults (0, white, 0, 1, white, 1). Returns false for unknown names.
   */
  static bool GetPresetFields(const char* name, double& reflectance, double reflectanceColor[3],
    double& transmittance, double& indexOfRefraction, double attenuationColor[3],
    double& attenuationDistance);

  ///@{
  /**
   * Reads an OSPRay material library from a JSON file or string; the materials are added to
   * those already read (a name read again is replaced). Returns false, with an error, for what
   * is not such a library (not JSON, family not "OSPRay", no "materials").
   */
  bool ReadFile(const char* filename);
  bool ReadBuffer(const char* json);
  ///@}

  ///@{
  /**
   * Materials read so far, in name order, and the OSPRay type of one ("" if not read).
   */
  int GetNumberOfMaterials();
  const char* GetMaterialName(int index);
  const char* GetMaterialType(const char* name);
  ///@}

  /**
   * Applies a material read from a library to property: the Whitted keys of its type (class
   * documentation), every other key removed, and the vtkProperty fields the type maps to.
   * Warns once per call about each field that is not used. Returns false, leaving property
   * unchanged, for a name not read or a type with no Whitted mapping.
   */
  bool ApplyMaterial(const char* name, vtkProperty* property);

protected:
  vtkWhittedMaterialLibrary();
  ~vtkWhittedMaterialLibrary() override;

private:
  bool Parse(const std::string& text, const char* origin);

  vtkWhittedMaterialLibraryInternals* Internals;

  vtkWhittedMaterialLibrary(const vtkWhittedMaterialLibrary&) = delete;
  void operator=(const vtkWhittedMaterialLibrary&) = delete;
};

#endif
