// The benchmark's scenes: Whitted's classic scene, VTK wavelet isosurfaces read from .whtmesh files (written by
// gen_wavelet.py), 100k points as spheres, streamline tubes and a glass-and-mirror scene with deep recursion.
//
// Every coordinate is representable in single precision, so Embree (float) and our BVH (double) see exactly the
// same geometry and any disagreement between them comes from the intersection code, not from the input.
#pragma once

#include "scenes/scenes.h"

#include <string>
#include <vector>

namespace whitted::bench {

/// Binary triangle mesh (little endian):
///   char magic[8] = "WHTMESH1"; uint32 vertexCount, triangleCount, flags (bit 0: normals present), reserved;
///   float32 positions[3 * vertexCount]; float32 normals[3 * vertexCount] (if flagged);
///   uint32 indices[3 * triangleCount].
bool readMeshFile(const std::string& path, TriangleMesh& mesh, std::string& error);
bool writeMeshFile(const std::string& path, const TriangleMesh& mesh);

/// A scene plus what the benchmark needs to know about it.
struct BenchScene {
  std::string name;
  Scene scene;
  CameraSpec camera;
  std::string description;
  /// Material of the main actor (for the VTK script and descriptions).
  Material mainMaterial;
  /// Index of the light that sits at the camera looking at the focal point (VTK's headlight), -1 if none. VTK
  /// renderings of the scene make it a headlight: it then follows the camera and, in VTK's shadow-map pass, casts
  /// no shadow map, as it casts no shadow here.
  int headlight = -1;
};

/// Scene names in benchmark order.
std::vector<std::string> benchSceneNames();

/// Builds a named scene. Isosurfaces ("iso60k", "iso1m", "iso4m") are read from wavelet_<size>.whtmesh in the
/// first of dataDirs that holds it. Returns false with a message if the name is unknown or a file is missing.
bool buildBenchScene(const std::string& name, const std::vector<std::string>& dataDirs, BenchScene& out,
                     std::string& error);

/// File name of an isosurface scene's mesh ("" for other scenes).
std::string meshFileFor(const std::string& sceneName);

/// Rounds every position to the nearest float (in place).
void roundToFloat(TriangleMesh& m);

/// Camera that frames bounds as vtkRenderer::ResetCamera does, looking along -dir with the given view-up.
CameraSpec frameBounds(const Bounds3& b, const Vec3& dir, const Vec3& up, double viewAngle, double zoom = 1.0);

}  // namespace whitted::bench
