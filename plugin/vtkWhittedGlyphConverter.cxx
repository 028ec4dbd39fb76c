#include "vtkWhittedGlyphConverter.h"

#include "vtkWhittedActorPieces.h"
#include "vtkWhittedGlyphPlacement.h"
#include "vtkWhittedInstanceSlots.h"
#include "vtkWhittedMaterials.h"
#include "vtkWhittedTextureCache.h"
#include "vtkWhittedWarnings.h"

#include "vtkActor.h"
#include "vtkCellArray.h"
#include "vtkCompositeDataIterator.h"
#include "vtkCompositeDataSet.h"
#include "vtkGlyph3DMapper.h"
#include "vtkNew.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkScalarsToColors.h"
#include "vtkTexture.h"
#include "vtkUnsignedCharArray.h"

#include "scene/scene.h"

#include <algorithm>
#include <array>

using vtkWhittedActorPieces::Piece;
using whitted::Mat4;
using whitted::Vec3;

//------------------------------------------------------------------------------
vtkWhittedGlyphConverter::vtkWhittedGlyphConverter(whitted::Scene& scene,
  vtkWhittedGeometryCache& geometries, vtkWhittedTextureCache& textures,
  vtkWhittedInstanceSlots& slots, vtkWhittedWarnings& warnings)
  : Scene(scene)
  , Geometries(geometries)
  , Textures(textures)
  , Slots(slots)
  , Warnings(warnings)
{
}

vtkWhittedGlyphConverter::~vtkWhittedGlyphConverter() = default;

void vtkWhittedGlyphConverter::BeginFrame()
{
  ++this->Frame;
}

void vtkWhittedGlyphConverter::Clear()
{
  this->Glyphers.clear();
  this->GlyphActors.clear();
}

//------------------------------------------------------------------------------
vtkWhittedGlyphConverter::Helpers& vtkWhittedGlyphConverter::HelpersOf(vtkGlyph3DMapper* mapper)
{
  Helpers& h = this->Glyphers[mapper];
  h.LastFrame = this->Frame;
  if (!h.Shape)
  {
    h.Shape = vtkSmartPointer<vtkPolyDataMapper>::New();
    h.Shape->ScalarVisibilityOff();
    h.Colors = vtkSmartPointer<vtkPolyDataMapper>::New();
    // vtkOpenGLGlyph3DMapper's default glyph: a line from (0,0,0) to (1,0,0)
    h.DefaultSource = vtkSmartPointer<vtkPolyData>::New();
    vtkNew<vtkPoints> points;
    points->InsertNextPoint(0.0, 0.0, 0.0);
    points->InsertNextPoint(1.0, 0.0, 0.0);
    vtkNew<vtkCellArray> lines;
    const vtkIdType ids[2] = { 0, 1 };
    lines->InsertNextCell(2, ids);
    h.DefaultSource->SetPoints(points);
    h.DefaultSource->SetLines(lines);
  }
  return h;
}

//------------------------------------------------------------------------------
vtkWhittedGlyphConverter::Verdict vtkWhittedGlyphConverter::Collect(
  vtkActor* actor, vtkGlyph3DMapper* mapper, Input& input)
{
  if (mapper->GetUseSourceTableTree())
  {
    this->Warnings.Warn(actor, vtkWhittedWarnings::GlyphSourceTableTree);
    return OpenGL;
  }
  if (!mapper->GetStatic())
  {
    mapper->Update();
  }
  input.Mapper = mapper;
  Helpers& helpers = this->HelpersOf(mapper);

  // The sources (VTK's default line when there is none)
  std::vector<vtkPolyData*>& sources = input.Sources;
  for (int i = 0, n = mapper->GetNumberOfInputConnections(1); i < n; ++i)
  {
    vtkPolyData* source = mapper->GetSource(i);
    if (!source)
    {
      return Nothing; // VTK draws nothing when a source is missing
    }
    sources.push_back(source);
  }
  if (sources.empty())
  {
    sources.push_back(helpers.DefaultSource);
  }
  for (vtkPolyData* source : sources)
  {
    if (vtkWhittedActorPieces::OnlyPlainPointsOrLines(
          { Piece{ source, {} } }, actor->GetProperty()))
    {
      return OpenGL;
    }
  }

  // The datasets whose points carry glyphs: the input, or the leaves of a composite input
  std::vector<vtkDataSet*>& blocks = input.Blocks;
  vtkDataObject* data = mapper->GetInputDataObject(0, 0);
  if (auto* composite = vtkCompositeDataSet::SafeDownCast(data))
  {
    auto iter = vtk::TakeSmartPointer(composite->NewIterator());
    for (iter->InitTraversal(); !iter->IsDoneWithTraversal(); iter->GoToNextItem())
    {
      if (auto* ds = vtkDataSet::SafeDownCast(iter->GetCurrentDataObject()))
      {
        blocks.push_back(ds);
      }
    }
  }
  else if (auto* ds = vtkDataSet::SafeDownCast(data))
  {
    blocks.push_back(ds);
  }
  return blocks.empty() ? Nothing : Trace;
}

//------------------------------------------------------------------------------
void vtkWhittedGlyphConverter::Convert(vtkActor* actor, int occurrence, const Input& input,
  const Mat4& matrix, const vtkWhittedPolyDataConverter::Options& options, bool lightsOn,
  int& converted)
{
  vtkGlyph3DMapper* mapper = input.Mapper;
  const std::vector<vtkPolyData*>& sources = input.Sources;
  const std::vector<vtkDataSet*>& blocks = input.Blocks;
  Helpers& helpers = this->HelpersOf(mapper); // made by Collect()

  // Each source's geometry, and whether any changed since the placement was computed
  GlyphActor& glyphs = this->GlyphActors[{ actor, occurrence }];
  glyphs.LastFrame = this->Frame;
  const size_t numberOfSources = sources.size();
  const size_t slots = blocks.size() * numberOfSources;
  bool placementValid = glyphs.Sources.size() == slots;
  for (size_t k = slots; k < glyphs.Sources.size(); ++k)
  {
    this->FreeSource(glyphs.Sources[k]);
  }
  glyphs.Sources.resize(slots);
  const int actorTexture = actor->GetTexture() ? this->Textures.Get(actor->GetTexture()) : -1;
  std::vector<const vtkWhittedGeometryCache::Geometry*> geometries;
  for (size_t s = 0; s < numberOfSources; ++s)
  {
    const std::vector<Piece> piece{ Piece{ sources[s], {} } };
    const vtkWhittedGeometryCache::Geometry& g = this->Geometries.Get(
      helpers.Shape, sources[s], static_cast<int>(s), options,
      [&piece]() { return vtkWhittedActorPieces::RadiusScale(piece); }, converted);
    this->Warnings.WarnProblems(
      actor, actor->GetProperty(), g.Issues, numberOfSources > 1 ? int(s) : -1);
    geometries.push_back(&g);
    for (size_t b = 0; b < blocks.size(); ++b)
    {
      const GlyphSource& gs = glyphs.Sources[b * numberOfSources + s];
      placementValid = placementValid && gs.Origin == g.Origin &&
        std::equal(gs.Objects, gs.Objects + vtkWhittedGeometryCache::NumberOfKinds, g.Objects);
    }
  }

  // Colours: mapped per point by the mapper's settings (one instance colour per glyph)
  vtkMTimeType stamp = mapper->GetMTime();
  if (vtkScalarsToColors* lut = mapper->GetLookupTable())
  {
    stamp = std::max(stamp, lut->GetMTime());
  }
  for (vtkDataSet* ds : blocks)
  {
    stamp = std::max(stamp, ds->GetMTime());
  }
  placementValid = placementValid && glyphs.Stamp == stamp && glyphs.Matrix == matrix;
  bool colored = false;
  for (size_t b = 0; b < blocks.size(); ++b)
  {
    vtkUnsignedCharArray* colors = placementValid
      ? nullptr
      : vtkWhittedGlyphPlacement::MapColors(mapper, helpers.Colors, blocks[b]);
    if (!placementValid)
    {
      this->Place(
        actor, mapper, blocks[b], matrix, geometries, colors, &glyphs.Sources[b * numberOfSources]);
    }
    colored = colored || colors;
  }
  if (!placementValid)
  {
    glyphs.Stamp = stamp;
    glyphs.Matrix = matrix;
    glyphs.Colored = colored;
  }

  // One material per source and block, updated every frame (cheap)
  for (size_t k = 0; k < slots; ++k)
  {
    GlyphSource& gs = glyphs.Sources[k];
    const vtkWhittedGeometryCache::Geometry& g = *geometries[k % numberOfSources];
    const whitted::Material material = vtkWhittedMaterials::Convert(actor, {}, glyphs.Colored,
      actorTexture >= 0 && g.TCoords ? actorTexture : -1, lightsOn, this->Warnings);
    this->Scene.material(static_cast<uint32_t>(gs.Material)) = material;
  }
}

//------------------------------------------------------------------------------
// Instances are reused in place, new ones taken from the freed ones, surplus ones hidden and freed.
void vtkWhittedGlyphConverter::Place(vtkActor* actor, vtkGlyph3DMapper* mapper, vtkDataSet* points,
  const Mat4& matrix, const std::vector<const vtkWhittedGeometryCache::Geometry*>& geometries,
  vtkUnsignedCharArray* colors, GlyphSource* sources)
{
  const int numberOfSources = static_cast<int>(geometries.size());
  constexpr int kinds = vtkWhittedGeometryCache::NumberOfKinds;
  std::vector<std::array<size_t, kinds>> used(geometries.size());
  for (int s = 0; s < numberOfSources; ++s)
  {
    GlyphSource& gs = sources[s];
    if (gs.Material < 0)
    {
      gs.Material = static_cast<int>(this->Slots.AddMaterial());
    }
    for (int k = 0; k < kinds; ++k)
    {
      used[s][k] = 0;
      // A source whose object changed: its reused instances take the new one
      if (gs.Objects[k] != geometries[s]->Objects[k] && geometries[s]->Objects[k] >= 0)
      {
        for (uint32_t id : gs.Instances[k])
        {
          this->Scene.setInstanceObject(id, static_cast<uint32_t>(geometries[s]->Objects[k]));
        }
      }
      gs.Objects[k] = geometries[s]->Objects[k];
    }
    gs.Origin = geometries[s]->Origin;
  }
  const unsigned char* rgba = colors ? colors->GetPointer(0) : nullptr;
  const vtkWhittedGlyphPlacement::Problem problem =
    vtkWhittedGlyphPlacement::ForEachGlyph(mapper, points, numberOfSources,
      [&](int s, vtkIdType point, const Mat4& glyph)
      {
        GlyphSource& gs = sources[s];
        Mat4 placed = matrix * glyph;
        if (gs.Origin != Vec3(0.0))
        {
          placed[3] = placed * whitted::Vec4(gs.Origin, 1.0); // * translate(Origin)
        }
        for (int k = 0; k < kinds; ++k)
        {
          if (gs.Objects[k] < 0)
          {
            continue;
          }
          const uint32_t id = this->Instance(gs, k, used[s][k]++, placed);
          if (rgba)
          {
            const unsigned char* c = rgba + 4 * point;
            this->Scene.setInstanceColor(
              id, whitted::Color4(c[0], c[1], c[2], c[3]) * (1.0f / 255.0f));
          }
          else
          {
            this->Scene.clearInstanceColor(id);
          }
        }
      });
  if (problem != vtkWhittedGlyphPlacement::None)
  {
    this->Warnings.WarnGlyphArrays(actor, problem);
  }
  // Surplus instances of the last placement: hidden, their ids reused later
  for (int s = 0; s < numberOfSources; ++s)
  {
    for (int k = 0; k < kinds; ++k)
    {
      std::vector<uint32_t>& ids = sources[s].Instances[k];
      for (size_t j = used[s][k]; j < ids.size(); ++j)
      {
        this->Slots.RemoveInstance(ids[j]);
      }
      ids.resize(used[s][k]);
    }
  }
}

//------------------------------------------------------------------------------
uint32_t vtkWhittedGlyphConverter::Instance(GlyphSource& gs, int k, size_t j, const Mat4& matrix)
{
  std::vector<uint32_t>& ids = gs.Instances[k];
  if (j < ids.size())
  {
    this->Scene.setInstanceTransform(ids[j], matrix);
    return ids[j];
  }
  ids.push_back(this->Slots.AddInstance(
    static_cast<uint32_t>(gs.Objects[k]), matrix, static_cast<uint32_t>(gs.Material)));
  return ids.back();
}

//------------------------------------------------------------------------------
void vtkWhittedGlyphConverter::FreeSource(GlyphSource& gs)
{
  for (std::vector<uint32_t>& ids : gs.Instances)
  {
    for (uint32_t id : ids)
    {
      this->Slots.RemoveInstance(id);
    }
    ids.clear();
  }
  if (gs.Material >= 0)
  {
    this->Slots.RemoveMaterial(static_cast<uint32_t>(gs.Material));
    gs.Material = -1;
  }
}

//------------------------------------------------------------------------------
void vtkWhittedGlyphConverter::FreeUnused()
{
  for (auto it = this->GlyphActors.begin(); it != this->GlyphActors.end();)
  {
    if (it->second.LastFrame != this->Frame)
    {
      for (GlyphSource& gs : it->second.Sources)
      {
        this->FreeSource(gs);
      }
      it = this->GlyphActors.erase(it);
    }
    else
    {
      ++it;
    }
  }
  for (auto it = this->Glyphers.begin(); it != this->Glyphers.end();)
  {
    it = it->second.LastFrame != this->Frame ? this->Glyphers.erase(it) : std::next(it);
  }
}
