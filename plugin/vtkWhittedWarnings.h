/**
 * @class   vtkWhittedWarnings
 * @brief   internal: every warning of the scene conversion, each said once per prop
 *
 * Private to the Whitted module. One enum names every warning the conversion can give; a warning
 * is printed (through the owner's vtkWarningWithObjectMacro) the first time a prop meets it, and
 * never again for that prop, so a scene with bad input warns once, not every frame. Every message
 * text lives in vtkWhittedWarnings.cxx (Warn's table and the Warn* functions), found by its enum
 * value; callers name the warning and pass only the values a message quotes.
 *
 * @sa vtkWhittedSceneConverter vtkWhittedPolyDataConverter
 */

#ifndef vtkWhittedWarnings_h
#define vtkWhittedWarnings_h

#include "vtkWhittedPolyDataConverter.h" // for vtkWhittedPolyDataConverter::Problems

#include <cstdint> // for uint32_t
#include <set>     // for std::set
#include <string>  // for std::string
#include <utility> // for std::pair

class vtkObject;
class vtkProp;
class vtkProperty;

class vtkWhittedWarnings
{
public:
  /// Every warning of the conversion, one bit each. Material fixes combine bits 0-7 as
  /// whitted::sanitizeMaterial returns them (core/scene/material.h) and are said once per combination.
  enum Warning : uint32_t
  {
    // A material value out of range or not finite, clamped (whitted::sanitizeMaterial bits)
    MaterialColor = 1u << 0,
    MaterialCoefficients = 1u << 1, // Ambient, Diffuse, Specular
    MaterialSpecularPower = 1u << 2,
    MaterialOpacity = 1u << 3,
    MaterialReflectance = 1u << 4,
    MaterialTransmittance = 1u << 5,
    MaterialIndexOfRefraction = 1u << 6,
    MaterialAbsorption = 1u << 7,
    MaterialClamped =
      0xffu, ///< Mask of the eight bits above.
             /// REFLECTANCE + TRANSMITTANCE above 1: both scaled (whitted::kMaterialEnergyScaled).
    MaterialEnergyScaled = 1u << 8,

    // Property settings the tracer does not honour
    PBRInterpolation = 1u << 9,
    UntraceableAssemblyPart = 1u << 11,

    // Actor matrices the tracer cannot use (the actor is not drawn)
    NonFiniteMatrix = 1u << 12,
    SingularMatrix = 1u << 13,

    // Input left out or ignored (vtkWhittedPolyDataConverter::Problems)
    NonFinitePoints = 1u << 14,
    InvalidCells = 1u << 15,
    MalformedCells = 1u << 16,
    BadNormals = 1u << 17,
    ShortNormals = 1u << 18,
    ShortScalars = 1u << 19,
    UnusableColors = 1u << 20,
    ShortTCoords = 1u << 21,
    NoSphereRadius = 1u << 22,
    NoTubeRadius = 1u << 23,

    // Environment (vtkSkybox) that reflections cannot sample as drawn
    StereoSkybox = 1u << 24,
    SkyboxCubeFaces = 1u << 25,
    FloorSkybox = 1u << 26,

    // Glyphs (vtkGlyph3DMapper)
    GlyphSourceTableTree = 1u << 27,
    GlyphArrays = 1u << 28,

    // Volumes (vtkWhittedVolumeConverter)
    VolumeOpenGL = 1u << 10,         ///< A setting the tracer does not trace: OpenGL draws it.
    VolumeSkipped = 1u << 29,        ///< Bad input: not drawn.
    VolumeInvalidScalars = 1u << 30, ///< NaN or infinite scalars: transparent.
    VolumeResampled = 1u << 31       ///< An unstructured grid traced after resampling to image data.
  };

  /// Object the warnings are printed for (the pass).
  void SetOwner(vtkObject* owner) { this->Owner = owner; }

  /**
   * A warning whose text is fixed (PBRInterpolation, UntraceableAssemblyPart, NonFiniteMatrix,
   * SingularMatrix, GlyphSourceTableTree, StereoSkybox, SkyboxCubeFaces, FloorSkybox), once per prop.
   */
  void Warn(vtkProp* prop, Warning warning);

  /**
   * GlyphArrays: the vtkWhittedGlyphPlacement::Problem (not None) that kept actor's glyphs from
   * being placed or scaled.
   */
  void WarnGlyphArrays(vtkProp* actor, int problem);

  /**
   * A volume warning (VolumeOpenGL, VolumeSkipped, VolumeInvalidScalars, VolumeResampled), once per
   * volume; what names the setting, the bad input, how many scalars, or the resampling.
   */
  void WarnVolume(vtkProp* volume, Warning warning, const std::string& what);

  /**
   * The problems found in one converted geometry of actor (drawn with property), each once;
   * block >= 0 names the composite block the geometry came from.
   */
  void WarnProblems(vtkProp* actor, vtkProperty* property,
    const vtkWhittedPolyDataConverter::Problems& problems, int block);

  /**
   * What whitted::sanitizeMaterial fixed (its result) in actor's material; energy is the largest
   * channel sum of REFLECTANCE + TRANSMITTANCE after clamping each to [0, 1] (for the message).
   */
  void WarnMaterial(vtkProp* actor, uint32_t fixed, float energy);

private:
  /// Prints "Actor <prop> (<class>): message" unless prop has had this warning before.
  void WarnOnce(vtkProp* prop, uint32_t warning, const std::string& message);

  vtkObject* Owner = nullptr;
  std::set<std::pair<vtkProp*, uint32_t>> Warned;
};

#endif
// VTK-HeaderTest-Exclude: vtkWhittedWarnings.h
