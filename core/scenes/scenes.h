// Built-in scenes (used by the command-line renderer, the tests and the benchmark).
#pragma once

#include "shading/camera.h"
#include "scene/scene.h"

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

/// Whitted's classic scene as data: a checkerboard floor, a mirror sphere, a glass sphere, one point light. The one
/// description of the scene: buildClassicScene traces it (whitted_render, the benchmark and its POV-Ray export, the
/// core tests), and the VTK module's vtkWhittedClassicScene builds it from VTK sources (the demo, the C++ and Python
/// regression tests). Values in VTK's terms (vtkPlaneSource, vtkProperty, vtkLight, vtkCamera) and in double, so
/// the VTK side is handed exactly these numbers.
struct ClassicSceneDescription {
  /// The floor: a plane given as vtkPlaneSource gives it (origin, point1, point2) of cellsX x cellsY cells whose
  /// colours alternate between color0 (cell (0, 0)) and color1.
  struct Floor {
    Vec3 origin, point1, point2;
    int cellsX, cellsY;
    Vec3 color0, color1;
    double ambient, diffuse;  ///< vtkProperty coefficients.
  };
  /// A sphere and its material: vtkProperty colour and coefficients, Whitted kr, kt and IOR (kt 0: opaque, and
  /// neither kt nor IOR is set on the VTK side).
  struct Ball {
    Vec3 center;
    double radius;
    Vec3 color;
    double ambient, diffuse, specular, specularPower;
    double reflectance, transmittance, ior;
  };
  Floor floor;
  Ball mirror, glass;
  Vec3 lightPosition;  ///< A white positional light (intensity 1) here, aimed at the origin, cone 180 degrees.
  Vec3 background;     ///< Background colour (RGB).
  CameraSpec camera;   ///< Eye, focal point, view-up and view angle; clipping range derived from the bounds.
};

/// The classic scene's description (see ClassicSceneDescription).
const ClassicSceneDescription& classicSceneDescription();

/// Whitted's classic scene (classicSceneDescription()) into scene and cam, objects in the order floor, mirror, glass.
/// sphereSubdivisions == 0 gives analytic spheres; > 0 gives UV-sphere meshes with that many rings.
void buildClassicScene(Scene& scene, CameraSpec& cam, int sphereSubdivisions = 0);

/// A UV sphere mesh (theta x phi resolution) with outward normals, as vtkSphereSource builds it.
TriangleMesh makeSphereMesh(const Vec3& center, double radius, int thetaRes, int phiRes);

/// A grid of quads on the plane spanned by (origin, origin+u, origin+v), nu x nv cells, two triangles each,
/// per-triangle colours alternating between c0 and c1 (checkerboard) when given.
TriangleMesh makeGrid(const Vec3& origin, const Vec3& u, const Vec3& v, int nu, int nv, const Color4* c0 = nullptr,
                      const Color4* c1 = nullptr);

/// Adds a volume of n^3 points (a smooth blob with ripples, blue to orange) over the middle of the scene's box.
void addFogVolume(Scene& scene, int n);

/// Names of the built-in scenes and a builder by name (false if unknown). classic-fog: the classic scene with
/// addFogVolume(64).
std::vector<std::string> builtinSceneNames();
bool buildBuiltinScene(const std::string& name, Scene& scene, CameraSpec& cam);

}  // namespace whitted
