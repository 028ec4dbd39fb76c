/**
 * @class   vtkWhittedGeometryRepresentation
 * @brief   surface representation carrying the Whitted material ("Whitted Surface" in the GUI)
 *
 * A vtkGeometryRepresentationWithFaces (ParaView's "Surface" representation class) with the
 * Whitted material, stored as vtkWhittedMaterialKeys information keys on the actor's vtkProperty,
 * where vtkWhittedPass reads them: the same keys a VTK program sets by hand.
 *
 * - MaterialPreset: 0 None (the fields below apply), else a vtkWhittedMaterialLibrary preset by
 *   index (1 Glass, 2 Water, 3 Mirror, 4 Chrome, 5 Gold, 6 Copper, 7 Plastic) that sets every key
 *   and overrides the fields below. Default 0.
 * - Reflectance: weight of the mirror-reflected ray in [0,1], times ReflectanceColor (RGB in
 *   [0,1], default white) -> vtkWhittedMaterialKeys::REFLECTANCE. Default 0.
 * - Transmittance: weight of the refracted ray and shadow filter in [0,1]
 *   (vtkWhittedMaterialKeys::TRANSMITTANCE). 0, the default, leaves the key unset so the pass
 *   uses 1 - Opacity.
 * - IndexOfRefraction: index of the inside (vtkWhittedMaterialKeys::INDEX_OF_REFRACTION).
 *   Default 1.
 * - AttenuationColor, AttenuationDistance: Beer-Lambert absorption inside, the colour white light
 *   keeps after that many world units (vtkWhittedMaterialKeys::ATTENUATION_COLOR,
 *   ATTENUATION_DISTANCE). Default white (no absorption), 1.
 * - MaterialLibrary, LibraryMaterial: an OSPRay material library file (JSON, as ParaView's "Load
 *   Ray Tracing Materials" reads; read where the representation runs, i.e. on the server) and the
 *   name of one of its materials. With MaterialPreset None and a material of that name, the
 *   material is applied (vtkWhittedMaterialLibrary::ApplyMaterial) instead of the fields above.
 *   Default none ("" or "None"). GetLibraryMaterialNames lists the materials read (information
 *   property LibraryMaterialNames).
 *
 * Per-point radii: ParaView's OSPRay scaling properties of the representation (Scaling Mode
 * "OSPRayUseScaleArray", Scale Array, Scale Function; hidden in the GUI of a ParaView without ray
 * tracing, settable from Python), which Debian's ParaView ignores, set the Whitted radius keys
 * instead: Each Exact (2) -> vtkWhittedMaterialKeys::RADIUS_ARRAY (points as spheres, lines as
 * tubes take the array's value as radius), Each Scaled (1) -> RADIUS_ARRAY and RADIUS_FUNCTION
 * (values through the Scale Function); All Approximate (0, the default) and All Exact (-1) leave
 * them unset (PointSize / LineWidth radii).
 *
 * The server-manager XML (xml/WhittedView.xml) adds it as representation type "Whitted Surface" to
 * ParaView's Geometry (polygonal and any other data set), UnstructuredGrid, StructuredGrid and
 * UniformGrid representations; the other properties (colouring, opacity, specular, ...) are shared
 * with "Surface".
 *
 * @sa vtkWhittedPass vtkWhittedMaterialLibrary vtkPVWhittedView
 */

#ifndef vtkWhittedGeometryRepresentation_h
#define vtkWhittedGeometryRepresentation_h

#include "WhittedParaViewModule.h" // for export macro
#include "vtkGeometryRepresentationWithFaces.h"
#include "vtkSmartPointer.h" // for vtkSmartPointer

#include <string> // for std::string

class vtkPiecewiseFunction;
class vtkStringArray;
class vtkWhittedMaterialLibrary;

class WHITTEDPARAVIEW_EXPORT vtkWhittedGeometryRepresentation
  : public vtkGeometryRepresentationWithFaces
{
public:
  static vtkWhittedGeometryRepresentation* New();
  vtkTypeMacro(vtkWhittedGeometryRepresentation, vtkGeometryRepresentationWithFaces);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Whitted material of this representation's actor (see class documentation).
   */
  void SetMaterialPreset(int preset);
  vtkGetMacro(MaterialPreset, int);
  void SetReflectance(double value);
  vtkGetMacro(Reflectance, double);
  void SetReflectanceColor(double r, double g, double b);
  vtkGetVector3Macro(ReflectanceColor, double);
  void SetTransmittance(double value);
  vtkGetMacro(Transmittance, double);
  void SetIndexOfRefraction(double value);
  vtkGetMacro(IndexOfRefraction, double);
  void SetAttenuationColor(double r, double g, double b);
  vtkGetVector3Macro(AttenuationColor, double);
  void SetAttenuationDistance(double value);
  vtkGetMacro(AttenuationDistance, double);
  void SetMaterialLibrary(const char* filename);
  vtkGetStringMacro(MaterialLibrary);
  void SetLibraryMaterial(const char* name);
  vtkGetStringMacro(LibraryMaterial);
  vtkStringArray* GetLibraryMaterialNames(); ///< the materials of MaterialLibrary, in name order
  ///@}

  ///@{
  /**
   * The Surface's highlight. With a MaterialPreset other than None the preset's highlight is
   * used instead (vtkWhittedMaterialLibrary::GetPresetHighlight: glass and mirrors show the
   * lights); these values come back with None.
   */
  void SetSpecular(double value) override;
  void SetSpecularPower(double value) override;
  void SetSpecularColor(double r, double g, double b) override;
  ///@}

  ///@{
  /**
   * OSPRay scaling properties, forwarded as the Whitted radius keys (see class documentation).
   */
  void SetEnableScaling(int mode) override;
  void SetScalingArrayName(const char* name) override;
  void SetScalingFunction(vtkPiecewiseFunction* function) override;
  ///@}

protected:
  vtkWhittedGeometryRepresentation();
  ~vtkWhittedGeometryRepresentation() override;

  int MaterialPreset = 0;
  double Reflectance = 0.0;
  double ReflectanceColor[3] = { 1.0, 1.0, 1.0 };
  double Transmittance = 0.0;
  double IndexOfRefraction = 1.0;
  double AttenuationColor[3] = { 1.0, 1.0, 1.0 };
  double AttenuationDistance = 1.0;
  char* MaterialLibrary = nullptr;
  char* LibraryMaterial = nullptr;
  double UserSpecular = 0.0;
  double UserSpecularPower = 100.0;
  double UserSpecularColor[3] = { 1.0, 1.0, 1.0 };
  int ScalingMode = 0;
  std::string ScalingArray;
  vtkSmartPointer<vtkPiecewiseFunction> ScalingFunction;

private:
  // Writes the keys of the preset, the library material or the fields onto the actor's property.
  void UpdateMaterialKeys();
  // Gives the superclass the preset's highlight, or the user's
  void UpdateHighlight();
  // Writes (or removes) the radius keys from the scaling mode, array and function.
  void UpdateRadiusKeys();
  // Sets a field (a colour) and updates the keys if it changed.
  template <typename T>
  void Assign(T& field, T value);
  void AssignColor(double* field, double r, double g, double b);

  vtkSmartPointer<vtkWhittedMaterialLibrary> Library; ///< MaterialLibrary as read (empty if none).
  vtkSmartPointer<vtkStringArray> LibraryMaterialNames; ///< its names (GetLibraryMaterialNames).

  vtkWhittedGeometryRepresentation(const vtkWhittedGeometryRepresentation&) = delete;
  void operator=(const vtkWhittedGeometryRepresentation&) = delete;
};

#endif
