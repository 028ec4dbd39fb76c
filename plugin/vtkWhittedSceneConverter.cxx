#include "vtkWhittedSceneConverter.h"

#include "vtkWhittedActorPieces.h"
#include "vtkWhittedEnvironment.h"
#include "vtkWhittedGeometryCache.h"
#include "vtkWhittedGlyphConverter.h"
#include "vtkWhittedInstanceSlots.h"
#include "vtkWhittedLights.h"
#include "vtkWhittedMaterialKeys.h"
#include "vtkWhittedMaterials.h"
#include "vtkWhittedMatrix.h"
#include "vtkWhittedTextureCache.h"
#include "vtkWhittedVolumeConverter.h"
#include "vtkWhittedWarnings.h"

#include "vtkActor.h"
#include "vtkAssembly.h"
#include "vtkAssemblyNode.h"
#include "vtkAssemblyPath.h"
#include "vtkDataSetMapper.h"
#include "vtkGlyph3DMapper.h"
#include "vtkInformation.h"
#include "vtkInformationDoubleVectorKey.h"
#include "vtkInformationObjectBaseKey.h"
#include "vtkInformationStringKey.h"
#include "vtkMatrix4x4.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointGaussianMapper.h"
#include "vtkPolyDataMapper.h"
#include "vtkPropCollection.h"
#include "vtkProperty.h"
#include "vtkRenderer.h"
#include "vtkSkybox.h"
#include "vtkVolume.h"

#include "scene/scene.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_set>
#include <utility>

namespace
{
using vtkWhittedActorPieces::Piece;
using whitted::Mat4;
using whitted::Vec3;

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

// A leaf actor found in this frame's props, with its world matrix (null: the actor's own).
struct Leaf
{
  vtkActor* Actor;
  vtkMatrix4x4* Matrix;
  int Occurrence;
};

} // namespace

//------------------------------------------------------------------------------
struct vtkWhittedSceneConverter::Internals
{
  whitted::Scene Scene;
  vtkWhittedTextureCache Textures{ Scene };
  vtkWhittedGeometryCache Geometries{ Scene, Textures };
  vtkWhittedInstanceSlots Slots{ Scene };
  vtkWhittedWarnings Warnings;
  vtkWhittedGlyphConverter Glyphs{ Scene, Geometries, Textures, Slots, Warnings };
  vtkWhittedVolumeConverter Volumes{ Scene };
  bool LightsOn = true;
  bool BrightestLightShadowsOnly = false; // vtkWhittedPass ShadowsFromBrightestLightOnly

  void Clear()
  {
    this->Scene = whitted::Scene();
    this->Textures.Clear();
    this->Geometries.Clear();
    this->Slots.Clear();
    this->Glyphs.Clear();
    this->Volumes.Clear();
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
    if (!vtkWhittedActorPieces::Collect(actor, this->Geometries, pieces))
    {
      return true; // nothing to draw
    }
    if (vtkWhittedActorPieces::OnlyPlainPointsOrLines(pieces, p, mapper))
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
      radiusScale = radiusScale < 0.0 ? vtkWhittedActorPieces::RadiusScale(pieces) : radiusScale;
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
          this->Slots.Place({ actor, leaf.Occurrence, static_cast<int>(i), k },
            static_cast<uint32_t>(g.Objects[k]), placed, front, hasBack ? &back : nullptr);
        }
      }
    }
    return true;
  }

  //----------------------------------------------------------------------------
  // A glyph actor (vtkWhittedGlyphConverter); false if OpenGL has to draw it.
  bool ConvertGlyphs(const Leaf& leaf, vtkGlyph3DMapper* mapper, int& converted)
  {
    vtkWhittedGlyphConverter::Input input;
    const vtkWhittedGlyphConverter::Verdict verdict =
      this->Glyphs.Collect(leaf.Actor, mapper, input);
    if (verdict != vtkWhittedGlyphConverter::Trace)
    {
      return verdict == vtkWhittedGlyphConverter::Nothing;
    }
    Mat4 matrix;
    if (this->DrawsNothing(leaf.Actor) || !this->TraceableMatrix(leaf, matrix))
    {
      return true;
    }
    this->Glyphs.Convert(leaf.Actor, leaf.Occurrence, input, matrix, GeometryOptions(leaf.Actor),
      this->LightsOn, converted);
    return true;
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
void vtkWhittedSceneConverter::SetShadowsFromBrightestLightOnly(bool on)
{
  this->Impl->BrightestLightShadowsOnly = on;
}

//------------------------------------------------------------------------------
void vtkWhittedSceneConverter::Update(
  vtkRenderer* ren, vtkProp** props, int count, vtkObject* owner, Result& result)
{
  Internals& in = *this->Impl;
  in.Warnings.SetOwner(owner);
  result = Result();
  in.Textures.BeginFrame();
  in.Geometries.BeginFrame();
  in.Slots.BeginFrame();
  in.Glyphs.BeginFrame();
  in.Volumes.BeginFrame();

  // Lights
  const vtkWhittedLights::Summary lights = vtkWhittedLights::Convert(ren, in.Scene.lights(), in.BrightestLightShadowsOnly);
  result.HeadlightShading = lights.HeadlightShading;
  in.Scene.volumeAmbient = lights.VolumeAmbient;
  in.Scene.volumeLightsAlongRays = lights.VolumeLightsAlongRays;
  in.LightsOn = lights.LightsOn;

  // What to trace; of the render state's props, those the tracer does not draw go to OpenGL
  vtkSkybox* skybox = nullptr;
  const std::vector<Leaf> leaves = in.CollectLeaves(ren, skybox);
  // Volumes: every visible one of the renderer (also those culled from the render state)
  std::unordered_set<vtkProp*> volumesNotForOpenGL;
  vtkPropCollection* viewProps = ren->GetViewProps();
  vtkCollectionSimpleIterator vit;
  viewProps->InitTraversal(vit);
  while (vtkProp* prop = viewProps->GetNextProp(vit))
  {
    auto* volume = vtkVolume::SafeDownCast(prop);
    if (volume && volume->GetVisibility() &&
      in.Volumes.Convert(volume, in.Warnings, result.VolumesConverted,
        result.VolumeTransferUpdates) != vtkWhittedVolumeConverter::OpenGL)
    {
      volumesNotForOpenGL.insert(volume);
      ++result.TracedVolumes;
    }
  }
  for (int i = 0; i < count; ++i)
  {
    vtkProp* prop = props[i];
    vtkActor* actor = vtkActor::SafeDownCast(prop);
    if (vtkSkybox::SafeDownCast(prop))
    {
      result.BackgroundProps.push_back(prop); // drawn by OpenGL behind the traced image
    }
    else if (prop && !vtkAssembly::SafeDownCast(prop) && !(actor && IsTraceable(actor)) &&
      !volumesNotForOpenGL.count(prop))
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
  in.Slots.FreeUnused();
  in.Glyphs.FreeUnused();
  in.Volumes.FreeUnused();
  in.Geometries.FreeUnused();
  in.Textures.FreeUnused();
  const vtkWhittedGeometryCache::TimeCacheCounts kept = in.Geometries.GetTimeCacheCounts();
  result.TimeCacheHits = kept.Hits;
  result.TimeCacheEntries = kept.Entries;
  result.TimeCacheBytes = kept.Bytes;
}
