#include "vtkWhittedSceneConverter.h"

#include "vtkWhittedPass.h"
#include "vtkWhittedPolyDataConverter.h"

#include "vtkActor.h"
#include "vtkAssembly.h"
#include "vtkAssemblyNode.h"
#include "vtkAssemblyPath.h"
#include "vtkCamera.h"
#include "vtkBoundingBox.h"
#include "vtkCompositeDataDisplayAttributes.h"
#include "vtkCompositePolyDataMapper2.h"
#include "vtkDataObjectTree.h"
#include "vtkDataObjectTreeIterator.h"
#include "vtkDataSetMapper.h"
#include "vtkDataSetSurfaceFilter.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationDoubleKey.h"
#include "vtkInformationDoubleVectorKey.h"
#include "vtkLight.h"
#include "vtkLightCollection.h"
#include "vtkMatrix4x4.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkPropCollection.h"
#include "vtkProperty.h"
#include "vtkRenderer.h"
#include "vtkScalarsToColors.h"
#include "vtkSkybox.h"
#include "vtkSmartPointer.h"
#include "vtkTexture.h"
#include "vtkVersionMacros.h"

#include "material.h"
#include "scene.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <string>
#include <tuple>
#include <unordered_set>
#include <utility>

namespace
{
using whitted::Color;
using whitted::Color4;
using whitted::Mat4;
using whitted::Vec2f;
using whitted::Vec3;
using whitted::Vec3f;

enum Kind
{
  KindTriangles = 0,
  KindSpheres = 1,
  KindCapsules = 2,
  KindCount = 3
};

//------------------------------------------------------------------------------
// vtkMatrix4x4 is row-major with column vectors (p' = M p); glm is column-major: element (r, c)
// goes to m[c][r].
Mat4 ToMat4(const vtkMatrix4x4* m)
{
  Mat4 r(1.0);
  if (m)
  {
    for (int row = 0; row < 4; ++row)
    {
      for (int col = 0; col < 4; ++col)
      {
        r[col][row] = m->GetElement(row, col);
      }
    }
  }
  return r;
}

// Cache key of a geometry: what is drawn (mapper and its input or block) and how.
struct GeometryKey
{
  vtkMapper* Mapper;
  vtkDataObject* Data;
  vtkWhittedPolyDataConverter::Options Options;
  bool operator<(const GeometryKey& o) const
  {
    return std::make_tuple(this->Mapper, this->Data, this->Options.Tie()) <
      std::make_tuple(o.Mapper, o.Data, o.Options.Tie());
  }
};

// The converted form of one geometry: up to one object per primitive kind.
struct Geometry
{
  vtkMTimeType Stamp = 0;
  int Objects[KindCount] = { -1, -1, -1 };
  bool ScalarColors = false; // primitives carry colours mapped from scalars
  int ColorTexture = -1;     // InterpolateScalarsBeforeMapping: scene texture of the colour map
  bool TCoords = false;      // the triangles carry texture coordinates
  vtkWhittedPolyDataConverter::Problems Issues; // bad input left out (warned once per actor)
  Vec3 Origin{ 0.0 }; // the objects' coordinates are relative to this point
  unsigned long LastFrame = 0;
};

//------------------------------------------------------------------------------
// A piece of an actor: its polydata, or one visible block of a composite input with its
// display-attribute overrides.
struct Piece
{
  vtkPolyData* Poly = nullptr;
  bool HasColor = false;
  double Color[3] = { 1.0, 1.0, 1.0 };
  bool HasOpacity = false;
  double Opacity = 1.0;
};

void CollectBlocks(vtkDataObject* obj, vtkCompositeDataDisplayAttributes* attrs, bool visible,
  const Piece& inherited, std::vector<Piece>& out)
{
  if (!obj)
  {
    return;
  }
  Piece state = inherited;
  if (attrs)
  {
    if (attrs->HasBlockVisibility(obj))
    {
      visible = attrs->GetBlockVisibility(obj);
    }
    if (attrs->HasBlockColor(obj))
    {
      state.HasColor = true;
      attrs->GetBlockColor(obj, state.Color);
    }
    if (attrs->HasBlockOpacity(obj))
    {
      state.HasOpacity = true;
      state.Opacity = attrs->GetBlockOpacity(obj);
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
      CollectBlocks(iter->GetCurrentDataObject(), attrs, visible, state, out);
    }
  }
  else if (auto* poly = vtkPolyData::SafeDownCast(obj))
  {
    if (visible)
    {
      state.Poly = poly;
      out.push_back(state);
    }
  }
}

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
  uint32_t Object = 0;
  Mat4 Matrix{ 1.0 };
  unsigned long LastFrame = 0;
};

struct TextureEntry
{
  vtkMTimeType Stamp = 0;
  int Id = -1;
  unsigned long LastFrame = 0;
};

// The six faces of a cube-map environment texture
struct CubeEntry
{
  int Faces[6] = { -1, -1, -1, -1, -1, -1 };
  vtkMTimeType Stamp = 0;
  unsigned long LastFrame = 0;
};

// A leaf actor found in this frame's props, with its world matrix.
struct Leaf
{
  vtkActor* Actor;
  vtkMatrix4x4* Matrix;
  int Occurrence;
};

// What whitted::sanitizeMaterial fixed, in words.
std::string SanitizeMessage(uint32_t bits)
{
  static const char* const what[] = { "a colour", "Ambient/Diffuse/Specular", "SpecularPower",
    "Opacity", "REFLECTANCE", "TRANSMITTANCE", "INDEX_OF_REFRACTION", "absorption" };
  std::string msg;
  for (int i = 0; i < 8; ++i)
  {
    if (bits & (1u << i))
    {
      msg += msg.empty() ? "" : ", ";
      msg += what[i];
    }
  }
  return (msg.empty() ? std::string("a material value") : msg) +
    " out of range or not finite: clamped" +
    ((bits & (1u << 6)) ? " (an INDEX_OF_REFRACTION <= 0 or NaN becomes 1)" : "");
}

// Warning bits of input problems (distinct from sanitizeMaterial's bits 0-8 and the 1 << 16..18
// bits of unsupported settings)
enum ProblemBit : uint32_t
{
  BitNonFinitePoints = 1u << 20,
  BitInvalidCells = 1u << 21,
  BitMalformedCells = 1u << 22,
  BitBadNormals = 1u << 23,
  BitShortNormals = 1u << 24,
  BitShortScalars = 1u << 25,
  BitShortTCoords = 1u << 26,
  BitNoSphereRadius = 1u << 27,
  BitNoTubeRadius = 1u << 28,
  BitUnusableColors = 1u << 30
};

// Warning bits of the environment (skybox) props, above every 32-bit bit
constexpr uint64_t BitStereoSkybox = uint64_t(1) << 32;
constexpr uint64_t BitSkyboxCubeFaces = uint64_t(1) << 33;
constexpr uint64_t BitFloorSkybox = uint64_t(1) << 34;

// The problems of one converted geometry, in words, with the bit each is warned under.
std::vector<std::pair<uint32_t, std::string>> ProblemMessages(
  const vtkWhittedPolyDataConverter::Problems& p, vtkProperty* prop)
{
  std::vector<std::pair<uint32_t, std::string>> out;
  const std::string np = std::to_string(p.NumberOfPoints);
  if (p.NonFinitePoints)
  {
    out.emplace_back(BitNonFinitePoints,
      std::to_string(p.NonFinitePoints) + " of " + np +
        " points have NaN or infinite coordinates: the cells using them are not drawn");
  }
  if (p.InvalidCells)
  {
    out.emplace_back(BitInvalidCells,
      std::to_string(p.InvalidCells) + " cells use point ids outside [0, " + np +
        "): they are not drawn");
  }
  if (p.MalformedCellArrays)
  {
    out.emplace_back(BitMalformedCells,
      std::to_string(p.MalformedCellArrays) +
        " cell arrays are malformed (offsets do not match the connectivity): not drawn");
  }
  if (p.BadNormals)
  {
    out.emplace_back(BitBadNormals,
      std::to_string(p.BadNormals) +
        " normals are NaN, infinite or zero-length: the facet normal is used there");
  }
  if (p.ShortNormals)
  {
    out.emplace_back(BitShortNormals,
      "the normals array has fewer tuples than points (cells) or not 3 components: ignored, "
      "facet normals used");
  }
  if (p.ShortScalars)
  {
    out.emplace_back(BitShortScalars,
      "the colour array has fewer tuples than the points (cells) it colours: ignored, the "
      "property colour is used");
  }
  if (p.UnusableColors)
  {
    out.emplace_back(BitUnusableColors,
      "the scalars are used directly as colours but have no 1 to 4 components (or are a char "
      "array): ignored, the property colour is used");
  }
  if (p.ShortTCoords)
  {
    out.emplace_back(BitShortTCoords,
      "the texture coordinates have fewer tuples than points or more than 3 components: the "
      "texture is not applied");
  }
  if (p.NoSphereRadius)
  {
    out.emplace_back(BitNoSphereRadius,
      "PointSize " + std::to_string(prop->GetPointSize()) +
        " gives spheres no positive radius: the points (vertices) are not drawn");
  }
  if (p.NoTubeRadius)
  {
    out.emplace_back(BitNoTubeRadius,
      "LineWidth " + std::to_string(prop->GetLineWidth()) +
        " gives tubes no positive radius: the lines are not drawn");
  }
  return out;
}

} // namespace

//------------------------------------------------------------------------------
struct vtkWhittedSceneConverter::Internals
{
  whitted::Scene Scene;
  unsigned long Frame = 0;

  std::map<GeometryKey, Geometry> Geometries;
  std::map<InstanceKey, InstanceSlot> Instances;
  std::map<vtkTexture*, TextureEntry> Textures;
  std::map<vtkTexture*, CubeEntry> CubeTextures;
  std::vector<uint32_t> FreeObjects;
  std::vector<std::pair<uint32_t, uint32_t>> FreeInstances; // (instance, material)
  std::set<std::pair<vtkProp*, uint64_t>> Warned;

  vtkObject* Owner = nullptr;
  bool LightsOn = true;

  // Surface extraction for vtkDataSetMapper inputs that are not polydata (as that mapper does
  // itself)
  struct Surface
  {
    vtkSmartPointer<vtkDataSetSurfaceFilter> Filter;
    unsigned long LastFrame = 0;
  };
  std::map<vtkMapper*, Surface> Surfaces;

  void Clear()
  {
    this->Scene = whitted::Scene();
    this->Geometries.clear();
    this->Instances.clear();
    this->Textures.clear();
    this->CubeTextures.clear();
    this->FreeObjects.clear();
    this->FreeInstances.clear();
    this->Surfaces.clear();
  }

  void WarnOnce(vtkProp* prop, uint64_t what, const std::string& msg)
  {
    if (this->Warned.insert(std::make_pair(prop, what)).second)
    {
      vtkWarningWithObjectMacro(
        this->Owner, << "Actor " << prop << " (" << prop->GetClassName() << "): " << msg);
    }
  }

  //----------------------------------------------------------------------------
  // Stores converted primitives of one kind in the core scene: in the geometry's existing object
  // (whose BVH is kept when only attributes such as colours changed), a freed one, or a new one.
  uint32_t StoreObject(int existing, int kind, vtkWhittedPolyDataConverter::Primitives& c)
  {
    if (existing >= 0)
    {
      const uint32_t id = static_cast<uint32_t>(existing);
      switch (kind)
      {
        case KindTriangles:
          this->Scene.updateMesh(id, std::move(c.Mesh));
          break;
        case KindSpheres:
          this->Scene.updateSpheres(id, std::move(c.Spheres));
          break;
        default:
          this->Scene.updateCapsules(id, std::move(c.Capsules));
          break;
      }
      return id;
    }
    if (this->FreeObjects.empty())
    {
      switch (kind)
      {
        case KindTriangles:
          return this->Scene.addMesh(std::move(c.Mesh));
        case KindSpheres:
          return this->Scene.addSpheres(std::move(c.Spheres));
        default:
          return this->Scene.addCapsules(std::move(c.Capsules));
      }
    }
    const uint32_t id = this->FreeObjects.back();
    this->FreeObjects.pop_back();
    switch (kind)
    {
      case KindTriangles:
        this->Scene.setMesh(id, std::move(c.Mesh));
        break;
      case KindSpheres:
        this->Scene.setSpheres(id, std::move(c.Spheres));
        break;
      default:
        this->Scene.setCapsules(id, std::move(c.Capsules));
        break;
    }
    return id;
  }

  void FreeObject(int& id)
  {
    if (id >= 0)
    {
      this->Scene.removeObject(static_cast<uint32_t>(id));
      this->FreeObjects.push_back(static_cast<uint32_t>(id));
      id = -1;
    }
  }

  //----------------------------------------------------------------------------
  // Converted geometry of one piece, converted again only if something it depends on changed.
  template <typename RadiusScaleFn>
  Geometry& GetGeometry(vtkMapper* mapper, vtkPolyData* poly,
    const vtkWhittedPolyDataConverter::Options& opts, RadiusScaleFn&& radiusScale, int& converted)
  {
    GeometryKey key{ mapper, poly, opts };
    Geometry& g = this->Geometries[key];
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
    vtkWhittedPolyDataConverter::Convert(poly, mapper, opts, radiusScale(), c);
    ++converted;

    // The colour map (InterpolateScalarsBeforeMapping) replaces the geometry's previous one in
    // place, so a lookup-table edit changes no id (and the mesh referring to it keeps its BVH)
    if (c.HasColorTexture && c.ColorTexture.width > 0)
    {
      this->StoreTexture(g.ColorTexture, std::move(c.ColorTexture));
      // InterpolateScalarsBeforeMapping: the interpolated coordinate is looked up in the colour map
      // before lighting, as VTK's shader does (so highlights are not tinted by the map)
      if (c.Mesh.texcoords.size() == c.Mesh.positions.size())
      {
        c.Mesh.colorCoords.resize(c.Mesh.texcoords.size());
        for (size_t i = 0; i < c.Mesh.texcoords.size(); ++i)
        {
          c.Mesh.colorCoords[i] = c.Mesh.texcoords[i].x;
        }
        c.Mesh.colorMap = g.ColorTexture;
      }
    }
    else
    {
      this->FreeTexture(g.ColorTexture);
    }
    const bool has[KindCount] = { !c.Mesh.triangles.empty(), !c.Spheres.centers.empty(),
      !c.Capsules.p0.empty() };
    for (int k = 0; k < KindCount; ++k)
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
    g.TCoords = c.TCoords;
    g.Issues = c.Issues;
    g.Origin = c.Origin;
    // Mapping scalars may have created a lookup table or touched the mapper: stamp afterwards
    g.Stamp = stamp();
    return g;
  }

  //----------------------------------------------------------------------------
  int GetTexture(vtkTexture* texture)
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
    TextureEntry& e = this->Textures[texture];
    e.LastFrame = this->Frame;
    if (e.Id >= 0 && e.Stamp == stamp)
    {
      return e.Id;
    }
    whitted::Texture t = vtkWhittedPolyDataConverter::ConvertImage(
      image, image->GetPointData()->GetScalars(), texture);
    t.repeat = texture->GetRepeat() != 0;
    t.interpolate = texture->GetInterpolate() != 0;
    this->StoreTexture(e.Id, std::move(t));
    e.Stamp = stamp;
    return e.Id;
  }

  // Stores texels under id: an edited texture replaces its previous texels in place (same id:
  // materials and meshes referring to it stay valid and nothing is rebuilt), a new one gets an id,
  // an empty one frees the id (-1).
  void StoreTexture(int& id, whitted::Texture t)
  {
    if (t.width <= 0)
    {
      this->FreeTexture(id);
    }
    else if (id >= 0)
    {
      this->Scene.setTexture(static_cast<uint32_t>(id), std::move(t));
    }
    else
    {
      id = static_cast<int>(this->Scene.addTexture(std::move(t)));
    }
  }

  // Frees a scene texture (its id may be reused by the next addTexture) and sets id to -1.
  void FreeTexture(int& id)
  {
    if (id >= 0)
    {
      this->Scene.removeTexture(static_cast<uint32_t>(id));
      id = -1;
    }
  }

  //----------------------------------------------------------------------------
  // The six faces of a cube-map texture (inputs 0..5: +X, -X, +Y, -Y, +Z, -Z), converted again
  // when the texture or a face changed
  bool GetCubeTextures(vtkTexture* texture, int32_t faces[6])
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
    CubeEntry& e = this->CubeTextures[texture];
    e.LastFrame = this->Frame;
    if (e.Stamp != stamp || e.Faces[0] < 0)
    {
      for (int i = 0; i < 6; ++i)
      {
        whitted::Texture t = vtkWhittedPolyDataConverter::ConvertImage(
          images[i], images[i]->GetPointData()->GetScalars(), texture);
        t.repeat = false;
        t.interpolate = texture->GetInterpolate() != 0;
        this->StoreTexture(e.Faces[i], std::move(t));
      }
      e.Stamp = stamp;
    }
    std::copy(e.Faces, e.Faces + 6, faces);
    return std::all_of(faces, faces + 6, [](int32_t f) { return f >= 0; });
  }

  //----------------------------------------------------------------------------
  // What reflected and bent rays see (whitted::EnvironmentMap), in VTK's order of precedence: a
  // visible vtkSkybox with a texture (what the user sees around the scene), else the renderer's
  // environment texture (image-based lighting), else its textured (screen-space) background.
  // Without any, the background colour or gradient.
  void ConvertEnvironment(vtkRenderer* ren, vtkSkybox* skybox)
  {
    using Projection = whitted::EnvironmentMap::Projection;
    whitted::EnvironmentMap env;
    auto vec = [](const double* v) { return whitted::Vec3(v[0], v[1], v[2]); };
    auto unit = [](const whitted::Vec3& v, const whitted::Vec3& fallback)
    {
      const double l = glm::length(v);
      return std::isfinite(l) && l > 0.0 ? v / l : fallback;
    };
    vtkTexture* skyTexture = skybox ? skybox->GetTexture() : nullptr;
    if (skyTexture)
    {
      // vtkSkybox's shader: up = floor plane normal, right = FloorRight, front = up x right
      const float* plane = skybox->GetFloorPlane();
      const float* right = skybox->GetFloorRight();
      const whitted::Vec3 up = unit(whitted::Vec3(plane[0], plane[1], plane[2]), { 0, 1, 0 });
      const whitted::Vec3 r = unit(whitted::Vec3(right[0], right[1], right[2]), { 1, 0, 0 });
      const int projection = skybox->GetProjection();
      if (projection == vtkSkybox::Sphere || projection == vtkSkybox::StereoSphere)
      {
        if (projection == vtkSkybox::StereoSphere)
        {
          this->WarnOnce(skybox, BitStereoSkybox,
            "stereo skybox: reflections see the whole image as one equirectangular panorama");
        }
        env.projection = Projection::Sphere;
        env.faces[0] = this->GetTexture(skyTexture);
        env.right = r;
        env.up = up;
        env.front = glm::cross(up, r);
      }
      else if (projection == vtkSkybox::Cube)
      {
        if (this->GetCubeTextures(skyTexture, env.faces))
        {
          env.projection = Projection::Cube;
#if VTK_MAJOR_VERSION > 9 || (VTK_MAJOR_VERSION == 9 && VTK_MINOR_VERSION >= 2)
          // From VTK 9.2 (ParaView 5.11) the cube lookup is (d.right, d.up, d.front)
          env.right = r;
          env.up = up;
          env.front = -glm::cross(up, r);
#endif
        }
        else
        {
          this->WarnOnce(skybox, BitSkyboxCubeFaces,
            "cube-map skybox without six image faces: reflections see the background colour");
        }
      }
      else
      {
        this->WarnOnce(skybox, BitFloorSkybox,
          "floor skybox: reflections see the background colour (only sphere and cube skyboxes "
          "are sampled by direction)");
      }
    }
    else if (vtkTexture* t = ren->GetEnvironmentTexture())
    {
      const whitted::Vec3 up = unit(vec(ren->GetEnvironmentUp()), { 0, 1, 0 });
      const whitted::Vec3 r = unit(vec(ren->GetEnvironmentRight()), { 1, 0, 0 });
      if (t->GetCubeMap())
      {
        if (this->GetCubeTextures(t, env.faces))
        {
          env.projection = Projection::Cube;
          env.right = r;
          env.up = up;
          env.front = -glm::cross(r, up);
        }
      }
      else
      {
        // VTK's equirectangular convention: u = atan2(d.z, d.x) / 2pi + 0.5 in the default frame
        env.projection = Projection::Sphere;
        env.faces[0] = this->GetTexture(t);
        env.right = glm::cross(r, up);
        env.up = up;
        env.front = r;
      }
    }
    else if (ren->GetTexturedBackground() && ren->GetBackgroundTexture())
    {
      env.projection = Projection::Screen;
      env.faces[0] = this->GetTexture(ren->GetBackgroundTexture());
      vtkCamera* cam = ren->GetActiveCamera();
      env.worldToClip =
        ToMat4(cam->GetCompositeProjectionTransformMatrix(ren->GetTiledAspectRatio(), -1, 1));
      double fp[3], pos[3];
      cam->GetFocalPoint(fp);
      cam->GetPosition(pos);
      env.viewDirection = unit(vec(fp) - vec(pos), { 0, 0, -1 });
      // The up vector perpendicular to the view direction
      const whitted::Vec3 up = unit(vec(cam->GetViewUp()), { 0, 1, 0 });
      env.viewUp =
        unit(up - glm::dot(up, env.viewDirection) * env.viewDirection, { 0, 1, 0 });
    }
    if (env.projection != Projection::None && env.faces[0] < 0)
    {
      env.projection = Projection::None; // an empty image: the background colour
    }
    this->Scene.environmentMap = env;
  }

  //----------------------------------------------------------------------------
  whitted::Material MakeMaterial(
    vtkActor* actor, const Piece& piece, const Geometry& g, int actorTexture)
  {
    vtkProperty* p = actor->GetProperty();
    whitted::Material m;
    double c[3];
    p->GetAmbientColor(c);
    m.ambientColor = Color(c[0], c[1], c[2]);
    p->GetDiffuseColor(c);
    m.diffuseColor = Color(c[0], c[1], c[2]);
    p->GetSpecularColor(c);
    m.specularColor = Color(c[0], c[1], c[2]);
    m.ambient = static_cast<float>(p->GetAmbient());
    m.diffuse = static_cast<float>(p->GetDiffuse());
    m.specular = static_cast<float>(p->GetSpecular());
    m.specularPower = static_cast<float>(p->GetSpecularPower());
    m.opacity = static_cast<float>(p->GetOpacity());
    m.lighting = p->GetLighting() && this->LightsOn;
    m.flatShading = p->GetInterpolation() == VTK_FLAT;

    // Block overrides of a composite mapper replace the property's colour and opacity
    if (piece.HasColor)
    {
      m.ambientColor = m.diffuseColor = Color(piece.Color[0], piece.Color[1], piece.Color[2]);
    }
    if (piece.HasOpacity)
    {
      m.opacity = static_cast<float>(piece.Opacity);
    }

    // Scalar colours replace ambient and diffuse colours (VTK 9.1); so do colour-map lookups of
    // interpolated scalars (the mesh carries the coordinates and the map)
    if (g.ScalarColors || (g.ColorTexture >= 0 && g.TCoords))
    {
      m.colorSource = whitted::ColorSource::ScalarsAmbientAndDiffuse;
    }
    if (actorTexture >= 0 && g.TCoords)
    {
      m.texture = actorTexture;
    }

    // Whitted terms from the property's information keys; defaults keep VTK's look
    // (from an Opacity that is in range: a NaN or out-of-range Opacity is one problem, not two)
    const float opacity = std::isfinite(m.opacity) ? std::clamp(m.opacity, 0.0f, 1.0f) : 1.0f;
    m.transmittance = Color(1.0f - opacity);
    m.ior = 1.0f;
    if (vtkInformation* info = p->GetInformation())
    {
      auto readColor = [&](vtkInformationDoubleVectorKey* key, Color& dst)
      {
        if (info->Has(key))
        {
          const int n = info->Length(key);
          const double* v = info->Get(key);
          if (n >= 3)
          {
            dst = Color(v[0], v[1], v[2]);
          }
          else if (n >= 1)
          {
            dst = Color(static_cast<float>(v[0]));
          }
        }
      };
      readColor(vtkWhittedPass::REFLECTANCE(), m.reflectance);
      readColor(vtkWhittedPass::TRANSMITTANCE(), m.transmittance);
      if (info->Has(vtkWhittedPass::INDEX_OF_REFRACTION()))
      {
        m.ior = static_cast<float>(info->Get(vtkWhittedPass::INDEX_OF_REFRACTION()));
      }
    }

    // Largest channel sum of kr + kt as sanitizeMaterial sees it after clamping each to [0,1] (for
    // the energy warning)
    float energy = 0.0f;
    for (int i = 0; i < 3; ++i)
    {
      auto clamp01 = [](float v) { return std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f; };
      energy = std::max(energy, clamp01(m.reflectance[i]) + clamp01(m.transmittance[i]));
    }
    if (const uint32_t fixed = whitted::sanitizeMaterial(m))
    {
      if (const uint32_t clamped = fixed & ~whitted::kMaterialEnergyScaled)
      {
        this->WarnOnce(actor, clamped, SanitizeMessage(clamped));
      }
      if (fixed & whitted::kMaterialEnergyScaled)
      {
        char sum[32];
        std::snprintf(sum, sizeof(sum), "%.4g", energy);
        this->WarnOnce(actor, whitted::kMaterialEnergyScaled,
          std::string("REFLECTANCE + TRANSMITTANCE is above 1 (largest channel sum ") + sum +
            "): both scaled by 1/" + sum +
            " so that sum is 1 (a surface cannot return more light than reaches it)");
      }
    }
    return m;
  }

  //----------------------------------------------------------------------------
  void PlaceInstance(
    const InstanceKey& key, uint32_t object, const Mat4& matrix, const whitted::Material& material)
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
  }

  //----------------------------------------------------------------------------
  // Whether the tracer draws this actor (else VTK's OpenGL path does).
  static bool IsTraceable(vtkActor* actor)
  {
    // A skybox is the environment, not geometry (its mapper holds a stand-in square)
    if (actor->IsA("vtkSkybox"))
    {
      return false;
    }
    vtkMapper* mapper = actor->GetMapper();
    if (!mapper || !actor->GetProperty() ||
      !(vtkPolyDataMapper::SafeDownCast(mapper) || vtkDataSetMapper::SafeDownCast(mapper)))
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
    return true;
  }

  // Surface actors whose data has only vertices / lines are drawn by OpenGL unless they ask for
  // spheres / tubes.
  static bool OnlyPlainPointsOrLines(const std::vector<Piece>& pieces, vtkProperty* p)
  {
    if (p->GetRepresentation() != VTK_SURFACE)
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

  //----------------------------------------------------------------------------
  // Converts one leaf actor; false if OpenGL has to draw it.
  bool ConvertActor(const Leaf& leaf, int& converted)
  {
    vtkActor* actor = leaf.Actor;
    vtkMapper* mapper = actor->GetMapper();
    vtkProperty* p = actor->GetProperty();

    // Same update as vtkPolyDataMapper::Render / vtkDataSetMapper::Render
    if (!mapper->GetStatic())
    {
      mapper->Update();
    }
    vtkDataObject* input = mapper->GetInputDataObject(0, 0);
    if (!input)
    {
      return true; // nothing to draw
    }
    if (vtkDataSetMapper::SafeDownCast(mapper) && !vtkPolyData::SafeDownCast(input))
    {
      // vtkDataSetMapper draws the outer surface of other datasets
      auto* dataset = vtkDataSet::SafeDownCast(input);
      if (!dataset)
      {
        return true;
      }
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
      input = surface.Filter->GetOutput();
    }
    std::vector<Piece> pieces;
    if (auto* poly = vtkPolyData::SafeDownCast(input))
    {
      Piece piece;
      piece.Poly = poly;
      pieces.push_back(piece);
    }
    else
    {
      auto* cpdm = vtkCompositePolyDataMapper2::SafeDownCast(mapper);
      CollectBlocks(
        input, cpdm ? cpdm->GetCompositeDataDisplayAttributes() : nullptr, true, Piece(), pieces);
    }
    if (OnlyPlainPointsOrLines(pieces, p))
    {
      return false;
    }

    // An invisible actor (opacity 0, VTK discards its fragments) unless it has Whitted terms
    vtkInformation* info = p->GetInformation();
    const bool whittedKeys = info &&
      (info->Has(vtkWhittedPass::REFLECTANCE()) || info->Has(vtkWhittedPass::TRANSMITTANCE()));
    if (p->GetOpacity() <= 0.0 && !whittedKeys)
    {
      return true;
    }
    if (p->GetInterpolation() == VTK_PBR)
    {
      this->WarnOnce(actor, 1u << 16, "PBR interpolation is not supported: shaded as Gouraud");
    }
    if (p->GetBackfaceCulling() || p->GetFrontfaceCulling())
    {
      this->WarnOnce(actor, 1u << 17, "face culling is ignored by the ray tracer");
    }

    vtkWhittedPolyDataConverter::Options opts;
    opts.Representation = p->GetRepresentation();
    opts.Flat = p->GetInterpolation() == VTK_FLAT;
    opts.Spheres = p->GetRenderPointsAsSpheres();
    opts.Tubes = p->GetRenderLinesAsTubes();
    opts.PointSize = p->GetPointSize();
    opts.LineWidth = p->GetLineWidth();
    vtkTexture* texture = actor->GetTexture();
    opts.TCoords = texture != nullptr;
    // Sphere and tube radii as VTK's OSPRay pass chooses them: size * (data diagonal / 1000). The
    // diagonal is that of the finite points of all pieces (never the mapper's cell bounds: those
    // read points through connectivity that may be invalid), computed only if a piece is converted.
    double radiusScale = -1.0;
    auto radiusScaleFn = [&pieces, &radiusScale]()
    {
      if (radiusScale < 0.0)
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
        radiusScale = (length > 0.0 && std::isfinite(length) ? length : 1.0) / 1000.0;
      }
      return radiusScale;
    };

    const int actorTexture = texture ? this->GetTexture(texture) : -1;
    const Mat4 matrix = ToMat4(leaf.Matrix ? leaf.Matrix : actor->GetMatrix());
    for (int c = 0; c < 4; ++c)
    {
      if (!whitted::isFinite(Vec3(matrix[c])) || !std::isfinite(matrix[c][3]))
      {
        this->WarnOnce(actor, 1u << 29,
          "its matrix (Position, Orientation, Scale, Origin, UserMatrix) has NaN or infinite "
          "entries: not drawn");
        return true;
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
      this->WarnOnce(actor, 1u << 31,
        "its matrix is singular (e.g. a zero Scale flattening it): the ray tracer cannot draw "
        "it");
      return true;
    }
    for (size_t i = 0; i < pieces.size(); ++i)
    {
      Geometry& g = this->GetGeometry(mapper, pieces[i].Poly, opts, radiusScaleFn, converted);
      for (const auto& problem : ProblemMessages(g.Issues, p))
      {
        this->WarnOnce(actor, problem.first,
          pieces.size() > 1 ? "block " + std::to_string(i) + ": " + problem.second
                            : problem.second);
      }
      const whitted::Material material = this->MakeMaterial(actor, pieces[i], g, actorTexture);
      Mat4 placed = matrix;
      if (g.Origin != Vec3(0.0))
      {
        placed[3] = matrix * whitted::Vec4(g.Origin, 1.0); // matrix * translate(Origin)
      }
      for (int k = 0; k < KindCount; ++k)
      {
        if (g.Objects[k] >= 0)
        {
          this->PlaceInstance(InstanceKey{ actor, leaf.Occurrence, static_cast<int>(i), k },
            static_cast<uint32_t>(g.Objects[k]), placed, material);
        }
      }
    }
    return true;
  }

  //----------------------------------------------------------------------------
  // Lights in world coordinates and VTK's light complexity (vtkOpenGLRenderer::UpdateLights).
  bool ConvertLights(vtkRenderer* ren)
  {
    std::vector<whitted::Light>& lights = this->Scene.lights();
    lights.clear();
    int count = 0;
    int complexity = 0;
    vtkLightCollection* lc = ren->GetLights();
    vtkCollectionSimpleIterator sit;
    lc->InitTraversal(sit);
    while (vtkLight* light = lc->GetNextLight(sit))
    {
      const double status = light->GetSwitch();
      if (status > 0.0)
      {
        ++count;
        if (complexity == 0)
        {
          complexity = 1;
        }
      }
      if (complexity == 1 && (count > 1 || light->GetLightType() != VTK_LIGHT_TYPE_HEADLIGHT))
      {
        complexity = 2;
      }
      if (complexity < 3 && light->GetPositional())
      {
        complexity = 3;
      }
      if (status <= 0.0)
      {
        continue;
      }
      whitted::Light l;
      double v[3];
      light->GetTransformedPosition(v);
      l.position = Vec3(v[0], v[1], v[2]);
      light->GetTransformedFocalPoint(v);
      l.focalPoint = Vec3(v[0], v[1], v[2]);
      light->GetDiffuseColor(v);
      l.color = Color(v[0], v[1], v[2]);
      l.intensity = static_cast<float>(light->GetIntensity());
      l.positional = light->GetPositional() != 0;
      light->GetAttenuationValues(v);
      l.attenuation = Vec3(v[0], v[1], v[2]);
      l.coneAngle = light->GetConeAngle();
      l.exponent = light->GetExponent();
      l.castShadows = light->GetShadowAttenuation() > 0.0f;
      lights.push_back(l);
    }
    this->LightsOn = count > 0;
    return complexity == 1;
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

//------------------------------------------------------------------------------
void vtkWhittedSceneConverter::Update(
  vtkRenderer* ren, vtkProp** props, int count, vtkObject* owner, Result& result)
{
  Internals& in = *this->Impl;
  in.Owner = owner;
  result = Result();

  ++in.Frame;

  // Lights and background
  result.HeadlightShading = in.ConvertLights(ren);
  double c[3];
  ren->GetBackground(c);
  in.Scene.background = Color(c[0], c[1], c[2]);
  ren->GetBackground2(c);
  in.Scene.background2 = Color(c[0], c[1], c[2]);
  in.Scene.gradientBackground = ren->GetGradientBackground();
  // Misses are written with alpha 0 and not composited: what VTK cleared (background, gradient,
  // lower layers, transparent compositing background) stays
  in.Scene.backgroundAlpha = 0.0f;

  // Traced: every visible actor of the renderer, also those the frustum culler left out of the
  // render state (they still cast shadows and show in mirrors); assemblies contribute their parts
  // with the concatenated matrices. OpenGL: the render state's props that the tracer does not draw.
  std::vector<Leaf> leaves;
  std::map<vtkProp*, int> seen;
  std::unordered_set<vtkProp*> inState(props, props + count);
  vtkPropCollection* viewProps = ren->GetViewProps();
  vtkCollectionSimpleIterator pit;
  viewProps->InitTraversal(pit);
  vtkSkybox* skybox = nullptr;
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
        if (!Internals::IsTraceable(actor))
        {
          in.WarnOnce(actor, 1u << 18,
            "part of an assembly that the ray tracer cannot draw (not a surface polydata actor): "
            "skipped");
          continue;
        }
        leaves.push_back(Leaf{ actor, node->GetMatrix(), seen[actor]++ });
      }
      continue;
    }
    vtkActor* actor = vtkActor::SafeDownCast(prop);
    if (actor && Internals::IsTraceable(actor))
    {
      leaves.push_back(Leaf{ actor, nullptr, seen[actor]++ });
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
    else if (prop && !vtkAssembly::SafeDownCast(prop) &&
      !(actor && Internals::IsTraceable(actor)))
    {
      result.OpenGLProps.push_back(prop);
    }
  }
  in.ConvertEnvironment(ren, skybox);

  // Convert; actors found to need OpenGL go to the OpenGL list (if the render state has them)
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
  for (auto it = in.Instances.begin(); it != in.Instances.end();)
  {
    if (it->second.LastFrame != in.Frame)
    {
      in.Scene.setInstanceVisible(it->second.Instance, false);
      in.FreeInstances.emplace_back(it->second.Instance, it->second.Material);
      it = in.Instances.erase(it);
    }
    else
    {
      ++it;
    }
  }
  for (auto it = in.Geometries.begin(); it != in.Geometries.end();)
  {
    if (it->second.LastFrame != in.Frame)
    {
      for (int k = 0; k < KindCount; ++k)
      {
        in.FreeObject(it->second.Objects[k]);
      }
      in.FreeTexture(it->second.ColorTexture);
      it = in.Geometries.erase(it);
    }
    else
    {
      ++it;
    }
  }
  for (auto it = in.Surfaces.begin(); it != in.Surfaces.end();)
  {
    it = it->second.LastFrame != in.Frame ? in.Surfaces.erase(it) : std::next(it);
  }
  for (auto it = in.CubeTextures.begin(); it != in.CubeTextures.end();)
  {
    if (it->second.LastFrame != in.Frame)
    {
      for (int& face : it->second.Faces)
      {
        in.FreeTexture(face);
      }
      it = in.CubeTextures.erase(it);
    }
    else
    {
      ++it;
    }
  }
  for (auto it = in.Textures.begin(); it != in.Textures.end();)
  {
    if (it->second.LastFrame != in.Frame)
    {
      in.FreeTexture(it->second.Id);
      it = in.Textures.erase(it);
    }
    else
    {
      ++it;
    }
  }
}
