#include "vtkWhittedGeometryCache.h"

#include "vtkWhittedTextureCache.h"

#include "vtkDataSetSurfaceFilter.h"
#include "vtkMapper.h"
#include "vtkPolyData.h"
#include "vtkScalarsToColors.h"

#include "scene.h"

#include <algorithm>
#include <tuple>
#include <utility>

//------------------------------------------------------------------------------
bool vtkWhittedGeometryCache::Key::operator<(const Key& o) const
{
  return std::make_tuple(this->Mapper, this->Data, this->Options.Tie()) <
    std::make_tuple(o.Mapper, o.Data, o.Options.Tie());
}

//------------------------------------------------------------------------------
vtkWhittedGeometryCache::vtkWhittedGeometryCache(
  whitted::Scene& scene, vtkWhittedTextureCache& textures)
  : Scene(scene)
  , Textures(textures)
{
}

//------------------------------------------------------------------------------
const vtkWhittedGeometryCache::Geometry& vtkWhittedGeometryCache::Get(vtkMapper* mapper,
  vtkPolyData* poly, const vtkWhittedPolyDataConverter::Options& options,
  const std::function<double()>& radiusScale, int& converted)
{
  Geometry& g = this->Geometries[Key{ mapper, poly, options }];
  g.LastFrame = this->Frame;
  auto stamp = [&]()
  {
    vtkMTimeType s = std::max(mapper->GetMTime(), poly->GetMTime());
    if (vtkScalarsToColors* lut = mapper->GetLookupTable())
    {
      s = std::max(s, lut->GetMTime());
    }
    return s;
  };
  if (g.Stamp != 0 && g.Stamp == stamp())
  {
    return g;
  }

  vtkWhittedPolyDataConverter::Primitives c;
  vtkWhittedPolyDataConverter::Convert(poly, mapper, options, radiusScale(), c);
  ++converted;

  // The colour map (InterpolateScalarsBeforeMapping) replaces the geometry's previous one in place,
  // so a lookup-table edit changes no id (and the mesh referring to it keeps its BVH)
  if (c.HasColorTexture && c.ColorTexture.width > 0)
  {
    this->Textures.Store(g.ColorTexture, std::move(c.ColorTexture));
    if (!c.Mesh.colorCoords.empty())
    {
      c.Mesh.colorMap = g.ColorTexture;
    }
  }
  else
  {
    this->Textures.Free(g.ColorTexture);
    c.Mesh.colorCoords.clear();
  }
  const bool colorCoords = !c.Mesh.colorCoords.empty();
  const bool has[NumberOfKinds] = { !c.Mesh.triangles.empty(), !c.Spheres.centers.empty(),
    !c.Tubes.p0.empty() };
  for (int k = 0; k < NumberOfKinds; ++k)
  {
    if (has[k])
    {
      g.Objects[k] = static_cast<int>(this->StoreObject(g.Objects[k], k, c));
    }
    else
    {
      this->FreeObject(g.Objects[k]);
    }
  }
  g.ScalarColors = c.ScalarColors;
  g.ColorCoords = colorCoords;
  g.TCoords = c.TCoords;
  g.Issues = c.Issues;
  g.Origin = c.Origin;
  // Mapping scalars may have created a lookup table or touched the mapper: stamp afterwards
  g.Stamp = stamp();
  return g;
}

//------------------------------------------------------------------------------
vtkPolyData* vtkWhittedGeometryCache::GetSurface(vtkMapper* mapper, vtkDataSet* dataset)
{
  Surface& surface = this->Surfaces[mapper];
  if (!surface.Filter)
  {
    surface.Filter = vtkSmartPointer<vtkDataSetSurfaceFilter>::New();
  }
  surface.LastFrame = this->Frame;
  if (surface.Filter->GetInput() != dataset)
  {
    surface.Filter->SetInputData(dataset);
  }
  surface.Filter->Update();
  return surface.Filter->GetOutput();
}

//------------------------------------------------------------------------------
uint32_t vtkWhittedGeometryCache::StoreObject(
  int existing, int kind, vtkWhittedPolyDataConverter::Primitives& c)
{
  whitted::Scene& s = this->Scene;
  if (existing >= 0)
  {
    const uint32_t id = static_cast<uint32_t>(existing);
    switch (kind)
    {
      case Triangles:
        s.updateMesh(id, std::move(c.Mesh));
        break;
      case Spheres:
        s.updateSpheres(id, std::move(c.Spheres));
        break;
      default:
        s.updateTubes(id, std::move(c.Tubes));
        break;
    }
    return id;
  }
  if (this->FreeObjects.empty())
  {
    switch (kind)
    {
      case Triangles:
        return s.addMesh(std::move(c.Mesh));
      case Spheres:
        return s.addSpheres(std::move(c.Spheres));
      default:
        return s.addTubes(std::move(c.Tubes));
    }
  }
  const uint32_t id = this->FreeObjects.back();
  this->FreeObjects.pop_back();
  switch (kind)
  {
    case Triangles:
      s.setMesh(id, std::move(c.Mesh));
      break;
    case Spheres:
      s.setSpheres(id, std::move(c.Spheres));
      break;
    default:
      s.setTubes(id, std::move(c.Tubes));
      break;
  }
  return id;
}

//------------------------------------------------------------------------------
void vtkWhittedGeometryCache::FreeObject(int& id)
{
  if (id >= 0)
  {
    this->Scene.removeObject(static_cast<uint32_t>(id));
    this->FreeObjects.push_back(static_cast<uint32_t>(id));
    id = -1;
  }
}

//------------------------------------------------------------------------------
void vtkWhittedGeometryCache::FreeUnused()
{
  for (auto it = this->Geometries.begin(); it != this->Geometries.end();)
  {
    if (it->second.LastFrame != this->Frame)
    {
      for (int& object : it->second.Objects)
      {
        this->FreeObject(object);
      }
      this->Textures.Free(it->second.ColorTexture);
      it = this->Geometries.erase(it);
    }
    else
    {
      ++it;
    }
  }
  for (auto it = this->Surfaces.begin(); it != this->Surfaces.end();)
  {
    it = it->second.LastFrame != this->Frame ? this->Surfaces.erase(it) : std::next(it);
  }
}

//------------------------------------------------------------------------------
void vtkWhittedGeometryCache::Clear()
{
  this->Geometries.clear();
  this->Surfaces.clear();
  this->FreeObjects.clear();
}
