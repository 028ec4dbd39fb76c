#include "vtkWhittedWarnings.h"

#include "vtkWhittedGlyphPlacement.h"

#include "vtkObject.h"
#include "vtkProp.h"
#include "vtkProperty.h"

#include "scene/material.h"

#include <cstdio>

static_assert(vtkWhittedWarnings::MaterialEnergyScaled == whitted::kMaterialEnergyScaled,
  "the energy warning is sanitizeMaterial's energy bit");

//------------------------------------------------------------------------------
void vtkWhittedWarnings::WarnOnce(vtkProp* prop, uint32_t warning, const std::string& message)
{
  if (this->Warned.insert(std::make_pair(prop, warning)).second)
  {
    vtkWarningWithObjectMacro(
      this->Owner, << (prop->IsA("vtkVolume") ? "Volume " : "Actor ") << prop << " (" << prop->GetClassName() << "): " << message);
  }
}

//------------------------------------------------------------------------------
void vtkWhittedWarnings::Warn(vtkProp* prop, Warning warning)
{
  const char* message = nullptr;
  switch (warning)
  {
    case PBRInterpolation:
      message = "PBR interpolation is approximated by a Whitted material: base colour as diffuse colour, "
                "(1 - Roughness) x (Metallic x base colour + (1 - Metallic) x F0(BaseIOR)) as reflectance, "
                "EmissiveFactor as ambient term with an emissive texture (not sampled); roughness blur, "
                "anisotropy, normal and ORM textures are not traced";
      break;
    case UntraceableAssemblyPart:
      message = "part of an assembly that the ray tracer cannot draw (not a surface polydata actor): "
                "skipped";
      break;
    case NonFiniteMatrix:
      message = "its matrix (Position, Orientation, Scale, Origin, UserMatrix) has NaN or infinite "
                "entries: not drawn";
      break;
    case SingularMatrix:
      message = "its matrix is singular (e.g. a zero Scale flattening it): the ray tracer cannot draw "
                "it";
      break;
    case GlyphSourceTableTree:
      message = "glyphs from a source table tree are not traced: drawn by OpenGL";
      break;
    case StereoSkybox:
      message = "stereo skybox: reflections see the whole image as one equirectangular panorama";
      break;
    case SkyboxCubeFaces:
      message = "cube-map skybox without six image faces: reflections see the background colour";
      break;
    case FloorSkybox:
      message = "floor skybox: reflections see the background colour (only sphere and cube skyboxes "
                "are sampled by direction)";
      break;
    default:
      break;
  }
  if (message)
  {
    this->WarnOnce(prop, warning, message);
  }
  else
  {
    vtkErrorWithObjectMacro(this->Owner, << "vtkWhittedWarnings::Warn: warning " << warning
                                         << " has parameters: use its own Warn function");
  }
}

//------------------------------------------------------------------------------
void vtkWhittedWarnings::WarnGlyphArrays(vtkProp* actor, int problem)
{
  static const char* const what[] = { "",
    "its orientation array does not have 3 components (4 for quaternions)",
    "its mask array has more than one component",
    "scaling by components needs a scale array of 3 components",
    "one of its orientation, mask, source index or scale arrays has fewer tuples than the dataset has "
    "points" };
  static_assert(vtkWhittedGlyphPlacement::ShortArray == 4, "one message per glyph problem");
  if (problem <= vtkWhittedGlyphPlacement::None || problem > vtkWhittedGlyphPlacement::ShortArray)
  {
    return;
  }
  this->WarnOnce(actor, GlyphArrays,
    std::string(what[problem]) + ": as in VTK, " +
      (problem == vtkWhittedGlyphPlacement::ScaleComponents ? "glyphs are not scaled"
                                                            : "no glyph is drawn"));
}

//------------------------------------------------------------------------------
void vtkWhittedWarnings::WarnVolume(vtkProp* volume, Warning warning, const std::string& what)
{
  switch (warning)
  {
    case VolumeOpenGL:
      this->WarnOnce(volume, warning,
        "volume not ray traced (" + what +
          "): drawn by VTK's OpenGL volume mapper over the traced image, so it is absent from "
          "mirrors and glass, casts no shadow and composites with surfaces by depth only");
      break;
    case VolumeSkipped:
      this->WarnOnce(volume, warning, "volume not drawn: " + what);
      break;
    case VolumeInvalidScalars:
      this->WarnOnce(volume, warning, what + " scalars are NaN or infinite: traced as transparent");
      break;
    case VolumeResampled:
      this->WarnOnce(volume, warning,
        "unstructured grid resampled to image data for tracing (vtkResampleToImage, " + what +
          ", as ParaView's 'Resample To Image' volume mode): detail finer than its spacing is smoothed");
      break;
    default:
      break;
  }
}

//------------------------------------------------------------------------------
void vtkWhittedWarnings::WarnProblems(
  vtkProp* actor, vtkProperty* property, const vtkWhittedPolyDataConverter::Problems& p, int block)
{
  const std::string prefix = block >= 0 ? "block " + std::to_string(block) + ": " : "";
  auto warn = [&](bool found, Warning warning, const std::string& message)
  {
    if (found)
    {
      this->WarnOnce(actor, warning, prefix + message);
    }
  };
  const std::string np = std::to_string(p.NumberOfPoints);
  warn(p.NonFinitePoints, NonFinitePoints,
    std::to_string(p.NonFinitePoints) + " of " + np +
      " points have NaN or infinite coordinates: the cells using them are not drawn");
  warn(p.InvalidCells, InvalidCells,
    std::to_string(p.InvalidCells) + " cells use point ids outside [0, " + np +
      "): they are not drawn");
  warn(p.MalformedCellArrays, MalformedCells,
    std::to_string(p.MalformedCellArrays) +
      " cell arrays are malformed (offsets do not match the connectivity): not drawn");
  warn(p.BadNormals, BadNormals,
    std::to_string(p.BadNormals) +
      " normals are NaN, infinite or zero-length: the facet normal is used there");
  warn(p.ShortNormals, ShortNormals,
    "the normals array has fewer tuples than points (cells) or not 3 components: ignored, "
    "facet normals used");
  warn(p.ShortScalars, ShortScalars,
    "the colour array has fewer tuples than the points (cells) it colours: ignored, the "
    "property colour is used");
  warn(p.UnusableColors, UnusableColors,
    "the scalars are used directly as colours but have no 1 to 4 components (or are a char "
    "array): ignored, the property colour is used");
  warn(p.ShortTCoords, ShortTCoords,
    "the texture coordinates have fewer tuples than points or more than 3 components: the "
    "texture is not applied");
  warn(p.NoSphereRadius, NoSphereRadius,
    "PointSize " + std::to_string(property->GetPointSize()) +
      " gives spheres no positive radius: the points (vertices) are not drawn");
  warn(p.NoTubeRadius, NoTubeRadius,
    "LineWidth " + std::to_string(property->GetLineWidth()) +
      " gives tubes no positive radius: the lines are not drawn");
}

//------------------------------------------------------------------------------
void vtkWhittedWarnings::WarnMaterial(vtkProp* actor, uint32_t fixed, float energy)
{
  if (const uint32_t clamped = fixed & MaterialClamped)
  {
    // What was clamped, in words
    static const char* const what[] = { "a colour", "Ambient/Diffuse/Specular", "SpecularPower",
      "Opacity", "REFLECTANCE", "TRANSMITTANCE", "INDEX_OF_REFRACTION", "ATTENUATION_COLOR/DISTANCE" };
    std::string msg;
    for (int i = 0; i < 8; ++i)
    {
      if (clamped & (1u << i))
      {
        msg += msg.empty() ? "" : ", ";
        msg += what[i];
      }
    }
    this->WarnOnce(actor, clamped,
      msg + " out of range or not finite: clamped" +
        ((clamped & MaterialIndexOfRefraction) ? " (an INDEX_OF_REFRACTION <= 0 or NaN becomes 1)"
                                               : ""));
  }
  if (fixed & MaterialEnergyScaled)
  {
    char sum[32];
    std::snprintf(sum, sizeof(sum), "%.4g", energy);
    this->WarnOnce(actor, MaterialEnergyScaled,
      std::string("REFLECTANCE + TRANSMITTANCE is above 1 (largest channel sum ") + sum +
        "): both scaled by 1/" + sum +
        " so that sum is 1 (a surface cannot return more light than reaches it)");
  }
}
