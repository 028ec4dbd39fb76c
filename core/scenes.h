// Built-in scenes (used by the command-line renderer, the tests and the benchmark).
#pragma once

#include "camera.h"
#include "scene.h"

#include <string>
#include <vector>

namespace whitted {

/// Camera in VTK terms; near/far are derived from the scene bounds when not positive.
struct CameraSpec {
  Vec3 eye{0.0, 0.0, 5.0}, focal{0.0}, up{0.0, 1.0, 0.0};
  double viewAngle = 30.0;  ///< Vertical, degrees (vtkCamera default 30).
  double nearDist = 0.0, farDist = 0.0;
  /// Builds the camera for an image of the given aspect; clipping range from bounds like
  /// vtkRenderer::ResetCameraClippingRange when not set.
  Camera make(double aspect, const Bounds3& sceneBounds) const;
};

/// Whitted's classic scene: checkerboard floor, mirror sphere, glass sphere, one point light.
/// sphereSubdivisions == 0 gives analytic spheres; > 0 gives UV-sphere meshes with that many rings.
void buildClassicScene(Scene& scene, CameraSpec& cam, int sphereSubdivisions = 0);

/// A UV sphere mesh (theta x phi resolution) with outward normals, as vtkSphereSource builds it.
TriangleMesh makeSphereMesh(const Vec3& center, double radius, int thetaRes, int phiRes);

/// A grid of quads on the plane spanned by (origin, origin+u, origin+v), nu x nv cells, two triangles each,
/// per-triangle colours alternating between c0 and c1 (checkerboard) when given.
TriangleMesh makeGrid(const Vec3& origin, const Vec3& u, const Vec3& v, int nu, int nv, const Color4* c0 = nullptr,
                      const Color4* c1 = nullptr);

/// Names of the built-in scenes and a builder by name (false if unknown).
std::vector<std::string> builtinSceneNames();
bool buildBuiltinScene(const std::string& name, Scene& scene, CameraSpec& cam);

}  // namespace whitted
