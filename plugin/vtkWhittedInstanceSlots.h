/**
 * @class   vtkWhittedInstanceSlots
 * @brief   internal: the instances and materials the conversion holds in a whitted::Scene
 *
 * Private to the Whitted module. The only place where the conversion adds instances (and the
 * materials they use) to the scene. The scene never removes any: an instance no longer needed is
 * hidden and its slot reused by the next one, so a scene that changes from frame to frame grows
 * only to its largest size. Two users:
 *
 * - Actor pieces (vtkWhittedSceneConverter): one instance per (leaf actor, occurrence in
 *   assemblies, block, primitive kind), with a material of its own and, when the back faces look
 *   different, a back material. Place() puts it every frame (object and transform are set only
 *   when they changed); FreeUnused() hides those not placed since BeginFrame(). A freed slot keeps
 *   its instance and material together for the next actor piece.
 * - Glyphs (vtkWhittedGlyphConverter): many instances sharing one material, taken with
 *   AddInstance() / AddMaterial() and given back with RemoveInstance() / RemoveMaterial(); they
 *   are reused by glyphs only.
 *
 * @sa vtkWhittedSceneConverter vtkWhittedGlyphConverter
 */

#ifndef vtkWhittedInstanceSlots_h
#define vtkWhittedInstanceSlots_h

#include "util/math.h" // for whitted::Mat4

#include <cstdint> // for uint32_t
#include <map>     // for std::map
#include <vector>  // for std::vector

class vtkProp;

namespace whitted
{
class Scene;
struct Material;
}

class vtkWhittedInstanceSlots
{
public:
  explicit vtkWhittedInstanceSlots(whitted::Scene& scene);

  /// An actor piece's instance: which leaf actor (and which of its occurrences in assemblies),
  /// which block of its input, which primitive kind (vtkWhittedGeometryCache::Kind).
  struct Key
  {
    vtkProp* Leaf;
    int Occurrence;
    int Piece;
    int Kind;
    bool operator<(const Key& o) const;
  };

  /// Starts a frame: the actor pieces not placed from here to FreeUnused() are hidden then.
  void BeginFrame();

  /**
   * Places the instance of key: object with matrix (object -> world coordinates) and front, and
   * back as the material of the back faces (null: the front's). Its slot from the last frame, a
   * freed one, or a new one.
   */
  void Place(const Key& key, uint32_t object, const whitted::Mat4& matrix,
    const whitted::Material& front, const whitted::Material* back);

  /// Hides the actor pieces not placed since BeginFrame(); their slots are reused by later ones.
  void FreeUnused();

  /// A visible glyph instance of object with matrix and material: a freed one or a new one.
  uint32_t AddInstance(uint32_t object, const whitted::Mat4& matrix, uint32_t material);

  /// Hides a glyph instance; AddInstance() reuses it.
  void RemoveInstance(uint32_t instance);

  /// A material slot for glyphs (a freed one or a new one); the caller sets its contents.
  uint32_t AddMaterial();

  /// Gives back a glyph material slot; AddMaterial() reuses it.
  void RemoveMaterial(uint32_t material);

  /// Forgets every slot (after the scene was replaced by an empty one).
  void Clear();

private:
  struct Slot
  {
    uint32_t Instance = 0;
    uint32_t Material = 0;
    int32_t BackMaterial = -1; ///< Material slot of the back faces, -1 = none yet.
    uint32_t Object = 0;
    whitted::Mat4 Matrix{ 1.0 };
    unsigned long LastFrame = 0;
  };

  /// Hidden instances and unused materials, reused last in, first out.
  struct FreeList
  {
    std::vector<uint32_t> Instances;
    std::vector<uint32_t> Materials;
  };

  // A visible instance of object with matrix and material, from free or new.
  uint32_t TakeInstance(
    FreeList& free, uint32_t object, const whitted::Mat4& matrix, uint32_t material);
  // A material slot holding material, from free or new.
  uint32_t TakeMaterial(std::vector<uint32_t>& free, const whitted::Material& material);
  // The back material of a slot: a material slot of its own that the front names
  // (whitted::Material::backMaterial), kept with the slot and reused.
  void SetBackMaterial(Slot& slot, const whitted::Material* back);

  whitted::Scene& Scene;
  unsigned long Frame = 0;
  std::map<Key, Slot> Slots;
  FreeList FreePieces;                     ///< Instances with their materials, freed together.
  std::vector<uint32_t> FreeBackMaterials; ///< Back materials of freed actor pieces.
  FreeList FreeGlyphs;
};

#endif
// VTK-HeaderTest-Exclude: vtkWhittedInstanceSlots.h
