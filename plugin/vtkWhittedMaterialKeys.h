/**
 * @class   vtkWhittedMaterialKeys
 * @brief   the Whitted information keys of a vtkProperty: materials and per-point radii
 *
 * The keys an actor's vtkProperty information carries for the Whitted ray tracer, as
 * vtkOSPRayActorNode holds OSPRay's. Only static key accessors: the class is not instantiated.
 * @code
 *   vtkInformation* info = prop->GetInformation();
 *   double kr = 0.8;
 *   info->Set(vtkWhittedMaterialKeys::REFLECTANCE(), &kr, 1);         // grey mirror
 *   double kt[3] = { 0.9, 0.9, 0.8 };
 *   info->Set(vtkWhittedMaterialKeys::TRANSMITTANCE(), kt, 3);        // tinted glass
 *   info->Set(vtkWhittedMaterialKeys::INDEX_OF_REFRACTION(), 1.5);
 * @endcode
 * In Python: `from whitted import vtkWhittedMaterialKeys`,
 * `info.Set(vtkWhittedMaterialKeys.REFLECTANCE(), [0.8], 1)`.
 *
 * Readers of the keys: vtkWhittedMaterials (material keys -> whitted::Material) and
 * vtkWhittedSceneConverter (radius keys); writers: vtkWhittedMaterialLibrary (presets and OSPRay
 * material libraries), vtkWhittedClassicScene and ParaView's vtkWhittedGeometryRepresentation.
 * vtkWhittedPass::REFLECTANCE() and the other key functions of vtkWhittedPass return these same
 * key objects (kept for compatibility).
 *
 * @sa vtkWhittedPass vtkWhittedMaterialLibrary vtkWhittedMaterials
 */

#ifndef vtkWhittedMaterialKeys_h
#define vtkWhittedMaterialKeys_h

#include "vtkObject.h"
#include "vtkWhittedModule.h" // For export macro

class vtkInformationDoubleKey;
class vtkInformationDoubleVectorKey;
class vtkInformationObjectBaseKey;
class vtkInformationStringKey;

class VTKWHITTED_EXPORT vtkWhittedMaterialKeys : public vtkObject
{
public:
  vtkAbstractTypeMacro(vtkWhittedMaterialKeys, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Whitted material keys, set on an actor's vtkProperty information.
   * REFLECTANCE: weight of the mirror-reflected ray, 1 value (grey) or 3 (RGB) in [0,1]. Default 0.
   * TRANSMITTANCE: weight of the transmitted (refracted) ray and the filter applied to shadow rays
   * crossing the actor, 1 or 3 values in [0,1]. Default 1 - Opacity.
   * Energy: where REFLECTANCE + TRANSMITTANCE exceeds 1 in some channel, both are scaled (all
   * channels) by 1 / the largest channel sum, with one warning per actor.
   * INDEX_OF_REFRACTION: index of the actor's inside (outside is 1). Default 1 (no bending).
   * ATTENUATION_COLOR: Beer-Lambert absorption inside the actor, as the colour (1 or 3 values in
   * (0,1]) that white light keeps after ATTENUATION_DISTANCE world units inside it; applied to
   * refracted rays over the distance they travel inside. Default 1 (no absorption).
   * ATTENUATION_DISTANCE: world units over which light inside keeps ATTENUATION_COLOR (> 0).
   * Default 1. (The absorption coefficient per unit is -ln(colour) / distance, per channel.)
   * Energy rule (how the actor's own colour shares the pixel with these rays): vtkWhittedPass's
   * class documentation.
   */
  static vtkInformationDoubleVectorKey* REFLECTANCE();
  static vtkInformationDoubleVectorKey* TRANSMITTANCE();
  static vtkInformationDoubleKey* INDEX_OF_REFRACTION();
  static vtkInformationDoubleVectorKey* ATTENUATION_COLOR();
  static vtkInformationDoubleKey* ATTENUATION_DISTANCE();
  ///@}

  ///@{
  /**
   * Per-point radii of points drawn as spheres (RenderPointsAsSpheres, points representation) and
   * lines drawn as tubes (RenderLinesAsTubes), set on an actor's vtkProperty information (the
   * counterpart of vtkOSPRayActorNode's SCALE_ARRAY_NAME / SCALE_FUNCTION, which Debian's VTK
   * does not build).
   * RADIUS_ARRAY: name of a point array; a point's radius is its value (its only component, or
   * the magnitude of a vector), in data units. A tube segment has the mean of its two end
   * points' radii. Default unset: radius PointSize (LineWidth) x data diagonal / 1000.
   * RADIUS_FUNCTION: a vtkPiecewiseFunction the values go through first (clamped to its range),
   * e.g. to map a scalar range onto a radius range. Default unset (values are radii).
   * (vtkPointGaussianMapper's ScaleArray, ScaleFunction and ScaleFactor are read from the mapper.)
   */
  static vtkInformationStringKey* RADIUS_ARRAY();
  static vtkInformationObjectBaseKey* RADIUS_FUNCTION();
  ///@}

protected:
  vtkWhittedMaterialKeys() = default;
  ~vtkWhittedMaterialKeys() override = default;

private:
  vtkWhittedMaterialKeys(const vtkWhittedMaterialKeys&) = delete;
  void operator=(const vtkWhittedMaterialKeys&) = delete;
};

#endif
