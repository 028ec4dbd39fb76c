#include "vtkWhittedInstanceSlots.h"

#include "scene/scene.h"

#include <tuple>

//------------------------------------------------------------------------------
bool vtkWhittedInstanceSlots::Key::operator<(const Key& o) const
{
  return std::tie(this->Leaf, this->Occurrence, this->Piece, this->Kind) <
    std::tie(o.Leaf, o.Occurrence, o.Piece, o.Kind);
}

//------------------------------------------------------------------------------
vtkWhittedInstanceSlots::vtkWhittedInstanceSlots(whitted::Scene& scene)
  : Scene(scene)
{
}

void vtkWhittedInstanceSlots::BeginFrame()
{
  ++this->Frame;
}

void vtkWhittedInstanceSlots::Clear()
{
  this->Slots.clear();
  this->FreePieces = FreeList();
  this->FreeBackMaterials.clear();
  this->FreeGlyphs = FreeList();
}

//------------------------------------------------------------------------------
uint32_t vtkWhittedInstanceSlots::TakeInstance(
  FreeList& free, uint32_t object, const whitted::Mat4& matrix, uint32_t material)
{
  if (free.Instances.empty())
  {
    return this->Scene.addInstance(object, matrix, material);
  }
  const uint32_t id = free.Instances.back();
  free.Instances.pop_back();
  this->Scene.setInstanceObject(id, object);
  this->Scene.setInstanceTransform(id, matrix);
  this->Scene.setInstanceMaterial(id, material);
  this->Scene.setInstanceVisible(id, true);
  return id;
}

uint32_t vtkWhittedInstanceSlots::TakeMaterial(
  std::vector<uint32_t>& free, const whitted::Material& material)
{
  if (free.empty())
  {
    return this->Scene.addMaterial(material);
  }
  const uint32_t id = free.back();
  free.pop_back();
  this->Scene.material(id) = material;
  return id;
}

//------------------------------------------------------------------------------
void vtkWhittedInstanceSlots::Place(const Key& key, uint32_t object, const whitted::Mat4& matrix,
  const whitted::Material& front, const whitted::Material* back)
{
  auto it = this->Slots.find(key);
  if (it == this->Slots.end())
  {
    // A freed slot (its instance and material together) or a new one
    Slot slot;
    slot.Material = this->TakeMaterial(this->FreePieces.Materials, front);
    slot.Instance = this->TakeInstance(this->FreePieces, object, matrix, slot.Material);
    slot.Object = object;
    slot.Matrix = matrix;
    slot.LastFrame = this->Frame;
    this->SetBackMaterial(slot, back);
    this->Slots.emplace(key, slot);
    return;
  }

  // The slot of the last frame: object and transform set only if they changed
  Slot& slot = it->second;
  slot.LastFrame = this->Frame;
  if (slot.Object != object)
  {
    this->Scene.setInstanceObject(slot.Instance, object);
    slot.Object = object;
  }
  if (slot.Matrix != matrix)
  {
    this->Scene.setInstanceTransform(slot.Instance, matrix);
    slot.Matrix = matrix;
  }
  this->Scene.material(slot.Material) = front;
  this->SetBackMaterial(slot, back);
}

//------------------------------------------------------------------------------
void vtkWhittedInstanceSlots::SetBackMaterial(Slot& slot, const whitted::Material* back)
{
  if (!back)
  {
    this->Scene.material(slot.Material).backMaterial = -1;
    return;
  }
  if (slot.BackMaterial < 0)
  {
    slot.BackMaterial = static_cast<int32_t>(this->TakeMaterial(this->FreeBackMaterials, *back));
  }
  this->Scene.material(static_cast<uint32_t>(slot.BackMaterial)) = *back;
  this->Scene.material(slot.Material).backMaterial = slot.BackMaterial;
}

//------------------------------------------------------------------------------
void vtkWhittedInstanceSlots::FreeUnused()
{
  for (auto it = this->Slots.begin(); it != this->Slots.end();)
  {
    const Slot& slot = it->second;
    if (slot.LastFrame != this->Frame)
    {
      this->Scene.setInstanceVisible(slot.Instance, false);
      this->FreePieces.Instances.push_back(slot.Instance);
      this->FreePieces.Materials.push_back(slot.Material);
      if (slot.BackMaterial >= 0)
      {
        this->FreeBackMaterials.push_back(static_cast<uint32_t>(slot.BackMaterial));
      }
      it = this->Slots.erase(it);
    }
    else
    {
      ++it;
    }
  }
}

//------------------------------------------------------------------------------
uint32_t vtkWhittedInstanceSlots::AddInstance(
  uint32_t object, const whitted::Mat4& matrix, uint32_t material)
{
  return this->TakeInstance(this->FreeGlyphs, object, matrix, material);
}

void vtkWhittedInstanceSlots::RemoveInstance(uint32_t instance)
{
  this->Scene.setInstanceVisible(instance, false);
  this->FreeGlyphs.Instances.push_back(instance);
}

uint32_t vtkWhittedInstanceSlots::AddMaterial()
{
  return this->TakeMaterial(this->FreeGlyphs.Materials, whitted::Material());
}

void vtkWhittedInstanceSlots::RemoveMaterial(uint32_t material)
{
  this->FreeGlyphs.Materials.push_back(material);
}
