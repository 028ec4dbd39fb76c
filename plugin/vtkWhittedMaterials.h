/**
 * @file    vtkWhittedMaterials.h
 * @brief   internal: a vtkProperty (plus the Whitted keys) as the tracer's whitted::Material
 *
 * Private to the Whitted module. VTK's surface terms (Ambient, Diffuse, Specular and their colours,
 * SpecularPower, Opacity, Lighting, Interpolation) are taken as they are; the Whitted terms come
 * from the property's information keys (vtkWhittedMaterialKeys::REFLECTANCE, TRANSMITTANCE,
 * INDEX_OF_REFRACTION, ATTENUATION_COLOR, ATTENUATION_DISTANCE) with defaults that keep VTK's
 * look (no reflection, transmittance 1 - Opacity, index 1, no absorption). EdgeVisibility with
 * EdgeColor and LineWidth become the material's edges (pixels); PBR interpolation is mapped to a
 * Whitted material with a warning (plugin/README.md). The material is then
 * sanitised by the core (whitted::sanitizeMaterial) and
 * what it fixed is warned about once per actor. Cheap: converted again every frame.
 *
 * @sa vtkWhittedSceneConverter vtkWhittedWarnings
 */

#ifndef vtkWhittedMaterials_h
#define vtkWhittedMaterials_h

#include "scene/material.h" // for whitted::Material

class vtkActor;
class vtkProperty;
class vtkWhittedWarnings;

namespace vtkWhittedMaterials
{
/// Colour and opacity a composite mapper's display attributes set for one block.
struct BlockAttributes
{
  bool HasColor = false;
  double Color[3] = { 1.0, 1.0, 1.0 }; ///< Replaces the ambient and diffuse colours.
  bool HasOpacity = false;
  double Opacity = 1.0; ///< Replaces the property's Opacity.
};

/**
 * The material of actor (its property), for one block of its input.
 * - scalarColors: the geometry carries colours mapped from scalars (or colour-map coordinates):
 *   they replace the ambient and diffuse colours, as in VTK 9.1.
 * - texture: scene texture applied after lighting, -1 for none.
 * - lightsOn: the renderer has a light switched on (else every actor is unlit, as VTK draws it).
 */
whitted::Material Convert(vtkActor* actor, const BlockAttributes& block, bool scalarColors,
  int texture, bool lightsOn, vtkWhittedWarnings& warnings);

/**
 * The material of back faces (whitted::Material::backMaterial) from property back: the actor's
 * BackfaceProperty, or the property of another actor that draws this actor's back faces (ParaView's
 * backface actor). As VTK's shader does, the surface terms (colours, coefficients, Opacity) and the
 * Whitted keys come from back; lighting, interpolation and edges from shader (the property of the
 * actor that draws the faces); scalar colours, texture and block overrides as for the front.
 */
whitted::Material ConvertBackface(vtkActor* actor, vtkProperty* back, vtkProperty* shader,
  const BlockAttributes& block, bool scalarColors, int texture, bool lightsOn,
  vtkWhittedWarnings& warnings);

/// The material of a culled face side (BackfaceCulling / FrontfaceCulling): no colour of its own,
/// transmittance 1 and index 1, so rays and shadow rays pass it unchanged.
whitted::Material Culled();
}

#endif
// VTK-HeaderTest-Exclude: vtkWhittedMaterials.h
