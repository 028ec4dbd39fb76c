/**
 * @class   vtkSMWhittedSurfaceRepresentationProxy
 * @brief   client-side proxy of the "Whitted Surface" representation: a preset shows in its fields
 *
 * The server-manager proxy of vtkWhittedGeometryRepresentation (xml/WhittedView.xml,
 * `<WhittedSurfaceRepresentationProxy>`). Choosing a Material Preset writes the preset's values
 * into the Reflectance, Reflectance Color, Transmittance, Index Of Refraction, Attenuation Color and
 * Attenuation Distance properties (vtkWhittedMaterialLibrary::GetPresetFields), so that the
 * Properties panel, Python and saved states show what the preset renders. Editing one of those
 * fields afterwards to a value other than the preset's switches the preset to None: the fields,
 * which start from the preset's values, then apply (a preset overrides the fields while it is
 * chosen). Choosing None gives back the values the fields had before the first preset was chosen
 * (presets tried and dropped leave the user's material as it was). Loading a state keeps the state's preset; a preset chosen in a state saved before the
 * fields followed it fills them after the load.
 */
#ifndef vtkSMWhittedSurfaceRepresentationProxy_h
#define vtkSMWhittedSurfaceRepresentationProxy_h

#include "vtkSMRepresentationProxy.h"
#include "WhittedParaViewModule.h" // for export macro

#include <memory> // for std::unique_ptr

class WHITTEDPARAVIEW_EXPORT vtkSMWhittedSurfaceRepresentationProxy : public vtkSMRepresentationProxy
{
public:
  static vtkSMWhittedSurfaceRepresentationProxy* New();
  vtkTypeMacro(vtkSMWhittedSurfaceRepresentationProxy, vtkSMRepresentationProxy);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  int LoadXMLState(vtkPVXMLElement* element, vtkSMProxyLocator* locator) override;
  void UpdateVTKObjects() override;

  struct Fields;

protected:
  vtkSMWhittedSurfaceRepresentationProxy();
  ~vtkSMWhittedSurfaceRepresentationProxy() override;

  void SetPropertyModifiedFlag(const char* name, int flag) override;

private:
  vtkSMWhittedSurfaceRepresentationProxy(const vtkSMWhittedSurfaceRepresentationProxy&) = delete;
  void operator=(const vtkSMWhittedSurfaceRepresentationProxy&) = delete;

  /// Writes the chosen preset's values into the fields (nothing for None)
  void FillFieldsFromPreset();
  void WriteFields(const Fields& fields);
  Fields ReadFields();
  /// True once MaterialPreset and every field exist with their values
  bool HasFields();
  /// True if the fields hold other values than the chosen preset's
  bool FieldsDifferFromPreset();

  bool Updating = false; // set while this class writes properties, and while a state loads
  std::unique_ptr<Fields> UserFields; // the fields before a preset was chosen, given back by None
};

#endif
