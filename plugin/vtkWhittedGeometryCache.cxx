#include "vtkWhittedGeometryCache.h"

#include "vtkWhittedTextureCache.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDataSetSurfaceFilter.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkMapper.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkScalarsToColors.h"
#include "vtkStringArray.h"

#include "scene/scene.h"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <limits>
#include <set>
#include <string>
#include <tuple>
#include <utility>

namespace
{
//------------------------------------------------------------------------------
// A 64-bit fingerprint of byte ranges and values: four independent multiply-rotate lanes over
// 8-byte words, so hashing runs at memory speed (a 1M-triangle surface's arrays in a few ms).
class Fingerprint
{
public:
  void Add(const void* data, std::size_t bytes)
  {
    const unsigned char* p = static_cast<const unsigned char*>(data);
    std::size_t i = 0;
    for (; i + 32 <= bytes; i += 32)
    {
      for (int l = 0; l < 4; ++l)
      {
        uint64_t w;
        std::memcpy(&w, p + i + 8 * l, 8);
        this->Lanes[l] = Round(this->Lanes[l], w);
      }
    }
    for (; i < bytes; i += 8)
    {
      uint64_t w = 0;
      std::memcpy(&w, p + i, std::min<std::size_t>(8, bytes - i));
      this->Lanes[0] = Round(this->Lanes[0], w);
    }
    this->Length += bytes;
  }
  template <typename T>
  void AddValue(T v)
  {
    this->Add(&v, sizeof v);
  }
  void AddString(const char* s) { this->Add(s ? s : "", s ? std::strlen(s) + 1 : 1); }
  uint64_t Value() const
  {
    uint64_t h = Mix(this->Length);
    for (uint64_t lane : this->Lanes)
    {
      h = Mix(h ^ lane);
    }
    return h;
  }

private:
  static uint64_t Round(uint64_t lane, uint64_t w)
  {
    lane ^= w * 0x9E3779B97F4A7C15ull;
    lane = (lane << 31) | (lane >> 33);
    return lane * 0xC2B2AE3D27D4EB4Full;
  }
  static uint64_t Mix(uint64_t x) // splitmix64's finaliser
  {
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
  }
  uint64_t Lanes[4] = { 1, 2, 3, 4 };
  uint64_t Length = 0;
};

// Type, shape, name and every value of an array.
void AddArray(Fingerprint& f, vtkAbstractArray* a)
{
  if (!a)
  {
    f.AddValue(uint64_t(0));
    return;
  }
  f.AddValue(a->GetDataType());
  f.AddValue(a->GetNumberOfComponents());
  f.AddValue(a->GetNumberOfValues());
  f.AddString(a->GetName());
  auto* data = vtkDataArray::SafeDownCast(a);
  if (data && data->HasStandardMemoryLayout())
  {
    const std::size_t n = static_cast<std::size_t>(data->GetNumberOfValues());
    const std::size_t bytes =
      data->GetDataType() == VTK_BIT ? (n + 7) / 8 : n * data->GetDataTypeSize();
    f.Add(data->GetVoidPointer(0), bytes);
  }
  else if (data)
  {
    std::vector<double> tuple(static_cast<std::size_t>(data->GetNumberOfComponents()));
    for (vtkIdType i = 0; i < data->GetNumberOfTuples(); ++i)
    {
      data->GetTuple(i, tuple.data());
      f.Add(tuple.data(), tuple.size() * sizeof(double));
    }
  }
  else if (auto* strings = vtkStringArray::SafeDownCast(a))
  {
    for (vtkIdType i = 0; i < strings->GetNumberOfValues(); ++i)
    {
      f.AddString(strings->GetValue(i).c_str());
    }
  }
  else
  {
    f.AddValue(a->GetMTime()); // other arrays: any modification counts as a change
  }
}

// The contents of a polydata: points, cells, and every point, cell and field array with the
// attribute designations (which array is the scalars, normals, ...).
uint64_t ContentPrint(vtkPolyData* poly)
{
  Fingerprint f;
  AddArray(f, poly->GetPoints() ? poly->GetPoints()->GetData() : nullptr);
  for (vtkCellArray* cells :
    { poly->GetVerts(), poly->GetLines(), poly->GetPolys(), poly->GetStrips() })
  {
    AddArray(f, cells ? cells->GetOffsetsArray() : nullptr);
    AddArray(f, cells ? cells->GetConnectivityArray() : nullptr);
  }
  for (vtkFieldData* fd : { static_cast<vtkFieldData*>(poly->GetPointData()),
         static_cast<vtkFieldData*>(poly->GetCellData()), poly->GetFieldData() })
  {
    const int n = fd ? fd->GetNumberOfArrays() : 0;
    f.AddValue(n);
    for (int i = 0; i < n; ++i)
    {
      AddArray(f, fd->GetAbstractArray(i));
    }
    if (auto* dsa = vtkDataSetAttributes::SafeDownCast(fd))
    {
      int indices[vtkDataSetAttributes::NUM_ATTRIBUTES];
      dsa->GetAttributeIndices(indices);
      f.Add(indices, sizeof indices);
    }
  }
  return f.Value();
}

// The mapper state a conversion reads (how scalars become colours), and the sphere / tube radius
// scale when the options ask for spheres or tubes.
uint64_t StatePrint(vtkMapper* mapper, const vtkWhittedPolyDataConverter::Options& options,
  const std::function<double()>& radiusScale)
{
  Fingerprint f;
  f.AddString(mapper->GetClassName());
  f.AddValue(mapper->GetScalarVisibility());
  f.AddValue(mapper->GetScalarMode());
  f.AddValue(mapper->GetColorMode());
  f.AddValue(mapper->GetArrayAccessMode());
  f.AddValue(mapper->GetArrayId());
  f.AddString(mapper->GetArrayName());
  f.AddValue(mapper->GetArrayComponent());
  f.AddValue(mapper->GetInterpolateScalarsBeforeMapping());
  f.AddValue(mapper->GetUseLookupTableScalarRange());
  f.AddValue(mapper->GetFieldDataTupleId());
  f.Add(mapper->GetScalarRange(), 2 * sizeof(double));
  if (mapper->GetScalarVisibility())
  {
    vtkScalarsToColors* lut = mapper->GetLookupTable();
    f.AddValue(reinterpret_cast<std::uintptr_t>(lut));
    f.AddValue(lut ? lut->GetMTime() : 0);
  }
  if (options.Spheres || options.Tubes)
  {
    f.AddValue(radiusScale());
  }
  return f.Value();
}

// Whether the machine keeps a tenth of its memory available after `extra` more bytes are used
// (Linux's MemAvailable; true where it cannot be read).
bool MemoryAllows(std::size_t extra)
{
  std::ifstream meminfo("/proc/meminfo");
  std::string name;
  std::size_t kb = 0, total = 0, available = std::numeric_limits<std::size_t>::max();
  while (meminfo >> name >> kb)
  {
    if (name == "MemTotal:")
    {
      total = kb * 1024;
    }
    else if (name == "MemAvailable:")
    {
      available = kb * 1024;
    }
    meminfo.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
  }
  return available == std::numeric_limits<std::size_t>::max() ||
    (available > extra && available - extra >= total / 10);
}

// Primitives of an object (all of them, valid or not).
std::size_t PrimitiveCount(const whitted::Object& o)
{
  return whitted::visitShape(
    o, [](auto shape, const auto& g) { return decltype(shape)::count(g); });
}
} // namespace

//------------------------------------------------------------------------------
// Earlier contents of geometries, by fingerprint, kept outside the scene with their BVHs.
struct vtkWhittedGeometryCache::TimeCache
{
  struct Key
  {
    vtkMapper* Mapper;
    vtkWhittedPolyDataConverter::Options Options;
    uint64_t State, Content;
    bool operator<(const Key& o) const
    {
      return std::make_tuple(this->Mapper, this->Options.Tie(), this->State, this->Content) <
        std::make_tuple(o.Mapper, o.Options.Tie(), o.State, o.Content);
    }
  };
  struct Entry
  {
    std::vector<std::pair<int, whitted::Object>> Objects; // (kind, object)
    Geometry Info; // what the geometry said about these objects (its object ids are unused)
    whitted::Texture ColorMap; // the colour map the mesh's colour coordinates refer to
    std::size_t Bytes = 0;
    unsigned long LastUse = 0;
  };

  std::map<Key, Entry> Entries;
  std::size_t Bytes = 0;
  std::size_t Limit = 0;
  unsigned long Uses = 0;
  int Hits = 0;
  // Fingerprints of contents shown and replaced (not their geometry), by last use: a contents
  // seen here again is a re-shown input, kept the next time it is replaced
  static constexpr std::size_t SeenLimit = 4096;
  std::map<Key, unsigned long> Seen;

  // Notes that the contents of key were shown and replaced; true if they had been before.
  bool SeenBefore(const Key& key)
  {
    auto it = this->Seen.find(key);
    const bool before = it != this->Seen.end();
    this->Seen[key] = ++this->Uses;
    while (this->Seen.size() > SeenLimit)
    {
      auto oldest = this->Seen.begin();
      for (auto s = this->Seen.begin(); s != this->Seen.end(); ++s)
      {
        oldest = s->second < oldest->second ? s : oldest;
      }
      this->Seen.erase(oldest);
    }
    return before;
  }

  void Insert(const Key& key, Entry entry)
  {
    if (entry.Bytes > this->Limit || !MemoryAllows(entry.Bytes))
    {
      return; // dropped: its objects are freed
    }
    entry.LastUse = ++this->Uses;
    this->Bytes += entry.Bytes;
    auto it = this->Entries.find(key);
    if (it != this->Entries.end())
    {
      this->Bytes -= it->second.Bytes;
      it->second = std::move(entry);
    }
    else
    {
      this->Entries.emplace(key, std::move(entry));
    }
    this->Trim();
  }
  // Drops least recently used entries until within the limit (and the machine's memory).
  void Trim()
  {
    while (!this->Entries.empty() && (this->Bytes > this->Limit || !MemoryAllows(0)))
    {
      auto oldest = this->Entries.begin();
      for (auto it = this->Entries.begin(); it != this->Entries.end(); ++it)
      {
        oldest = it->second.LastUse < oldest->second.LastUse ? it : oldest;
      }
      this->Bytes -= oldest->second.Bytes;
      this->Entries.erase(oldest);
    }
  }
};

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
  , Kept(new TimeCache)
{
}

vtkWhittedGeometryCache::~vtkWhittedGeometryCache() = default;

//------------------------------------------------------------------------------
void vtkWhittedGeometryCache::BeginFrame()
{
  ++this->Frame;
  this->Kept->Hits = 0;
}

//------------------------------------------------------------------------------
void vtkWhittedGeometryCache::SetTimeCacheLimit(std::size_t bytes)
{
  this->Kept->Limit = bytes;
  this->Kept->Trim();
}

vtkWhittedGeometryCache::TimeCacheCounts vtkWhittedGeometryCache::GetTimeCacheCounts() const
{
  TimeCacheCounts counts;
  counts.Hits = this->Kept->Hits;
  counts.Entries = static_cast<int>(this->Kept->Entries.size());
  counts.Bytes = this->Kept->Bytes;
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
  if (!g.Fingerprinted || this->Kept->Limit == 0)
  {
    return;
  }
  // Worth keeping: a time step the time moved on from, or contents shown (and replaced) before
  const TimeCache::Key kept{ key.Mapper, key.Options, g.StatePrint, g.ContentPrint };
  const bool reShown = this->Kept->SeenBefore(kept);
  const bool timeStep = g.HasTime && (!nextHasTime || nextTime != g.Time);
  if (!reShown && !timeStep)
  {
    g.Fingerprinted = false;
    return;
  }
  TimeCache::Entry entry;
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
  TimeCache& tc = *this->Kept;
  auto it = tc.Entries.find(TimeCache::Key{ key.Mapper, key.Options, statePrint, contentPrint });
  if (it == tc.Entries.end())
  {
    return false;
  }
  TimeCache::Entry entry = std::move(it->second);
  tc.Bytes -= entry.Bytes;
  tc.Entries.erase(it);
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
  ++tc.Hits;
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
  if (this->Kept->Limit > 0)
  {
    statePrint = StatePrint(mapper, options, radiusScale);
    contentPrint = ContentPrint(poly);
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
  vtkWhittedPolyDataConverter::Convert(poly, mapper, options, radiusScale(), c);
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
  g.Fingerprinted = this->Kept->Limit > 0;
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
  TimeCache& tc = *this->Kept;
  for (auto it = tc.Entries.begin(); it != tc.Entries.end();)
  {
    if (mappers.count(it->first.Mapper))
    {
      ++it;
      continue;
    }
    tc.Bytes -= it->second.Bytes;
    it = tc.Entries.erase(it);
  }
  for (auto it = tc.Seen.begin(); it != tc.Seen.end();)
  {
    it = mappers.count(it->first.Mapper) ? std::next(it) : tc.Seen.erase(it);
  }
}

//------------------------------------------------------------------------------
void vtkWhittedGeometryCache::Clear()
{
  this->Geometries.clear();
  this->Surfaces.clear();
  this->FreeObjects.clear();
  this->Kept->Entries.clear();
  this->Kept->Seen.clear();
  this->Kept->Bytes = 0;
}
