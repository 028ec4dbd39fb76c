#include "vtkWhittedSceneConverter.h"

#include "vtkWhittedEnvironment.h"
#include "vtkWhittedGeometryCache.h"
#include "vtkWhittedGlyphConverter.h"
#include "vtkWhittedLights.h"
#include "vtkWhittedMaterialKeys.h"
#include "vtkWhittedMaterials.h"
#include "vtkWhittedMatrix.h"
#include "vtkWhittedTextureCache.h"
#include "vtkWhittedWarnings.h"

#include "vtkActor.h"
#include "vtkAssembly.h"
#include "vtkAssemblyNode.h"
#include "vtkAssemblyPath.h"
#include "vtkBoundingBox.h"
#include "vtkCellArray.h"
#include "vtkCompositeDataDisplayAttributes.h"
#include "vtkCompositeDataIterator.h"
#include "vtkCompositeDataSet.h"
#include "vtkCompositePolyDataMapper2.h"
#include "vtkDataObjectTree.h"
#include "vtkDataObjectTreeIterator.h"
#include "vtkDataSetMapper.h"
#include "vtkGlyph3DMapper.h"
#include "vtkInformation.h"
#include "vtkInformationDoubleVectorKey.h"
#include "vtkInformationObjectBaseKey.h"
#include "vtkInformationStringKey.h"
#include "vtkMatrix4x4.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointGaussianMapper.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkPropCollection.h"
#include "vtkProperty.h"
#include "vtkRenderer.h"
#include "vtkScalarsToColors.h"
#include "vtkSkybox.h"
#include "vtkTexture.h"
#include "vtkUnsignedCharArray.h"

#include "scene/scene.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <tuple>
#include <unordered_set>
#include <utility>

namespace
{
using whitted::Mat4;
using whitted::Vec3;

//------------------------------------------------------------------------------
// A piece of an actor: its polydata, or one visible block of a composite input with its
// display-attribute overrides.
struct Piece
{
  vtkPolyData* Poly = nullptr;
  vtkWhittedMaterials::BlockAttributes Block;
};

void CollectBlocks(vtkDataObject* obj, vtkCompositeDataDisplayAttributes* attrs, bool visible,
  const vtkWhittedMaterials::BlockAttributes& inherited, std::vector<Piece>& out)
{
  if (!obj)
  {
    return;
  }
  vtkWhittedMaterials::BlockAttributes block = inherited;
  if (attrs)
  {
    if (attrs->HasBlockVisibility(obj))
    {
      visible = attrs->GetBlockVisibility(obj);
    }
    if (attrs->HasBlockColor(obj))
    {
      block.HasColor = true;
      attrs->GetBlockColor(obj, block.Color);
    }
    if (attrs->HasBlockOpacity(obj))
    {
      block.HasOpacity = true;
      block.Opacity = attrs->GetBlockOpacity(obj);
    }
  }
  if (auto* tree = vtkDataObjectTree::SafeDownCast(obj))
  {
    auto iter = vtk::TakeSmartPointer(tree->NewTreeIterator());
    iter->VisitOnlyLeavesOff();
    iter->TraverseSubTreeOff();
    iter->SkipEmptyNodesOn();
    for (iter->InitTraversal(); !iter->IsDoneWithTraversal(); iter->GoToNextItem())
    {
      CollectBlocks(iter->GetCurrentDataObject(), attrs, visible, block, out);
    }
  }
  else if (auto* poly = vtkPolyData::SafeDownCast(obj))
  {
    if (visible)
    {
      out.push_back(Piece{ poly, block });
    }
  }
}

//------------------------------------------------------------------------------
// Whether the tracer draws this actor (else VTK's OpenGL path does).
bool IsTraceable(vtkActor* actor)
{
  // A skybox is the environment, not geometry (its mapper holds a stand-in square)
  if (actor->IsA("vtkSkybox"))
  {
    return false;
  }
  vtkMapper* mapper = actor->GetMapper();
  if (!mapper || !actor->GetProperty() ||
    !(vtkPolyDataMapper::SafeDownCast(mapper) || vtkDataSetMapper::SafeDownCast(mapper) ||
      vtkGlyph3DMapper::SafeDownCast(mapper)))
  {
    return false;
  }
  vtkProperty* p = actor->GetProperty();
  const int rep = p->GetRepresentation();
  if (rep == VTK_POINTS && !p->GetRenderPointsAsSpheres())
  {
    return false;
  }
  if (rep == VTK_WIREFRAME && !p->GetRenderLinesAsTubes())
  {
    return false;
  }
  // Point Gaussian with ScaleFactor 0 draws plain points
  auto* gaussian = vtkPointGaussianMapper::SafeDownCast(mapper);
  return !gaussian || gaussian->GetScaleFactor() != 0.0;
}

// Surface actors whose data has only vertices / lines are drawn by OpenGL unless they ask for
// spheres / tubes (Point Gaussian splats are spheres).
bool OnlyPlainPointsOrLines(
  const std::vector<Piece>& pieces, vtkProperty* p, vtkMapper* mapper = nullptr)
{
  if (p->GetRepresentation() != VTK_SURFACE || vtkPointGaussianMapper::SafeDownCast(mapper))
  {
    return false;
  }
  vtkIdType verts = 0, lines = 0, surfaces = 0;
  for (const Piece& piece : pieces)
  {
    verts += piece.Poly->GetNumberOfVerts();
    lines += piece.Poly->GetNumberOfLines();
    surfaces += piece.Poly->GetNumberOfPolys() + piece.Poly->GetNumberOfStrips();
  }
  if (surfaces > 0)
  {
    return false;
  }
  return (lines > 0 && !p->GetRenderLinesAsTubes()) ||
    (lines == 0 && verts > 0 && !p->GetRenderPointsAsSpheres());
}

// Sphere and tube radii as VTK's OSPRay pass chooses them: size * (data diagonal / 1000). The
// diagonal is that of the finite points of all pieces (never the mapper's cell bounds: those read
// points through connectivity that may be invalid).
double RadiusScale(const std::vector<Piece>& pieces)
{
  vtkBoundingBox box;
  for (const Piece& piece : pieces)
  {
    vtkPoints* points = piece.Poly->GetPoints();
    for (vtkIdType i = 0, n = points ? points->GetNumberOfPoints() : 0; i < n; ++i)
    {
      double x[3];
      points->GetPoint(i, x);
      if (std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]))
      {
        box.AddPoint(x);
      }
    }
  }
  const double length = box.IsValid() ? box.GetDiagonalLength() : 0.0;
  return (length > 0.0 && std::isfinite(length) ? length : 1.0) / 1000.0;
}

// The settings that change the primitives of a geometry: the property's, its radius keys, and a
// Point Gaussian mapper's splat settings.
vtkWhittedPolyDataConverter::Options GeometryOptions(vtkActor* actor)
{
  vtkProperty* p = actor->GetProperty();
  vtkWhittedPolyDataConverter::Options opts;
  vtkInformation* info = p->GetInformation();
  auto functionOf = [&opts](vtkObjectBase* o)
  {
    auto* f = vtkPiecewiseFunction::SafeDownCast(o);
    opts.FunctionsTime = std::max(opts.FunctionsTime, f ? f->GetMTime() : 0);
    return f;
  };
  if (info && info->Has(vtkWhittedMaterialKeys::RADIUS_ARRAY()))
  {
    opts.RadiusArray = info->Get(vtkWhittedMaterialKeys::RADIUS_ARRAY());
    opts.RadiusFunction = functionOf(info->Get(vtkWhittedMaterialKeys::RADIUS_FUNCTION()));
  }
  if (auto* gaussian = vtkPointGaussianMapper::SafeDownCast(actor->GetMapper()))
  {
    opts.Gaussian = true;
    opts.RadiusArray = gaussian->GetScaleArray() ? gaussian->GetScaleArray() : "";
    opts.RadiusComponent = gaussian->GetScaleArrayComponent();
    opts.RadiusFunction = functionOf(gaussian->GetScaleFunction());
    opts.RadiusFactor = gaussian->GetScaleFactor();
    opts.OpacityArray = gaussian->GetOpacityArray() ? gaussian->GetOpacityArray() : "";
    opts.OpacityComponent = gaussian->GetOpacityArrayComponent();
    opts.OpacityFunction = functionOf(gaussian->GetScalarOpacityFunction());
  }
  opts.Representation = p->GetRepresentation();
  opts.Flat = p->GetInterpolation() == VTK_FLAT;
  opts.Spheres = p->GetRenderPointsAsSpheres();
  opts.Tubes = p->GetRenderLinesAsTubes();
  opts.PointSize = p->GetPointSize();
  opts.LineWidth = p->GetLineWidth();
  opts.TCoords = actor->GetTexture() != nullptr;
  return opts;
}

// Cache key of an instance: which leaf actor (and which of its occurrences in assemblies), which
// block, which primitive kind.
struct InstanceKey
{
  vtkProp* Leaf;
  int Occurrence;
  int Piece;
  int Kind;
  bool operator<(const InstanceKey& o) const
  {
    return std::tie(this->Leaf, this->Occurrence, this->Piece, this->Kind) <
      std::tie(o.Leaf, o.Occurrence, o.Piece, o.Kind);
  }
};

struct InstanceSlot
{
  uint32_t Instance = 0;
  uint32_t Material = 0;
  int32_t BackMaterial = -1; ///< Material slot of the back faces (BackfaceProperty), -1 = none yet.
  uint32_t Object = 0;
  Mat4 Matrix{ 1.0 };
  unsigned long LastFrame = 0;
};

// A leaf actor found in this frame's props, with its world matrix (null: the actor's own).
struct Leaf
{
  vtkActor* Actor;
  vtkMatrix4x4* Matrix;
  int Occurrence;
};

// Helper mappers of one glyph mapper: its sources are converted without scalar colours (VTK colours
// a glyph by its point, never by its source's scalars) and its colours are mapped by a copy of its
// colour settings; the line VTK draws when the mapper has no source.
struct GlyphHelpers
{
  vtkSmartPointer<vtkPolyDataMapper> Shape;
  vtkSmartPointer<vtkPolyDataMapper> Colors;
  vtkSmartPointer<vtkPolyData> DefaultSource;
  unsigned long LastFrame = 0;
};

// The glyphs of one source in one dataset block of a glyph actor: per primitive kind of the
// source's geometry, its object and one instance per glyph; one material for all of them.
struct GlyphSource
{
  int Objects[vtkWhittedGeometryCache::NumberOfKinds] = { -1, -1, -1 };
  Vec3 Origin{ 0.0 };
  std::vector<uint32_t> Instances[vtkWhittedGeometryCache::NumberOfKinds];
  int Material = -1;
};

// A glyph actor (one occurrence of a leaf): its glyph sources (block-major) and what their
// placement was computed from, so an unchanged actor costs one material update per source.
struct GlyphActor
{
  std::vector<GlyphSource> Sources;
  vtkMTimeType Stamp = 0;
  Mat4 Matrix{ 1.0 };
  bool Colored = false; ///< The glyphs carry colours mapped from scalars.
  unsigned long LastFrame = 0;
};

} // namespace

//------------------------------------------------------------------------------
struct vtkWhittedSceneConverter::Internals
{
  whitted::Scene Scene;
  unsigned long Frame = 0;
  vtkWhittedTextureCache Textures{ Scene };
  vtkWhittedGeometryCache Geometries{ Scene, Textures };
  std::map<InstanceKey, InstanceSlot> Instances;
  std::vector<std::pair<uint32_t, uint32_t>> FreeInstances; // (instance, material)
  std::vector<int32_t> FreeBackMaterials;                   // back-face material slots
  vtkWhittedWarnings Warnings;
  bool LightsOn = true;
  std::map<vtkMapper*, GlyphHelpers> Glyphers;
  std::map<std::pair<vtkProp*, int>, GlyphActor> GlyphActors;
  std::vector<uint32_t> FreeGlyphInstances;
  std::vector<uint32_t> FreeGlyphMaterials;

  void Clear()
  {
    this->Scene = whitted::Scene();
    this->FreeBackMaterials.clear();
    this->Textures.Clear();
    this->Geometries.Clear();
    this->Instances.clear();
    this->FreeInstances.clear();
    this->Glyphers.clear();
    this->GlyphActors.clear();
    this->FreeGlyphInstances.clear();
    this->FreeGlyphMaterials.clear();
  }

  //----------------------------------------------------------------------------
  // The leaf actors to trace: every visible actor of the renderer, also those the frustum culler
  // left out of the render state (they still cast shadows and show in mirrors); assemblies
  // contribute their parts with the concatenated matrices. Also the first visible skybox.
  std::vector<Leaf> CollectLeaves(vtkRenderer* ren, vtkSkybox*& skybox)
  {
    std::vector<Leaf> leaves;
    std::map<vtkProp*, int> seen;
    vtkPropCollection* viewProps = ren->GetViewProps();
    vtkCollectionSimpleIterator pit;
    viewProps->InitTraversal(pit);
    skybox = nullptr;
    while (vtkProp* prop = viewProps->GetNextProp(pit))
    {
      if (!prop->GetVisibility())
      {
        continue;
      }
      if (vtkSkybox* sky = vtkSkybox::SafeDownCast(prop))
      {
        skybox = skybox ? skybox : sky; // the first visible one, like what is drawn first
        continue;
      }
      if (vtkAssembly::SafeDownCast(prop))
      {
        prop->InitPathTraversal();
        while (vtkAssemblyPath* path = prop->GetNextPath())
        {
          vtkAssemblyNode* node = path->GetLastNode();
          vtkActor* actor = vtkActor::SafeDownCast(node ? node->GetViewProp() : nullptr);
          if (!actor || !actor->GetVisibility())
          {
            continue;
          }
          if (!IsTraceable(actor))
          {
            this->Warnings.Warn(actor, vtkWhittedWarnings::UntraceableAssemblyPart);
            continue;
          }
          leaves.push_back(Leaf{ actor, node->GetMatrix(), seen[actor]++ });
        }
        continue;
      }
      vtkActor* actor = vtkActor::SafeDownCast(prop);
      if (actor && IsTraceable(actor))
      {
        leaves.push_back(Leaf{ actor, nullptr, seen[actor]++ });
      }
    }
    return leaves;
  }

  //----------------------------------------------------------------------------
  // The polydata pieces an actor draws, after the same update as vtkPolyDataMapper::Render /
  // vtkDataSetMapper::Render; false if it has no input to draw.
  bool CollectPieces(vtkActor* actor, std::vector<Piece>& pieces)
  {
    vtkMapper* mapper = actor->GetMapper();
    if (!mapper->GetStatic())
    {
      mapper->Update();
    }
    vtkDataObject* input = mapper->GetInputDataObject(0, 0);
    if (!input)
    {
      return false;
    }
    if (vtkDataSetMapper::SafeDownCast(mapper) && !vtkPolyData::SafeDownCast(input))
    {
      // vtkDataSetMapper draws the outer surface of other datasets
      auto* dataset = vtkDataSet::SafeDownCast(input);
      if (!dataset)
      {
        return false;
      }
      input = this->Geometries.GetSurface(mapper, dataset);
    }
    if (auto* poly = vtkPolyData::SafeDownCast(input))
    {
      pieces.push_back(Piece{ poly, {} });
    }
    else
    {
      auto* cpdm = vtkCompositePolyDataMapper2::SafeDownCast(mapper);
      CollectBlocks(
        input, cpdm ? cpdm->GetCompositeDataDisplayAttributes() : nullptr, true, {}, pieces);
    }
    return true;
  }

  //----------------------------------------------------------------------------
  // The actor's world matrix, false (with a warning) if the tracer cannot use it.
  bool TraceableMatrix(const Leaf& leaf, Mat4& matrix)
  {
    vtkActor* actor = leaf.Actor;
    matrix = vtkWhittedToMat4(leaf.Matrix ? leaf.Matrix : actor->GetMatrix());
    for (int c = 0; c < 4; ++c)
    {
      if (!whitted::isFinite(Vec3(matrix[c])) || !std::isfinite(matrix[c][3]))
      {
        this->Warnings.Warn(actor, vtkWhittedWarnings::NonFiniteMatrix);
        return false;
      }
    }
    // The tracer intersects in object space: a matrix without a finite inverse (a zero Scale
    // flattening the actor) cannot be traced
    const whitted::Mat3 linear(matrix);
    const whitted::Mat3 inverse = glm::inverse(linear);
    if (!(std::abs(glm::determinant(linear)) > 0.0) ||
      !(whitted::isFinite(inverse[0]) && whitted::isFinite(inverse[1]) &&
        whitted::isFinite(inverse[2])))
    {
      this->Warnings.Warn(actor, vtkWhittedWarnings::SingularMatrix);
      return false;
    }
    return true;
  }

  //----------------------------------------------------------------------------
  // True if the actor draws nothing of its own: invisible (opacity 0: VTK discards its fragments)
  // without Whitted terms, or the back-face partner of another actor (FaceMaterials).
  bool DrawsNothing(vtkActor* actor)
  {
    vtkProperty* p = actor->GetProperty();
    vtkInformation* info = p->GetInformation();
    const bool whittedKeys = info &&
      (info->Has(vtkWhittedMaterialKeys::REFLECTANCE()) ||
        info->Has(vtkWhittedMaterialKeys::TRANSMITTANCE()));
    if (p->GetOpacity() <= 0.0 && !whittedKeys)
    {
      return true;
    }
    if (this->BackfacePartners.count(actor) && !this->BackfacePartners[actor])
    {
      return true; // its faces are the back material of another actor (FaceMaterials)
    }
    return false;
  }

  //----------------------------------------------------------------------------
  // Converts one leaf actor; false if OpenGL has to draw it.
  bool ConvertActor(const Leaf& leaf, int& converted)
  {
    vtkActor* actor = leaf.Actor;
    vtkMapper* mapper = actor->GetMapper();
    if (auto* glyphMapper = vtkGlyph3DMapper::SafeDownCast(mapper))
    {
      return this->ConvertGlyphs(leaf, glyphMapper, converted);
    }
    vtkProperty* p = actor->GetProperty();
    std::vector<Piece> pieces;
    if (!this->CollectPieces(actor, pieces))
    {
      return true; // nothing to draw
    }
    if (OnlyPlainPointsOrLines(pieces, p, mapper))
    {
      return false;
    }
    if (this->DrawsNothing(actor))
    {
      return true;
    }

    const vtkWhittedPolyDataConverter::Options opts = GeometryOptions(actor);
    // The radius scale is computed only if a piece is converted
    double radiusScale = -1.0;
    auto radiusScaleFn = [&pieces, &radiusScale]()
    {
      radiusScale = radiusScale < 0.0 ? RadiusScale(pieces) : radiusScale;
      return radiusScale;
    };
    const int actorTexture = actor->GetTexture() ? this->Textures.Get(actor->GetTexture()) : -1;
    Mat4 matrix;
    if (!this->TraceableMatrix(leaf, matrix))
    {
      return true;
    }
    for (size_t i = 0; i < pieces.size(); ++i)
    {
      const vtkWhittedGeometryCache::Geometry& g = this->Geometries.Get(
        mapper, pieces[i].Poly, static_cast<int>(i), opts, radiusScaleFn, converted);
      this->Warnings.WarnProblems(actor, p, g.Issues, pieces.size() > 1 ? static_cast<int>(i) : -1);
      const bool scalarColors = g.ScalarColors || g.ColorCoords;
      const int texture = actorTexture >= 0 && g.TCoords ? actorTexture : -1;
      whitted::Material front, back;
      const bool hasBack =
        this->FaceMaterials(actor, pieces[i].Block, scalarColors, texture, front, back);
      Mat4 placed = matrix;
      if (g.Origin != Vec3(0.0))
      {
        placed[3] = matrix * whitted::Vec4(g.Origin, 1.0); // matrix * translate(Origin)
      }
      for (int k = 0; k < vtkWhittedGeometryCache::NumberOfKinds; ++k)
      {
        if (g.Objects[k] >= 0)
        {
          this->PlaceInstance(InstanceKey{ actor, leaf.Occurrence, static_cast<int>(i), k },
            static_cast<uint32_t>(g.Objects[k]), placed, front, hasBack ? &back : nullptr);
        }
      }
    }
    return true;
  }

  //----------------------------------------------------------------------------
  // The helper mappers of a glyph mapper (created on first use).
  GlyphHelpers& Glypher(vtkGlyph3DMapper* mapper)
  {
    GlyphHelpers& h = this->Glyphers[mapper];
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

  //----------------------------------------------------------------------------
  // A glyph actor: each source converted once (cached like any geometry) and each glyph an
  // instance of its source's objects with the glyph's matrix (vtkWhittedGlyphConverter) and its
  // colour as the instance colour, so a million glyphs cost instance records, not geometry, and
  // one material per source. Placement is recomputed only when the mapper, its lookup table, the
  // points, the actor's matrix or a source's objects changed. False if OpenGL has to draw it.
  bool ConvertGlyphs(const Leaf& leaf, vtkGlyph3DMapper* mapper, int& converted)
  {
    vtkActor* actor = leaf.Actor;
    vtkProperty* p = actor->GetProperty();
    if (mapper->GetUseSourceTableTree())
    {
      this->Warnings.Warn(actor, vtkWhittedWarnings::GlyphSourceTableTree);
      return false;
    }
    if (!mapper->GetStatic())
    {
      mapper->Update();
    }
    GlyphHelpers& helpers = this->Glypher(mapper);

    // The sources (VTK's default line when there is none)
    std::vector<vtkPolyData*> sources;
    for (int i = 0, n = mapper->GetNumberOfInputConnections(1); i < n; ++i)
    {
      vtkPolyData* source = mapper->GetSource(i);
      if (!source)
      {
        return true; // VTK draws nothing when a source is missing
      }
      sources.push_back(source);
    }
    if (sources.empty())
    {
      sources.push_back(helpers.DefaultSource);
    }
    for (vtkPolyData* source : sources)
    {
      if (OnlyPlainPointsOrLines({ Piece{ source, {} } }, p))
      {
        return false;
      }
    }

    // The datasets whose points carry glyphs: the input, or the leaves of a composite input
    std::vector<vtkDataSet*> blocks;
    vtkDataObject* input = mapper->GetInputDataObject(0, 0);
    if (auto* composite = vtkCompositeDataSet::SafeDownCast(input))
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
    else if (auto* ds = vtkDataSet::SafeDownCast(input))
    {
      blocks.push_back(ds);
    }
    if (blocks.empty() || this->DrawsNothing(actor))
    {
      return true;
    }
    Mat4 matrix;
    if (!this->TraceableMatrix(leaf, matrix))
    {
      return true;
    }

    // Each source's geometry, and whether any changed since the placement was computed
    GlyphActor& glyphs = this->GlyphActors[{ actor, leaf.Occurrence }];
    glyphs.LastFrame = this->Frame;
    const size_t numberOfSources = sources.size();
    const size_t slots = blocks.size() * numberOfSources;
    bool placementValid = glyphs.Sources.size() == slots;
    for (size_t k = slots; k < glyphs.Sources.size(); ++k)
    {
      this->FreeGlyphSource(glyphs.Sources[k]);
    }
    glyphs.Sources.resize(slots);
    vtkWhittedPolyDataConverter::Options opts = GeometryOptions(actor);
    const int actorTexture = actor->GetTexture() ? this->Textures.Get(actor->GetTexture()) : -1;
    std::vector<const vtkWhittedGeometryCache::Geometry*> geometries;
    for (size_t s = 0; s < numberOfSources; ++s)
    {
      const std::vector<Piece> piece{ Piece{ sources[s], {} } };
      const vtkWhittedGeometryCache::Geometry& g = this->Geometries.Get(helpers.Shape, sources[s],
        static_cast<int>(s), opts, [&piece]() { return RadiusScale(piece); }, converted);
      this->Warnings.WarnProblems(actor, p, g.Issues, numberOfSources > 1 ? int(s) : -1);
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
        : vtkWhittedGlyphConverter::MapColors(mapper, helpers.Colors, blocks[b]);
      if (!placementValid)
      {
        this->PlaceGlyphs(actor, mapper, blocks[b], matrix, geometries, colors,
          &glyphs.Sources[b * numberOfSources]);
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
        actorTexture >= 0 && g.TCoords ? actorTexture : -1, this->LightsOn, this->Warnings);
      this->Scene.material(static_cast<uint32_t>(gs.Material)) = material;
    }
    return true;
  }

  //----------------------------------------------------------------------------
  // Places the glyphs of one dataset block: instance j of a source's object is its j-th glyph
  // (instances reused in place, new ones from the freed pool, surplus ones hidden and freed).
  void PlaceGlyphs(vtkActor* actor, vtkGlyph3DMapper* mapper, vtkDataSet* points,
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
        gs.Material = static_cast<int>(this->AllocateGlyphMaterial());
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
    const vtkWhittedGlyphConverter::Problem problem =
      vtkWhittedGlyphConverter::ForEachGlyph(mapper, points, numberOfSources,
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
            const uint32_t id = this->GlyphInstance(gs, k, used[s][k]++);
            this->Scene.setInstanceTransform(id, placed);
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
    if (problem != vtkWhittedGlyphConverter::None)
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
          this->Scene.setInstanceVisible(ids[j], false);
          this->FreeGlyphInstances.push_back(ids[j]);
        }
        ids.resize(used[s][k]);
      }
    }
  }

  // Instance j of a glyph source's kind k: the one it had, a freed one, or a new one.
  uint32_t GlyphInstance(GlyphSource& gs, int k, size_t j)
  {
    std::vector<uint32_t>& ids = gs.Instances[k];
    if (j < ids.size())
    {
      return ids[j];
    }
    const uint32_t object = static_cast<uint32_t>(gs.Objects[k]);
    const uint32_t material = static_cast<uint32_t>(gs.Material);
    uint32_t id;
    if (!this->FreeGlyphInstances.empty())
    {
      id = this->FreeGlyphInstances.back();
      this->FreeGlyphInstances.pop_back();
      this->Scene.setInstanceObject(id, object);
      this->Scene.setInstanceMaterial(id, material);
      this->Scene.setInstanceVisible(id, true);
    }
    else
    {
      id = this->Scene.addInstance(object, Mat4(1.0), material);
    }
    ids.push_back(id);
    return id;
  }

  uint32_t AllocateGlyphMaterial()
  {
    if (this->FreeGlyphMaterials.empty())
    {
      return this->Scene.addMaterial(whitted::Material());
    }
    const uint32_t id = this->FreeGlyphMaterials.back();
    this->FreeGlyphMaterials.pop_back();
    return id;
  }

  // Hides a glyph source's instances and frees them and its material for reuse.
  void FreeGlyphSource(GlyphSource& gs)
  {
    for (std::vector<uint32_t>& ids : gs.Instances)
    {
      for (uint32_t id : ids)
      {
        this->Scene.setInstanceVisible(id, false);
        this->FreeGlyphInstances.push_back(id);
      }
      ids.clear();
    }
    if (gs.Material >= 0)
    {
      this->FreeGlyphMaterials.push_back(static_cast<uint32_t>(gs.Material));
      gs.Material = -1;
    }
  }

  // Frees the glyph actors and helper mappers this frame did not use.
  void FreeUnusedGlyphs()
  {
    for (auto it = this->GlyphActors.begin(); it != this->GlyphActors.end();)
    {
      if (it->second.LastFrame != this->Frame)
      {
        for (GlyphSource& gs : it->second.Sources)
        {
          this->FreeGlyphSource(gs);
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

  //----------------------------------------------------------------------------
  // Actors that draw another actor's back faces, as ParaView's backface representation does: a
  // second actor culling front faces over the same data as one culling back faces. The pair is
  // traced as one surface whose back material is the second actor's property (two coincident
  // surfaces would hide each other's faces). BackfacePartners maps the front actor to its partner
  // and the partner to null (not traced itself).
  std::map<vtkActor*, vtkActor*> BackfacePartners;

  void MatchBackfacePartners(const std::vector<Leaf>& leaves)
  {
    this->BackfacePartners.clear();
    auto culls = [](vtkActor* a, bool back)
    {
      vtkProperty* p = a->GetProperty();
      return p->GetRepresentation() == VTK_SURFACE && p->GetBackfaceCulling() == (back ? 1 : 0) &&
        p->GetFrontfaceCulling() == (back ? 0 : 1);
    };
    std::map<vtkDataObject*, vtkActor*> frontOnly;
    for (const Leaf& leaf : leaves)
    {
      if (leaf.Matrix == nullptr && culls(leaf.Actor, true))
      {
        frontOnly.emplace(leaf.Actor->GetMapper()->GetInputDataObject(0, 0), leaf.Actor);
      }
    }
    for (const Leaf& leaf : leaves)
    {
      if (leaf.Matrix != nullptr || !culls(leaf.Actor, false))
      {
        continue;
      }
      auto it = frontOnly.find(leaf.Actor->GetMapper()->GetInputDataObject(0, 0));
      if (it != frontOnly.end() && it->first && !this->BackfacePartners.count(it->second) &&
        SameMatrix(leaf.Actor, it->second))
      {
        this->BackfacePartners[it->second] = leaf.Actor;
        this->BackfacePartners[leaf.Actor] = nullptr;
      }
    }
  }

  static bool SameMatrix(vtkActor* a, vtkActor* b)
  {
    vtkMatrix4x4* ma = a->GetMatrix();
    vtkMatrix4x4* mb = b->GetMatrix();
    for (int i = 0; i < 16; ++i)
    {
      if (ma->GetData()[i] != mb->GetData()[i])
      {
        return false;
      }
    }
    return true;
  }

  //----------------------------------------------------------------------------
  // The front and back materials of one actor piece; false if the back faces use the front's.
  // Face culling makes the culled side pass rays unchanged (vtkWhittedMaterials::Culled); the back
  // faces use the BackfaceProperty or, for a ParaView backface pair, the partner's property.
  bool FaceMaterials(vtkActor* actor, const vtkWhittedMaterials::BlockAttributes& block,
    bool scalarColors, int texture, whitted::Material& front, whitted::Material& back)
  {
    vtkProperty* p = actor->GetProperty();
    front = vtkWhittedMaterials::Convert(
      actor, block, scalarColors, texture, this->LightsOn, this->Warnings);
    auto convertBack = [&](vtkProperty* bp, vtkProperty* shader)
    {
      return vtkWhittedMaterials::ConvertBackface(
        actor, bp, shader, block, scalarColors, texture, this->LightsOn, this->Warnings);
    };
    const bool cullBack = p->GetBackfaceCulling(), cullFront = p->GetFrontfaceCulling();
    if (cullBack)
    {
      auto partner = this->BackfacePartners.find(actor);
      back = partner != this->BackfacePartners.end() && partner->second
        ? convertBack(partner->second->GetProperty(), partner->second->GetProperty())
        : vtkWhittedMaterials::Culled();
      if (cullFront)
      {
        front = vtkWhittedMaterials::Culled();
      }
      return true;
    }
    vtkProperty* bp = actor->GetBackfaceProperty();
    if (bp)
    {
      back = convertBack(bp, p);
    }
    if (cullFront)
    {
      if (!bp)
      {
        back = front;
      }
      front = vtkWhittedMaterials::Culled();
    }
    return bp || cullFront;
  }


  //----------------------------------------------------------------------------
  // The instance of one object for one actor piece: its slot from the last frame (transform and
  // object updated only if they changed), a freed slot, or a new one.
  void PlaceInstance(const InstanceKey& key, uint32_t object, const Mat4& matrix,
    const whitted::Material& material, const whitted::Material* back = nullptr)
  {
    auto it = this->Instances.find(key);
    if (it == this->Instances.end())
    {
      InstanceSlot slot;
      if (!this->FreeInstances.empty())
      {
        std::tie(slot.Instance, slot.Material) = this->FreeInstances.back();
        this->FreeInstances.pop_back();
        this->Scene.material(slot.Material) = material;
        this->Scene.setInstanceObject(slot.Instance, object);
        this->Scene.setInstanceTransform(slot.Instance, matrix);
        this->Scene.setInstanceMaterial(slot.Instance, slot.Material);
        this->Scene.setInstanceVisible(slot.Instance, true);
      }
      else
      {
        slot.Material = this->Scene.addMaterial(material);
        slot.Instance = this->Scene.addInstance(object, matrix, slot.Material);
      }
      slot.Object = object;
      slot.Matrix = matrix;
      slot.LastFrame = this->Frame;
      this->SetBackMaterial(slot, back);
      this->Instances.emplace(key, slot);
      return;
    }
    InstanceSlot& slot = it->second;
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
    this->Scene.material(slot.Material) = material;
    this->SetBackMaterial(slot, back);
  }

  //----------------------------------------------------------------------------
  // The back-face material of an instance (its actor's BackfaceProperty, or none): a material slot
  // of its own that the front material names (whitted::Material::backMaterial). Kept with the
  // instance slot and reused.
  void SetBackMaterial(InstanceSlot& slot, const whitted::Material* back)
  {
    if (!back)
    {
      this->Scene.material(slot.Material).backMaterial = -1;
      return;
    }
    if (slot.BackMaterial < 0)
    {
      if (!this->FreeBackMaterials.empty())
      {
        slot.BackMaterial = this->FreeBackMaterials.back();
        this->FreeBackMaterials.pop_back();
      }
      else
      {
        slot.BackMaterial = static_cast<int32_t>(this->Scene.addMaterial(*back));
      }
    }
    this->Scene.material(static_cast<uint32_t>(slot.BackMaterial)) = *back;
    this->Scene.material(slot.Material).backMaterial = slot.BackMaterial;
  }

  // Hides the instances this frame did not place; their slots are reused by later ones.
  void FreeUnusedInstances()
  {
    for (auto it = this->Instances.begin(); it != this->Instances.end();)
    {
      if (it->second.LastFrame != this->Frame)
      {
        this->Scene.setInstanceVisible(it->second.Instance, false);
        this->FreeInstances.emplace_back(it->second.Instance, it->second.Material);
        if (it->second.BackMaterial >= 0)
        {
          this->FreeBackMaterials.push_back(it->second.BackMaterial);
        }
        it = this->Instances.erase(it);
      }
      else
      {
        ++it;
      }
    }
  }
};

//------------------------------------------------------------------------------
vtkWhittedSceneConverter::vtkWhittedSceneConverter()
  : Impl(new Internals)
{
}

vtkWhittedSceneConverter::~vtkWhittedSceneConverter() = default;

whitted::Scene& vtkWhittedSceneConverter::GetScene()
{
  return this->Impl->Scene;
}

void vtkWhittedSceneConverter::Reset()
{
  this->Impl->Clear();
}

void vtkWhittedSceneConverter::SetTimeCacheLimit(std::size_t bytes)
{
  this->Impl->Geometries.SetTimeCacheLimit(bytes);
}

//------------------------------------------------------------------------------
void vtkWhittedSceneConverter::Update(
  vtkRenderer* ren, vtkProp** props, int count, vtkObject* owner, Result& result)
{
  Internals& in = *this->Impl;
  in.Warnings.SetOwner(owner);
  result = Result();
  ++in.Frame;
  in.Textures.BeginFrame();
  in.Geometries.BeginFrame();

  // Lights
  const vtkWhittedLights::Summary lights = vtkWhittedLights::Convert(ren, in.Scene.lights());
  result.HeadlightShading = lights.HeadlightShading;
  in.LightsOn = lights.LightsOn;

  // What to trace; of the render state's props, those the tracer does not draw go to OpenGL
  vtkSkybox* skybox = nullptr;
  const std::vector<Leaf> leaves = in.CollectLeaves(ren, skybox);
  for (int i = 0; i < count; ++i)
  {
    vtkProp* prop = props[i];
    vtkActor* actor = vtkActor::SafeDownCast(prop);
    if (vtkSkybox::SafeDownCast(prop))
    {
      result.BackgroundProps.push_back(prop); // drawn by OpenGL behind the traced image
    }
    else if (prop && !vtkAssembly::SafeDownCast(prop) && !(actor && IsTraceable(actor)))
    {
      result.OpenGLProps.push_back(prop);
    }
  }

  // Background and environment
  vtkWhittedEnvironment::Convert(ren, skybox, in.Textures, in.Warnings, in.Scene);

  // Actors; those found to need OpenGL go to the OpenGL list (if the render state has them)
  const std::unordered_set<vtkProp*> inState(props, props + count);
  in.MatchBackfacePartners(leaves);
  for (const Leaf& leaf : leaves)
  {
    if (in.ConvertActor(leaf, result.GeometriesConverted))
    {
      ++result.TracedActors;
    }
    else if (leaf.Matrix == nullptr && inState.count(leaf.Actor))
    {
      result.OpenGLProps.push_back(leaf.Actor);
    }
  }

  // Retire what this frame did not use
  in.FreeUnusedInstances();
  in.FreeUnusedGlyphs();
  in.Geometries.FreeUnused();
  in.Textures.FreeUnused();
  const vtkWhittedGeometryCache::TimeCacheCounts kept = in.Geometries.GetTimeCacheCounts();
  result.TimeCacheHits = kept.Hits;
  result.TimeCacheEntries = kept.Entries;
  result.TimeCacheBytes = kept.Bytes;
}
