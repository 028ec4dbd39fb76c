// The environment: what reflected and bent rays see when they leave the scene (Scene::environment, defined in
// environment.cpp, looks it up by direction).
#pragma once

#include "util/math.h"

#include <cstdint>

namespace whitted {

/// An image around the scene, sampled by direction: what reflected and bent rays see when they leave the scene
/// (VTK's vtkSkybox / vtkRenderer::SetEnvironmentTexture, ParaView's Skybox background; or the screen-space
/// textured background seen as a backdrop). Texture ids index Scene textures; rows bottom to top.
struct EnvironmentMap {
  enum class Projection : uint8_t {
    None,    ///< No image: the background colour (or vertical gradient by elevation) is the environment.
    Sphere,  ///< Equirectangular image (VTK's vtkSkybox Sphere projection and equirectangular IBL textures).
    Cube,    ///< Six faces, +X, -X, +Y, -Y, +Z, -Z in VTK's input order, OpenGL cube-map face orientation.
    Screen,  ///< A screen-space backdrop (VTK's textured background) seen along the direction's projection.
  };
  Projection projection = Projection::None;
  int32_t faces[6] = {-1, -1, -1, -1, -1, -1};  ///< Sphere and Screen use faces[0].
  /// Sphere: orthonormal frame of the image. A direction d maps to u = atan2(d.right, d.front) / 2pi + 0.5,
  /// v = atan2(d.up, |(d.right, d.front)|) / pi + 0.5 (vtkSkybox's shader: front = up x right).
  /// Cube: (right, up, -front) is the frame of the cube-map lookup (defaults give the world direction).
  Vec3 right{1.0, 0.0, 0.0}, up{0.0, 1.0, 0.0}, front{0.0, 0.0, -1.0};
  /// Screen: the camera's world -> clip matrix, view direction and up (set per frame).
  Mat4 worldToClip{1.0};
  Vec3 viewDirection{0.0, 0.0, -1.0}, viewUp{0.0, 1.0, 0.0};
};

}  // namespace whitted
