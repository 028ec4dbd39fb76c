/**
 * @class   vtkWhittedTextureCache
 * @brief   internal: vtkTextures as scene textures, converted again only when they change
 *
 * Private to the Whitted module. Holds the scene texture of every vtkTexture used in a frame (actor
 * textures, background and environment images, the six faces of cube maps), stamped with the
 * texture's and its image's MTime. An edited texture replaces its texels in place: its id stays
 * the same, so materials and meshes referring to it stay valid and nothing is rebuilt. Textures no
 * frame used since BeginFrame() are freed by FreeUnused() (memory does not grow with edits).
 *
 * @sa vtkWhittedSceneConverter vtkWhittedGeometryCache
 */

#ifndef vtkWhittedTextureCache_h
#define vtkWhittedTextureCache_h

#include "vtkType.h" // for vtkMTimeType

#include <cstdint> // for int32_t
#include <map>     // for std::map

class vtkTexture;

namespace whitted
{
class Scene;
struct Texture;
}

class vtkWhittedTextureCache
{
public:
  explicit vtkWhittedTextureCache(whitted::Scene& scene);

  /// Starts a frame: what is not used from here to FreeUnused() is freed then.
  void BeginFrame() { ++this->Frame; }

  /// Scene texture id of texture's image (input 0), -1 if it has none.
  int Get(vtkTexture* texture);

  /**
   * Scene texture ids of the six faces of a cube-map texture (inputs 0-5: +X, -X, +Y, -Y, +Z, -Z).
   * False (faces undefined) unless all six are images.
   */
  bool GetCubeFaces(vtkTexture* texture, int32_t faces[6]);

  /**
   * Stores texels under id: replaces the texture id names in place, or adds one and sets id, or,
   * for an empty texture, frees id. For textures that are not vtkTextures (colour maps).
   */
  void Store(int& id, whitted::Texture texture);

  /// Frees a scene texture (its id may be reused) and sets id to -1; nothing if id is -1.
  void Free(int& id);

  /// Frees every vtkTexture's scene textures not used since BeginFrame().
  void FreeUnused();

  /// Forgets every texture (after the scene was replaced).
  void Clear();

private:
  struct Entry
  {
    int Faces[6] = { -1, -1, -1, -1, -1, -1 }; // a plain texture uses Faces[0]
    vtkMTimeType Stamp = 0;
    unsigned long LastFrame = 0;
  };
  whitted::Scene& Scene;
  unsigned long Frame = 0;
  std::map<vtkTexture*, Entry> Textures;
  std::map<vtkTexture*, Entry> CubeTextures;
};

#endif
// VTK-HeaderTest-Exclude: vtkWhittedTextureCache.h
