// Surface materials: VTK's vtkProperty lighting parameters plus Whitted's reflectance, transmittance and index of
// refraction. Textures and the colour sanitisers they share with geometry: geometry/texture.h.
#pragma once

#include "geometry/texture.h"
#include "util/math.h"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace whitted {

/// How the colour of a surface point combines with the material, mirroring VTK's mapper.
enum class ColorSource : uint8_t {
  Material,                  ///< Property colours only.
  ScalarsDiffuse,            ///< Geometry colour replaces the diffuse colour (VTK ScalarMaterialMode Diffuse).
  ScalarsAmbient,            ///< Geometry colour replaces the ambient colour.
  ScalarsAmbientAndDiffuse,  ///< Geometry colour replaces both (VTK's default when colouring by scalars).
};

/// One material. Field meanings and defaults are those of vtkProperty, plus the Whitted terms.
struct Material {
  // Local (VTK) shading
  Color ambientColor{1.0f};    ///< vtkProperty AmbientColor. Default white.
  Color diffuseColor{1.0f};    ///< vtkProperty DiffuseColor. Default white.
  Color specularColor{1.0f};   ///< vtkProperty SpecularColor. Default white.
  float ambient = 0.0f;        ///< vtkProperty Ambient coefficient. Default 0.
  float diffuse = 1.0f;        ///< vtkProperty Diffuse coefficient. Default 1.
  float specular = 0.0f;       ///< vtkProperty Specular coefficient. Default 0.
  float specularPower = 1.0f;  ///< vtkProperty SpecularPower (Phong exponent). Default 1.
  float opacity = 1.0f;        ///< vtkProperty Opacity: weight of the local colour (see bodyWeight). Default 1.
  bool lighting = true;        ///< vtkProperty Lighting: false = unlit (colour = ambient + diffuse colours).
  bool flatShading = false;    ///< true = facet normals (VTK_FLAT interpolation).
  ColorSource colorSource = ColorSource::Material;

  // Whitted terms. Energy: kr + kt <= 1 in every channel (sanitizeMaterial scales both down when the sum exceeds 1)
  Color reflectance{0.0f};    ///< kr: weight of the mirror-reflected ray, RGB in [0,1]. Default 0.
  Color transmittance{0.0f};  ///< kt: weight of the refracted ray and shadow-ray attenuation per crossing, RGB in
                              ///< [0,1]. Default 0.
  float ior = 1.0f;           ///< Index of refraction of the inside (outside is vacuum, 1). Default 1.
  Color absorption{0.0f};     ///< Beer-Lambert coefficient per world unit, used only when enabled. Default 0.

  int32_t texture = -1;  ///< Index into Scene textures, or -1. The texel modulates the diffuse/ambient colour.

  // Surface with edges (vtkProperty EdgeVisibility): triangle edges the mesh marks (TriangleMesh::edgeFlags) are
  // drawn where a ray passes within edgeWidth / 2 pixels of them (pixel footprint: IntegratorSettings), shaded
  // with edgeMaterial(*this).
  float edgeWidth = 0.0f;   ///< Edge width in pixels (vtkProperty LineWidth); 0 = no edges. Default 0.
  Color edgeColor{1.0f};    ///< vtkProperty EdgeColor. Default white.
  /// Material of the back faces (vtkProperty BackfaceProperty): index into Scene materials, or -1 = this one.
  /// Used where the ray meets the geometric normal from behind. Default -1.
  int32_t backMaterial = -1;
};

/// The material an edge pixel is shaded with: VTK draws edges as lines in EdgeColor over the surface, with the
/// surface's coefficients and Opacity but no texture, no scalar colours and no Whitted terms of their own. So:
/// ambient and diffuse colours = edgeColor, no reflection, transmittance min(kt, 1 - opacity) (VTK's blend of a
/// translucent actor, never more than the surface's own), index 1, no edges.
Material edgeMaterial(const Material& m);

/// The energy rule: the weight of a surface point's body colour (ambient + diffuse terms), given the point's
/// opacity (Opacity times the vertex and texel alpha, each <= 1). The reflected and transmitted rays take kr + kt;
/// the body gets what they leave, in the channel where they leave least, and never more than the opacity:
///   bodyWeight = min(opacity, 1 - max over channels of (kr + kt)).
/// So Transmittance alone makes clear glass and Reflectance alone a mirror (kr or kt = 1: no body colour, no
/// over-exposure), while a translucent actor with the default kt = 1 - Opacity and kr = 0 keeps exactly VTK's
/// blend, opacity x colour + (1 - Opacity) x behind: there 1 - (kr + kt) = Opacity, and the comparison below is
/// made against 1 - Opacity so that float rounding cannot change a pixel of such an actor. The body colour is
/// taken clamped to [0, 1], as VTK's shader writes it, before its share is applied. The specular highlight
/// is weighted by the opacity alone, as VTK weights it: it stands for the mirror image of the point lights,
/// which reflected rays cannot see. Requires a sanitised material (kr + kt <= 1).
inline float bodyWeight(const Material& m, float opacity) {
  const float e = std::max(m.reflectance.x + m.transmittance.x,
                           std::max(m.reflectance.y + m.transmittance.y, m.reflectance.z + m.transmittance.z));
  if (e <= 1.0f - m.opacity) return opacity;  // kr + kt leave at least the opacity (VTK's translucency)
  return std::max(0.0f, std::min(opacity, 1.0f - e));
}

/// Bit of sanitizeMaterial's result: kr + kt exceeded 1 in some channel, so kr and kt were both scaled (all
/// channels) by 1 / max over channels of (kr + kt): their ratio is kept and the largest sum becomes 1 (to float
/// rounding, never above), so a surface never returns more light than reaches it.
constexpr uint32_t kMaterialEnergyScaled = 1u << 8;

/// Largest Beer-Lambert coefficient (per world unit) a material keeps: sanitizeMaterial clamps
/// Material::absorption to [0, kMaxAbsorption]. Enough to keep nothing after any distance a scene can hold.
constexpr float kMaxAbsorption = 1e30f;

/// The Beer-Lambert coefficient per world unit (Material::absorption) that keeps the fraction kept of the light
/// after distance: -ln(kept) / distance in double, capped at kMaxAbsorption (kept 0 keeps nothing); kept exactly 1
/// gives 0 whatever the distance. kept above 1 or below 0 or NaN, or a negative distance, give a coefficient
/// (negative or NaN) that sanitizeMaterial clamps to 0 and reports (bit 7).
float absorptionFromAttenuation(double kept, double distance);

/// The one metallic -> reflectance rule, used by VTK's PBR interpolation (vtkProperty Metallic, Roughness, BaseIOR)
/// and by OSPRay's "principled" library material (metallic, roughness, ior): a smooth surface mirrors with
///   (1 - roughness) x (metallic x base + (1 - metallic) x F0),   F0 = ((n - 1) / (n + 1))^2,
/// F0 the dielectric normal-incidence reflectance of index n (0.04, that of n = 1.5, when n is not a positive
/// finite number). A Whitted mirror cannot blur, so roughness fades the mirror image out linearly instead.
/// metallic and roughness are clamped to [0, 1]; out is in double so that material keys keep it unrounded.
void metallicReflectance(const double base[3], double metallic, double roughness, double ior, double out[3]);

/// The opacity rule of sanitizeMaterial: a non-finite opacity becomes 1 (opaque), one outside [0, 1] is clamped.
/// Returns true if it changed opacity.
bool sanitizeOpacity(float& opacity);

/// Sanitises a material in place and returns a bit mask of what was fixed (0 = nothing), so adapters can warn
/// once. Bits 0-7: a value was NaN, infinite or outside its documented range and was replaced or clamped
/// (0 a colour, 1 ambient/diffuse/specular, 2 specularPower, 3 opacity, 4 reflectance, 5 transmittance, 6 ior,
/// 7 absorption; an edge colour outside [0,1] sets bit 0, a negative or non-finite edge width (set to 0) bit 1); kr and kt are each clamped to [0,1] first. Then, if kr + kt > 1 in any channel, both are
/// scaled as kMaterialEnergyScaled describes. A material with kr + kt <= 1 everywhere keeps kr and kt bit-exact.
/// energySum, if given, receives the largest channel sum of kr + kt after that clamping and before the scaling
/// (the sum a warning about kMaterialEnergyScaled quotes).
uint32_t sanitizeMaterial(Material& m, float* energySum = nullptr);

}  // namespace whitted
