#include "vtkWhittedLights.h"

#include "vtkLight.h"
#include "vtkLightCollection.h"
#include "vtkRenderer.h"

#include <algorithm>

//------------------------------------------------------------------------------
vtkWhittedLights::Summary vtkWhittedLights::Convert(
  vtkRenderer* renderer, std::vector<whitted::Light>& lights, bool brightestOnly)
{
  lights.clear();
  // VTK's light complexity, as vtkOpenGLRenderer::UpdateLights computes it: 0 no light on, 1 one
  // headlight, 2 directional lights, 3 positional lights
  int count = 0;
  int complexity = 0;
  // The same as vtkOpenGLGPUVolumeRayCastMapper computes it for shaded volumes (a lone headlight
  // must also have intensity 1), and the sum of the lights' ambient colours it lights them with
  int volumeComplexity = 0;
  whitted::Color ambient(0.0f);
  vtkLightCollection* lc = renderer->GetLights();
  vtkCollectionSimpleIterator sit;
  lc->InitTraversal(sit);
  while (vtkLight* light = lc->GetNextLight(sit))
  {
    const double status = light->GetSwitch();
    if (status > 0.0)
    {
      ++count;
      if (complexity == 0)
      {
        complexity = 1;
      }
    }
    if (complexity == 1 && (count > 1 || light->GetLightType() != VTK_LIGHT_TYPE_HEADLIGHT))
    {
      complexity = 2;
    }
    if (complexity < 3 && light->GetPositional())
    {
      complexity = 3;
    }
    volumeComplexity = status > 0.0 && volumeComplexity == 0 ? 1 : volumeComplexity;
    if (volumeComplexity == 1 &&
      (count > 1 || light->GetIntensity() != 1.0 || light->GetLightType() != VTK_LIGHT_TYPE_HEADLIGHT))
    {
      volumeComplexity = 2;
    }
    if (status <= 0.0)
    {
      continue;
    }

    whitted::Light l;
    double v[3];
    light->GetAmbientColor(v);
    ambient += static_cast<float>(light->GetIntensity()) * whitted::Color(v[0], v[1], v[2]);
    light->GetTransformedPosition(v);
    l.position = whitted::Vec3(v[0], v[1], v[2]);
    light->GetTransformedFocalPoint(v);
    l.focalPoint = whitted::Vec3(v[0], v[1], v[2]);
    light->GetDiffuseColor(v);
    l.color = whitted::Color(v[0], v[1], v[2]);
    l.intensity = static_cast<float>(light->GetIntensity());
    l.positional = light->GetPositional() != 0;
    light->GetAttenuationValues(v);
    l.attenuation = whitted::Vec3(v[0], v[1], v[2]);
    l.coneAngle = light->GetConeAngle();
    l.exponent = light->GetExponent();
    l.castShadows = light->GetShadowAttenuation() > 0.0f;
    lights.push_back(l);
  }
  if (brightestOnly)
  {
    whitted::Light* brightest = nullptr;
    float power = 0.0f;
    for (whitted::Light& l : lights)
    {
      const float p = l.intensity * std::max(l.color.x, std::max(l.color.y, l.color.z));
      if (l.castShadows && (!brightest || p > power))
      {
        brightest = &l;
        power = p;
      }
      l.castShadows = false;
    }
    if (brightest)
    {
      brightest->castShadows = true;
    }
  }
  Summary summary;
  summary.HeadlightShading = complexity == 1;
  summary.LightsOn = count > 0;
  summary.VolumeLightsAlongRays = volumeComplexity == 1;
  summary.VolumeAmbient = volumeComplexity == 1 ? whitted::Color(1.0f) : ambient;
  return summary;
}
