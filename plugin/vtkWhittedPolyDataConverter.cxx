#include "vtkWhittedPolyDataConverter.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCellData.h"
#include "vtkFloatArray.h"
#include "vtkIdList.h"
#include "vtkImageData.h"
#include "vtkMapper.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolygon.h"
#include "vtkScalarsToColors.h"
#include "vtkSmartPointer.h"
#include "vtkTexture.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <cmath>
#include <unordered_set>
#include <vector>

namespace
{
using whitted::Color4;
using whitted::Vec2f;
using whitted::Vec3;
using whitted::Vec3f;

Color4 ColorFromTuple(const unsigned char* c, int nc)
{
  const float s = 1.0f / 255.0f;
  switch (nc)
  {
    case 1:
      return Color4(c[0] * s, c[0] * s, c[0] * s, 1.0f);
    case 2:
      return Color4(c[0] * s, c[0] * s, c[0] * s, c[1] * s);
    case 3:
      return Color4(c[0] * s, c[1] * s, c[2] * s, 1.0f);
    default:
      return Color4(c[0] * s, c[1] * s, c[2] * s, c[3] * s);
  }
}

//------------------------------------------------------------------------------
// Convexity of a polygon (Newell normal, then every corner turns the same way).
bool IsConvexPolygon(vtkPoints* points, vtkIdType n, const vtkIdType* ids)
{
  std::vector<Vec3> p(static_cast<size_t>(n));
  for (vtkIdType i = 0; i < n; ++i)
  {
    double x[3];
    points->GetPoint(ids[i], x);
    p[i] = Vec3(x[0], x[1], x[2]);
  }
  Vec3 normal(0.0);
  for (vtkIdType i = 0; i < n; ++i)
  {
    const Vec3& a = p[i];
    const Vec3& b = p[(i + 1) % n];
    normal += Vec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
  }
  for (vtkIdType i = 0; i < n; ++i)
  {
    const Vec3 e0 = p[(i + 1) % n] - p[i];
    const Vec3 e1 = p[(i + 2) % n] - p[(i + 1) % n];
    if (glm::dot(glm::cross(e0, e1), normal) < 0.0)
    {
      return false;
    }
  }
  return true;
}

//------------------------------------------------------------------------------
// Triangles of polygons and strips, with the id of the cell each comes from. Convex polygons
// are split as a fan from their first point (as VTK's OpenGL mapper does, so interpolation
// matches); concave ones by ear cutting (VTK's OpenGL mapper draws those wrongly as fans).
struct TriangleList
{
  std::vector<glm::uvec3> Tris;
  std::vector<vtkIdType> Cells;
};

void Triangulate(vtkPolyData* poly, TriangleList& out)
{
  vtkPoints* points = poly->GetPoints();
  vtkIdType cellId = poly->GetVerts()->GetNumberOfCells() + poly->GetLines()->GetNumberOfCells();
  vtkNew<vtkPolygon> polygon;
  vtkNew<vtkIdList> tris;

  auto polys = vtk::TakeSmartPointer(poly->GetPolys()->NewIterator());
  for (polys->GoToFirstCell(); !polys->IsDoneWithTraversal(); polys->GoToNextCell(), ++cellId)
  {
    vtkIdType n;
    const vtkIdType* ids;
    polys->GetCurrentCell(n, ids);
    if (n < 3)
    {
      continue;
    }
    if (n == 3 || IsConvexPolygon(points, n, ids))
    {
      for (vtkIdType i = 1; i + 1 < n; ++i)
      {
        out.Tris.emplace_back(ids[0], ids[i], ids[i + 1]);
        out.Cells.push_back(cellId);
      }
      continue;
    }
    // Concave: ear cutting on a local copy
    polygon->GetPointIds()->SetNumberOfIds(n);
    polygon->GetPoints()->SetNumberOfPoints(n);
    for (vtkIdType i = 0; i < n; ++i)
    {
      polygon->GetPointIds()->SetId(i, ids[i]);
      polygon->GetPoints()->SetPoint(i, points->GetPoint(ids[i]));
    }
    tris->Reset();
    polygon->Triangulate(tris);
    for (vtkIdType i = 0; i + 2 < tris->GetNumberOfIds(); i += 3)
    {
      out.Tris.emplace_back(ids[tris->GetId(i)], ids[tris->GetId(i + 1)], ids[tris->GetId(i + 2)]);
      out.Cells.push_back(cellId);
    }
  }

  // Strips: alternate winding as OpenGL does
  auto strips = vtk::TakeSmartPointer(poly->GetStrips()->NewIterator());
  for (strips->GoToFirstCell(); !strips->IsDoneWithTraversal(); strips->GoToNextCell(), ++cellId)
  {
    vtkIdType n;
    const vtkIdType* ids;
    strips->GetCurrentCell(n, ids);
    for (vtkIdType j = 0; j + 2 < n; ++j)
    {
      out.Tris.emplace_back(ids[j], ids[j + 1 + j % 2], ids[j + 1 + (j + 1) % 2]);
      out.Cells.push_back(cellId);
    }
  }
}

//------------------------------------------------------------------------------
// Colours exactly as the mapper maps them (scalar visibility, scalar mode, lookup table and range,
// direct colours), decided per point or per cell with the rule of VTK's OpenGL mapper.
struct ColorSource
{
  vtkSmartPointer<vtkUnsignedCharArray> Colors;
  int NumComp = 0;
  bool Cell = false;
  vtkIdType FixedTuple = -1; // field data coloured by one tuple
  // InterpolateScalarsBeforeMapping: per-point coordinates into the colour texture
  vtkSmartPointer<vtkFloatArray> Coordinates;
  vtkSmartPointer<vtkImageData> TextureMap;

  bool PointColors() const { return this->Colors && !this->Cell; }
  bool CellColors() const { return this->Colors && this->Cell; }

  Color4 Point(vtkIdType i) const
  {
    return ColorFromTuple(this->Colors->GetPointer(i * this->NumComp), this->NumComp);
  }
  Color4 CellColor(vtkIdType cell) const
  {
    vtkIdType t = this->FixedTuple >= 0 ? this->FixedTuple : cell;
    if (t < 0 || t >= this->Colors->GetNumberOfTuples())
    {
      return Color4(1.0f);
    }
    return ColorFromTuple(this->Colors->GetPointer(t * this->NumComp), this->NumComp);
  }
};

void MapColors(vtkPolyData* poly, vtkMapper* mapper, bool actorTexture, ColorSource& out)
{
  // The mapper caches colours by MTime; a composite mapper maps several blocks in turn
  mapper->ClearColorArrays();
  int cellFlag = 0;
  vtkUnsignedCharArray* colors = mapper->MapScalars(poly, 1.0, cellFlag);
  if (!colors && mapper->GetColorTextureMap() && mapper->GetColorCoordinates())
  {
    if (!actorTexture)
    {
      out.Coordinates = mapper->GetColorCoordinates();
      out.TextureMap = mapper->GetColorTextureMap();
      return;
    }
    // The actor's own texture needs the texture coordinates: map the scalars per point instead
    int flag = 0;
    vtkAbstractArray* scalars = vtkAbstractMapper::GetAbstractScalars(poly, mapper->GetScalarMode(),
      mapper->GetArrayAccessMode(), mapper->GetArrayId(), mapper->GetArrayName(), flag);
    if (scalars && mapper->GetLookupTable())
    {
      out.Colors = vtk::TakeSmartPointer(mapper->GetLookupTable()->MapScalars(
        scalars, mapper->GetColorMode(), mapper->GetArrayComponent()));
    }
  }
  else if (colors)
  {
    out.Colors = colors;
  }
  if (!out.Colors || out.Colors->GetNumberOfTuples() == 0)
  {
    out.Colors = nullptr;
    return;
  }
  out.NumComp = out.Colors->GetNumberOfComponents();

  // vtkOpenGLPolyDataMapper::BuildBufferObjects: cell colours by scalar mode, not by cellFlag
  const int mode = mapper->GetScalarMode();
  out.Cell =
    (mode == VTK_SCALAR_MODE_USE_CELL_DATA || mode == VTK_SCALAR_MODE_USE_CELL_FIELD_DATA ||
      mode == VTK_SCALAR_MODE_USE_FIELD_DATA || !poly->GetPointData()->GetScalars()) &&
    mode != VTK_SCALAR_MODE_USE_POINT_FIELD_DATA;
  if (out.Cell && mode == VTK_SCALAR_MODE_USE_FIELD_DATA && mapper->GetFieldDataTupleId() > -1)
  {
    out.FixedTuple = mapper->GetFieldDataTupleId();
  }
  if (!out.Cell && out.Colors->GetNumberOfTuples() < poly->GetNumberOfPoints())
  {
    out.Colors = nullptr; // inconsistent array: draw with the property colours
  }
}

} // namespace

//------------------------------------------------------------------------------
whitted::Texture vtkWhittedPolyDataConverter::ConvertImage(
  vtkImageData* image, vtkDataArray* scalars, vtkTexture* texture)
{
  whitted::Texture t;
  if (!image || !scalars)
  {
    return t;
  }
  int dims[3];
  image->GetDimensions(dims);
  t.width = dims[0];
  t.height = dims[1];
  const size_t n = static_cast<size_t>(t.width) * t.height;
  if (n == 0 || scalars->GetNumberOfTuples() < static_cast<vtkIdType>(n))
  {
    t.width = t.height = 0;
    return t;
  }
  t.rgba.resize(n * 4);
  int nc = scalars->GetNumberOfComponents();
  const unsigned char* src = nullptr;
  if (scalars->GetDataType() == VTK_UNSIGNED_CHAR && nc >= 1 && nc <= 4 &&
    (!texture || texture->GetColorMode() != VTK_COLOR_MODE_MAP_SCALARS))
  {
    src = static_cast<vtkUnsignedCharArray*>(scalars)->GetPointer(0);
  }
  else if (texture)
  {
    src = texture->MapScalarsToColors(scalars); // RGBA, owned by the texture
    nc = 4;
  }
  if (!src)
  {
    t.width = t.height = 0;
    t.rgba.clear();
    return t;
  }
  for (size_t i = 0; i < n; ++i)
  {
    Color4 c = ColorFromTuple(src + i * nc, nc);
    for (int k = 0; k < 4; ++k)
    {
      t.rgba[i * 4 + k] = static_cast<uint8_t>(std::lround(c[k] * 255.0f));
    }
  }
  return t;
}

//------------------------------------------------------------------------------
void vtkWhittedPolyDataConverter::Convert(
  vtkPolyData* poly, vtkMapper* mapper, const Options& o, double radiusScale, Primitives& out)
{
  vtkPoints* points = poly->GetPoints();
  const vtkIdType np = points ? points->GetNumberOfPoints() : 0;
  if (np == 0)
  {
    return;
  }

  ColorSource colors;
  MapColors(poly, mapper, o.TCoords, colors);
  out.ScalarColors = colors.Colors != nullptr;
  if (colors.TextureMap)
  {
    out.HasColorTexture = true;
    out.ColorTexture =
      ConvertImage(colors.TextureMap, colors.TextureMap->GetPointData()->GetScalars(), nullptr);
    out.ColorTexture.repeat = false;
    out.ColorTexture.interpolate = false;
  }

  auto point = [&](vtkIdType i)
  {
    double x[3];
    points->GetPoint(i, x);
    return Vec3(x[0], x[1], x[2]);
  };
  const double sphereRadius = std::max(1e-30, o.PointSize * radiusScale);
  const double tubeRadius = std::max(1e-30, o.LineWidth * radiusScale);

  vtkCellArray* verts = poly->GetVerts();
  vtkCellArray* lines = poly->GetLines();
  const vtkIdType nVerts = verts->GetNumberOfCells();
  const vtkIdType nLines = lines->GetNumberOfCells();

  // Points as spheres: every vertex of a vertex cell, or in points representation every point any
  // cell uses (once)
  auto addSphere = [&](vtkIdType pid, vtkIdType cell)
  {
    out.Spheres.centers.push_back(point(pid));
    if (colors.PointColors())
    {
      out.Spheres.colors.push_back(colors.Point(pid));
    }
    else if (colors.CellColors())
    {
      out.Spheres.colors.push_back(colors.CellColor(cell));
    }
  };
  auto addCapsule = [&](vtkIdType a, vtkIdType b, vtkIdType cell)
  {
    out.Capsules.p0.push_back(point(a));
    out.Capsules.p1.push_back(point(b));
    if (colors.PointColors())
    {
      out.Capsules.colors0.push_back(colors.Point(a));
      out.Capsules.colors1.push_back(colors.Point(b));
    }
    else if (colors.CellColors())
    {
      out.Capsules.colors0.push_back(colors.CellColor(cell));
      out.Capsules.colors1.push_back(colors.CellColor(cell));
    }
  };

  if (o.Representation == VTK_POINTS)
  {
    std::vector<bool> seen(static_cast<size_t>(np), false);
    vtkIdType cellId = 0;
    for (vtkCellArray* ca : { verts, lines, poly->GetPolys(), poly->GetStrips() })
    {
      auto it = vtk::TakeSmartPointer(ca->NewIterator());
      for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell(), ++cellId)
      {
        vtkIdType n;
        const vtkIdType* ids;
        it->GetCurrentCell(n, ids);
        for (vtkIdType i = 0; i < n; ++i)
        {
          if (ids[i] >= 0 && ids[i] < np && !seen[ids[i]])
          {
            seen[ids[i]] = true;
            addSphere(ids[i], cellId);
          }
        }
      }
    }
  }
  else
  {
    vtkIdType cellId = 0;
    auto it = vtk::TakeSmartPointer(verts->NewIterator());
    for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell(), ++cellId)
    {
      vtkIdType n;
      const vtkIdType* ids;
      it->GetCurrentCell(n, ids);
      for (vtkIdType i = 0; i < n; ++i)
      {
        addSphere(ids[i], cellId);
      }
    }
  }
  if (!out.Spheres.centers.empty())
  {
    out.Spheres.radii.assign(1, sphereRadius);
  }

  // Lines as tubes (capsules, so consecutive segments join seamlessly)
  if (o.Representation != VTK_POINTS)
  {
    vtkIdType cellId = nVerts;
    auto it = vtk::TakeSmartPointer(lines->NewIterator());
    for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell(), ++cellId)
    {
      vtkIdType n;
      const vtkIdType* ids;
      it->GetCurrentCell(n, ids);
      for (vtkIdType i = 0; i + 1 < n; ++i)
      {
        addCapsule(ids[i], ids[i + 1], cellId);
      }
    }
  }
  if (o.Representation == VTK_WIREFRAME)
  {
    // Edges of polygons and strips, each once
    std::unordered_set<uint64_t> edges;
    auto addEdge = [&](vtkIdType a, vtkIdType b, vtkIdType cell)
    {
      const uint64_t key =
        (static_cast<uint64_t>(std::min(a, b)) << 32) | static_cast<uint64_t>(std::max(a, b));
      if (a != b && edges.insert(key).second)
      {
        addCapsule(a, b, cell);
      }
    };
    vtkIdType cellId = nVerts + nLines;
    auto polys = vtk::TakeSmartPointer(poly->GetPolys()->NewIterator());
    for (polys->GoToFirstCell(); !polys->IsDoneWithTraversal(); polys->GoToNextCell(), ++cellId)
    {
      vtkIdType n;
      const vtkIdType* ids;
      polys->GetCurrentCell(n, ids);
      for (vtkIdType i = 0; i < n; ++i)
      {
        addEdge(ids[i], ids[(i + 1) % n], cellId);
      }
    }
    auto strips = vtk::TakeSmartPointer(poly->GetStrips()->NewIterator());
    for (strips->GoToFirstCell(); !strips->IsDoneWithTraversal(); strips->GoToNextCell(), ++cellId)
    {
      vtkIdType n;
      const vtkIdType* ids;
      strips->GetCurrentCell(n, ids);
      if (n >= 2)
      {
        addEdge(ids[0], ids[1], cellId);
      }
      for (vtkIdType j = 0; j + 2 < n; ++j)
      {
        addEdge(ids[j], ids[j + 2], cellId);
        addEdge(ids[j + 1], ids[j + 2], cellId);
      }
    }
  }
  if (!out.Capsules.p0.empty())
  {
    out.Capsules.radii.assign(1, tubeRadius);
  }

  // Surfaces
  if (o.Representation != VTK_SURFACE)
  {
    return;
  }
  TriangleList tl;
  Triangulate(poly, tl);
  if (tl.Tris.empty())
  {
    return;
  }

  // Normals, by VTK's rule: point normals unless flat, else cell normals, else facet normals
  vtkDataArray* pointNormals = o.Flat ? nullptr : poly->GetPointData()->GetNormals();
  if (pointNormals && pointNormals->GetNumberOfTuples() < np)
  {
    pointNormals = nullptr;
  }
  vtkDataArray* cellNormals = pointNormals ? nullptr : poly->GetCellData()->GetNormals();

  vtkDataArray* tcoords = nullptr;
  if (o.TCoords)
  {
    tcoords = poly->GetPointData()->GetTCoords();
  }
  else if (colors.Coordinates)
  {
    tcoords = colors.Coordinates;
  }
  if (tcoords && (tcoords->GetNumberOfTuples() < np || tcoords->GetNumberOfComponents() < 1))
  {
    tcoords = nullptr;
  }
  auto tcoord = [&](vtkIdType i)
  {
    double t[3] = { 0.0, 0.0, 0.0 };
    tcoords->GetTuple(i, t);
    return Vec2f(static_cast<float>(t[0]),
      tcoords->GetNumberOfComponents() > 1 ? static_cast<float>(t[1]) : 0.5f);
  };
  out.TCoords = tcoords != nullptr;

  whitted::TriangleMesh& m = out.Mesh;
  if (!cellNormals)
  {
    // Shared vertices
    m.positions.resize(static_cast<size_t>(np));
    for (vtkIdType i = 0; i < np; ++i)
    {
      m.positions[i] = point(i);
    }
    m.triangles = std::move(tl.Tris);
    if (pointNormals)
    {
      m.normals.resize(static_cast<size_t>(np));
      for (vtkIdType i = 0; i < np; ++i)
      {
        double n[3];
        pointNormals->GetTuple(i, n);
        m.normals[i] = Vec3f(n[0], n[1], n[2]);
      }
    }
    if (colors.PointColors())
    {
      m.vertexColors.resize(static_cast<size_t>(np));
      for (vtkIdType i = 0; i < np; ++i)
      {
        m.vertexColors[i] = colors.Point(i);
      }
    }
    if (tcoords)
    {
      m.texcoords.resize(static_cast<size_t>(np));
      for (vtkIdType i = 0; i < np; ++i)
      {
        m.texcoords[i] = tcoord(i);
      }
    }
  }
  else
  {
    // Cell normals: the core interpolates per-vertex normals only, so each triangle gets its own
    // three vertices carrying its cell's normal
    const size_t nt = tl.Tris.size();
    m.positions.resize(nt * 3);
    m.normals.resize(nt * 3);
    m.triangles.resize(nt);
    if (colors.PointColors())
    {
      m.vertexColors.resize(nt * 3);
    }
    if (tcoords)
    {
      m.texcoords.resize(nt * 3);
    }
    for (size_t t = 0; t < nt; ++t)
    {
      double n[3];
      cellNormals->GetTuple(std::min(tl.Cells[t], cellNormals->GetNumberOfTuples() - 1), n);
      for (int k = 0; k < 3; ++k)
      {
        const vtkIdType pid = tl.Tris[t][k];
        const size_t v = t * 3 + k;
        m.positions[v] = point(pid);
        m.normals[v] = Vec3f(n[0], n[1], n[2]);
        if (colors.PointColors())
        {
          m.vertexColors[v] = colors.Point(pid);
        }
        if (tcoords)
        {
          m.texcoords[v] = tcoord(pid);
        }
      }
      m.triangles[t] = glm::uvec3(t * 3, t * 3 + 1, t * 3 + 2);
    }
  }
  if (colors.CellColors())
  {
    m.triangleColors.resize(tl.Cells.size());
    for (size_t t = 0; t < tl.Cells.size(); ++t)
    {
      m.triangleColors[t] = colors.CellColor(tl.Cells[t]);
    }
  }
}
