#include "vtkWhittedMaterialKeys.h"

#include "vtkInformationDoubleKey.h"
#include "vtkInformationDoubleVectorKey.h"
#include "vtkInformationObjectBaseKey.h"
#include "vtkInformationStringKey.h"

// The one definition of each key (vtkWhittedPass's key functions return these)
vtkInformationKeyMacro(vtkWhittedMaterialKeys, REFLECTANCE, DoubleVector);
vtkInformationKeyMacro(vtkWhittedMaterialKeys, TRANSMITTANCE, DoubleVector);
vtkInformationKeyMacro(vtkWhittedMaterialKeys, INDEX_OF_REFRACTION, Double);
vtkInformationKeyMacro(vtkWhittedMaterialKeys, ATTENUATION_COLOR, DoubleVector);
vtkInformationKeyMacro(vtkWhittedMaterialKeys, ATTENUATION_DISTANCE, Double);
vtkInformationKeyMacro(vtkWhittedMaterialKeys, RADIUS_ARRAY, String);
vtkInformationKeyMacro(vtkWhittedMaterialKeys, RADIUS_FUNCTION, ObjectBase);

//------------------------------------------------------------------------------
void vtkWhittedMaterialKeys::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
}
