#include "vtkWhittedTextureCache.h"

#include "vtkWhittedPolyDataConverter.h"

#include "vtkImageData.h"
#include "vtkPointData.h"
#include "vtkScalarsToColors.h"
#include "vtkTexture.h"

#include "scene/scene.h"

#include <algorithm>
#include <utility>

//------------------------------------------------------------------------------
vtkWhittedTextureCache::vtkWhittedTextureCache(whitted::Scene& scene)
  : Scene(scene)
{
}

//------------------------------------------------------------------------------
int vtkWhittedTextureCache::Get(vtkTexture* texture)
{
  texture->Update();
  vtkImageData* image = vtkImageData::SafeDownCast(texture->GetInput());
  if (!image)
  {
    return -1;
  }
  vtkMTimeType stamp = std::max(texture->GetMTime(), image->GetMTime());
  if (texture->GetLookupTable())
  {
    stamp = std::max(stamp, texture->GetLookupTable()->GetMTime());
  }
  Entry& e = this->Textures[texture];
  e.LastFrame = this->Frame;
  if (e.Faces[0] >= 0 && e.Stamp == stamp)
  {
    return e.Faces[0];
  }
  whitted::Texture t =
    vtkWhittedPolyDataConverter::ConvertImage(image, image->GetPointData()->GetScalars(), texture);
  t.repeat = texture->GetRepeat() != 0;
  t.interpolate = texture->GetInterpolate() != 0;
  this->Store(e.Faces[0], std::move(t));
  e.Stamp = stamp;
  return e.Faces[0];
}

//------------------------------------------------------------------------------
bool vtkWhittedTextureCache::GetCubeFaces(vtkTexture* texture, int32_t faces[6])
{
  texture->Update();
  vtkImageData* images[6];
  vtkMTimeType stamp = texture->GetMTime();
  for (int i = 0; i < 6; ++i)
  {
    images[i] = texture->GetNumberOfInputPorts() > i
      ? vtkImageData::SafeDownCast(texture->GetInputDataObject(i, 0))
      : nullptr;
    if (!images[i])
    {
      return false;
    }
    stamp = std::max(stamp, images[i]->GetMTime());
  }
  Entry& e = this->CubeTextures[texture];
  e.LastFrame = this->Frame;
  if (e.Stamp != stamp || e.Faces[0] < 0)
  {
    for (int i = 0; i < 6; ++i)
    {
      whitted::Texture t = vtkWhittedPolyDataConverter::ConvertImage(
        images[i], images[i]->GetPointData()->GetScalars(), texture);
      t.repeat = false;
      t.interpolate = texture->GetInterpolate() != 0;
      this->Store(e.Faces[i], std::move(t));
    }
    e.Stamp = stamp;
  }
  std::copy(e.Faces, e.Faces + 6, faces);
  return std::all_of(faces, faces + 6, [](int32_t f) { return f >= 0; });
}

//------------------------------------------------------------------------------
void vtkWhittedTextureCache::Store(int& id, whitted::Texture texture)
{
  if (texture.width <= 0)
  {
    this->Free(id);
  }
  else if (id >= 0)
  {
    this->Scene.setTexture(static_cast<uint32_t>(id), std::move(texture));
  }
  else
  {
    id = static_cast<int>(this->Scene.addTexture(std::move(texture)));
  }
}

//------------------------------------------------------------------------------
void vtkWhittedTextureCache::Free(int& id)
{
  if (id >= 0)
  {
    this->Scene.removeTexture(static_cast<uint32_t>(id));
    id = -1;
  }
}

//------------------------------------------------------------------------------
void vtkWhittedTextureCache::FreeUnused()
{
  for (auto* cache : { &this->CubeTextures, &this->Textures })
  {
    for (auto it = cache->begin(); it != cache->end();)
    {
      if (it->second.LastFrame != this->Frame)
      {
        for (int& face : it->second.Faces)
        {
          this->Free(face);
        }
        it = cache->erase(it);
      }
      else
      {
        ++it;
      }
    }
  }
}

//------------------------------------------------------------------------------
void vtkWhittedTextureCache::Clear()
{
  this->Textures.clear();
  this->CubeTextures.clear();
}
