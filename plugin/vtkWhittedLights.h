/**
 * @file    vtkWhittedLights.h
 * @brief   internal: a vtkRenderer's lights as the tracer's whitted::Light list
 *
 * Private to the Whitted module. Lights are read after vtkLightsPass has placed them, in world
 * coordinates (GetTransformedPosition / GetTransformedFocalPoint), so headlights and camera lights
 * follow the camera; switched-off lights are left out. Cheap: converted again every frame.
 *
 * @sa vtkWhittedSceneConverter
 */

#ifndef vtkWhittedLights_h
#define vtkWhittedLights_h

#include "scene/light.h" // for whitted::Light

#include <vector> // for std::vector

class vtkRenderer;

namespace vtkWhittedLights
{
/// What the lights mean for shading, beside the list itself.
struct Summary
{
  /// VTK's light complexity 1 (exactly one switched-on headlight): VTK's shader then uses the
  /// simpler specular term pow(N.L, power) (whitted::IntegratorSettings::headlightShading).
  bool HeadlightShading = false;
  /// At least one light is switched on (with none, VTK draws every actor unlit).
  bool LightsOn = false;
  /// How vtkGPUVolumeRayCastMapper (VTK 9.1) lights shaded volumes (whitted::VolumeLighting): a
  /// lone headlight of intensity 1 shines along each viewing ray and the ambient term is the
  /// property's (times the sample colour); otherwise each light has its direction and the ambient
  /// term is the property's times the sum of the lights' ambient colours (black by default).
  bool VolumeLightsAlongRays = false;
  whitted::Color VolumeAmbient{ 1.0f };
};

/// Fills lights with the renderer's switched-on lights, in the renderer's order. A light casts
/// shadows if its Shadow Attenuation is above 0 and, with brightestOnly, it is the brightest of
/// those (intensity x largest colour channel; the first of equals).
Summary Convert(vtkRenderer* renderer, std::vector<whitted::Light>& lights, bool brightestOnly);
}

#endif
// VTK-HeaderTest-Exclude: vtkWhittedLights.h
