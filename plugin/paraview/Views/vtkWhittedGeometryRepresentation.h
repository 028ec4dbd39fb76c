/**
 * @class   vtkWhittedGeometryRepresentation
 * @brief   surface representation carrying the Whitted material ("Whitted Surface" in the GUI)
 *
 * A vtkGeometryRepresentationWithFaces (ParaView's "Surface" representation class) with three more
 * settings, stored as vtkWhittedPass information keys on the actor's vtkProperty, where
 * vtkWhittedPass reads them: the same keys a VTK program sets by hand.
 *
 * - Reflectance: weight of the mirror-reflected ray in [0,1] (vtkWhittedPass::REFLECTANCE). Default
 * 0.
 * - Transmittance: weight of the refracted ray and shadow filter in [0,1]
 *   (vtkWhittedPass::TRANSMITTANCE). 0, the default, leaves the key unset so the pass uses 1 -
 * Opacity.
 * - IndexOfRefraction: index of the inside (vtkWhittedPass::INDEX_OF_REFRACTION). Default 1.
 *
 * The server-manager XML (xml/WhittedView.xml) adds it as representation type "Whitted Surface" to
 * ParaView's Geometry (polygonal and any other data set), UnstructuredGrid, StructuredGrid and
 * UniformGrid representations; the other properties (colouring, opacity, specular, ...) are shared
 * with "Surface".
 *
 * @sa vtkWhittedPass vtkPVWhittedView
 */

#ifndef vtkWhittedGeometryRepresentation_h
#define vtkWhittedGeometryRepresentation_h

#include "WhittedParaViewModule.h" // for export macro
#include "vtkGeometryRepresentationWithFaces.h"

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
  void SetReflectance(double value);
  double GetReflectance();
  void SetTransmittance(double value);
  double GetTransmittance();
  void SetIndexOfRefraction(double value);
  double GetIndexOfRefraction();
  ///@}

protected:
  vtkWhittedGeometryRepresentation();
  ~vtkWhittedGeometryRepresentation() override;

private:
  vtkWhittedGeometryRepresentation(const vtkWhittedGeometryRepresentation&) = delete;
  void operator=(const vtkWhittedGeometryRepresentation&) = delete;
};

#endif
