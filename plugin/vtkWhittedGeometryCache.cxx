#include "vtkWhittedGeometryCache.h"

#include "vtkWhittedGeometryFingerprint.h"
#include "vtkWhittedGeometryTimeCache.h"
#include "vtkWhittedTextureCache.h"

#include "vtkDataSetSurfaceFilter.h"
#include "vtkInformation.h"
#include "vtkMapper.h"
#include "vtkPolyData.h"
#include "vtkScalarsToColors.h"

#include "scene/scene.h"

#include <algorithm>
#include <iterator>
#include <set>
#include <tuple>
#include <utility>

namespace
{
// Primitives of an object (all of them, valid or not).
std::size_t PrimitiveCount(const whitted::Object& o)
{
  return whitted::visitShape(
    o, [](auto shape, const auto& g) { return decltype(shape)::count(g); });
}
} // namespace

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
  , Kept(new vtkWhittedGeometryTimeCache)
{
}

vtkWhittedGeometryCache::~vtkWhittedGeometryCache() = default;

//------------------------------------------------------------------------------
void vtkWhittedGeometryCache::BeginFrame()
{
  ++this->Frame;
  this->Kept->BeginFrame();
}

//------------------------------------------------------------------------------
void vtkWhittedGeometryCache::SetTimeCacheLimit(std::size_t bytes)
{
  this->Kept->SetLimit(bytes);
}

vtkWhittedGeometryCache::TimeCacheCounts vtkWhittedGeometryCache::GetTimeCacheCounts() const
{
  TimeCacheCounts counts;
  counts.Hits = this->Kept->GetHits();
  counts.Entries = this->Kept->GetNumberOfEntries();
  counts.Bytes = this->Kept->GetBytes();
  return counts;
}

//------------------------------------------------------------------------------
vtkWhittedGeometryCache::Geometry& vtkWhittedGeometryCache::Find(const Key& key, int piece)
{
  auto it = this->Geometries.find(key);
  if (it != this->Geometries.end())
  {
    return it->second;
  }
  // A new input object for the same mapper, piece and options (the next time step): it takes
  // over the previous one's objects, so that moved points refit the BVH
  for (auto old = this->Geometries.begin(); old != this->Geometries.end(); ++old)
  {
    if (old->first.Mapper == key.Mapper && old->first.Options.Tie() == key.Options.Tie() &&
      old->second.Piece == piece && old->second.LastFrame != this->Frame)
    {
      Geometry g = std::move(old->second);
      this->Geometries.erase(old);
      return this->Geometries[key] = std::move(g);
    }
  }
  Geometry& g = this->Geometries[key];
  g.Piece = piece;
  return g;
}

//------------------------------------------------------------------------------
void vtkWhittedGeometryCache::Keep(const Key& key, Geometry& g,
  const vtkWhittedPolyDataConverter::Primitives* next, bool nextHasTime, double nextTime)
{
  if (!g.Fingerprinted || this->Kept->GetLimit() == 0)
  {
    return;
  }
  const vtkWhittedGeometryTimeCache::Key kept{ key.Mapper, key.Options, g.StatePrint,
    g.ContentPrint };
  if (!this->Kept->WorthKeeping(kept, g.HasTime, g.Time, nextHasTime, nextTime))
  {
    g.Fingerprinted = false;
    return;
  }
  vtkWhittedGeometryTimeCache::Entry entry;
  entry.Info = g;
  if (g.ColorCoords && g.ColorTexture >= 0)
  {
    entry.ColorMap = this->Scene.texture(static_cast<uint32_t>(g.ColorTexture));
  }
  const std::size_t nextCounts[NumberOfKinds] = { next ? next->Mesh.triangles.size() : 0,
    next ? next->Spheres.centers.size() : 0, next ? next->Tubes.p0.size() : 0 };
  for (int k = 0; k < NumberOfKinds; ++k)
  {
    if (g.Objects[k] < 0 || !this->Scene.object(static_cast<uint32_t>(g.Objects[k])).alive)
    {
      continue;
    }
    const uint32_t id = static_cast<uint32_t>(g.Objects[k]);
    // A copy when the next contents may refit this object in place, else the object itself
    whitted::Object o =
      next && nextCounts[k] > 0 && nextCounts[k] == PrimitiveCount(this->Scene.object(id))
      ? this->Scene.object(id)
      : this->Scene.takeObject(id);
    entry.Bytes += o.memoryBytes();
    entry.Objects.emplace_back(k, std::move(o));
  }
  if (!entry.Objects.empty())
  {
    this->Kept->Insert(kept, std::move(entry));
  }
  g.Fingerprinted = false;
}

//------------------------------------------------------------------------------
bool vtkWhittedGeometryCache::Restore(const Key& key, Geometry& g, uint64_t statePrint,
  uint64_t contentPrint, bool hasTime, double time)
{
  vtkWhittedGeometryTimeCache::Entry entry;
  if (!this->Kept->Take({ key.Mapper, key.Options, statePrint, contentPrint }, entry))
  {
    return false;
  }
  this->Keep(key, g, nullptr, hasTime, time); // what the geometry holds now may be kept in turn
  if (entry.Info.ColorCoords)
  {
    this->Textures.Store(g.ColorTexture, std::move(entry.ColorMap));
  }
  else
  {
    this->Textures.Free(g.ColorTexture);
  }

  for (int k = 0; k < NumberOfKinds; ++k)
  {
    auto o = std::find_if(entry.Objects.begin(), entry.Objects.end(),
      [k](const std::pair<int, whitted::Object>& e) { return e.first == k; });
    if (o == entry.Objects.end())
    {
      this->FreeObject(g.Objects[k]);
      continue;
    }
    if (auto* mesh = std::get_if<whitted::TriangleMesh>(&o->second.geometry))
    {
      if (entry.Info.ColorCoords)
      {
        mesh->colorMap = g.ColorTexture; // the colour map stored above
      }
    }
    uint32_t id;
    if (g.Objects[k] >= 0)
    {
      id = static_cast<uint32_t>(g.Objects[k]);
    }
    else if (!this->FreeObjects.empty())
    {
      id = this->FreeObjects.back();
      this->FreeObjects.pop_back();
    }
    else
    {
      id = this->Scene.addMesh(whitted::TriangleMesh());
    }
    this->Scene.restoreObject(id, std::move(o->second));
    g.Objects[k] = static_cast<int>(id);
  }
  g.ScalarColors = entry.Info.ScalarColors;
  g.ColorCoords = entry.Info.ColorCoords;
  g.TCoords = entry.Info.TCoords;
  g.Issues = entry.Info.Issues;
  g.Origin = entry.Info.Origin;
  this->Kept->CountHit();
  return true;
}

//------------------------------------------------------------------------------
const vtkWhittedGeometryCache::Geometry& vtkWhittedGeometryCache::Get(vtkMapper* mapper,
  vtkPolyData* poly, int piece, const vtkWhittedPolyDataConverter::Options& options,
  const std::function<double()>& radiusScale, int& converted)
{
  const Key key{ mapper, poly, options };
  Geometry& g = this->Find(key, piece);
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
  if (g.Stamp != 0 && g.Data == poly && g.Stamp == stamp())
  {
    return g;
  }

  // Time cache: the same contents as held (nothing to do), or as kept from an earlier frame
  uint64_t statePrint = 0, contentPrint = 0;
  vtkInformation* dataInfo = poly->GetInformation();
  const bool hasTime = dataInfo && dataInfo->Has(vtkDataObject::DATA_TIME_STEP());
  const double time = hasTime ? dataInfo->Get(vtkDataObject::DATA_TIME_STEP()) : 0.0;
  if (this->Kept->GetLimit() > 0)
  {
    statePrint = vtkWhittedGeometryFingerprint::State(mapper, options, radiusScale);
    contentPrint = vtkWhittedGeometryFingerprint::Content(poly);
    const bool held =
      g.Fingerprinted && g.StatePrint == statePrint && g.ContentPrint == contentPrint;
    if (held || this->Restore(key, g, statePrint, contentPrint, hasTime, time))
    {
      // The time of what is held now (held: the same contents at another time, e.g. a static
      // object in an animation)
      g.Time = time;
      g.HasTime = hasTime;
      g.Fingerprinted = true;
      g.StatePrint = statePrint;
      g.ContentPrint = contentPrint;
      g.Data = poly;
      g.Stamp = stamp();
      return g;
    }
  }

  vtkWhittedPolyDataConverter::Primitives c;
  vtkWhittedPolyDataConverter::Convert(poly, mapper, options, radiusScale, c);
  ++converted;
  this->Keep(key, g, &c, hasTime, time); // the contents held until now, for a later hit

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
  g.Fingerprinted = this->Kept->GetLimit() > 0;
  g.Time = time;
  g.HasTime = hasTime;
  g.StatePrint = statePrint;
  g.ContentPrint = contentPrint;
  g.Data = poly;
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
  // Kept contents go with their mapper
  std::set<vtkMapper*> mappers;
  for (const auto& g : this->Geometries)
  {
    mappers.insert(g.first.Mapper);
  }
  this->Kept->RemoveOtherMappers(mappers);
}

//------------------------------------------------------------------------------
void vtkWhittedGeometryCache::Clear()
{
  this->Geometries.clear();
  this->Surfaces.clear();
  this->FreeObjects.clear();
  this->Kept->Clear();
}
