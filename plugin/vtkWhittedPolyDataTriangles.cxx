#include "vtkWhittedPolyDataPrimitives.h"

#include "vtkCellData.h"
#include "vtkIdList.h"
#include "vtkPointData.h"
#include "vtkPolygon.h"

namespace
{
using vtkWhittedPolyData::CellArrays;
using vtkWhittedPolyData::PrimitiveInput;
using whitted::Vec2f;
using whitted::Vec3;
using whitted::Vec3f;

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
// Cells using ids that name no point are skipped and counted.
struct TriangleList
{
  whitted::LargeVector<glm::uvec3> Tris;
  std::vector<vtkIdType> Cells;
  /// Per triangle, its edges that are polygon edges (whitted::TriangleMesh::edgeFlags): VTK draws a
  /// polygon's outline for Surface With Edges, not the diagonals of its triangulation.
  std::vector<uint8_t> Edges;

  void Add(const glm::uvec3& tri, vtkIdType cell, uint8_t edges)
  {
    this->Tris.push_back(tri);
    this->Cells.push_back(cell);
    this->Edges.push_back(edges);
  }
};

// The edge bits of triangle (a, b, c), local indices of an n-gon: an edge is the polygon's if its
// ends are neighbours on the outline.
uint8_t PolygonEdges(vtkIdType a, vtkIdType b, vtkIdType c, vtkIdType n)
{
  auto outline = [n](vtkIdType i, vtkIdType j)
  {
    const vtkIdType d = i > j ? i - j : j - i;
    return d == 1 || d == n - 1;
  };
  return static_cast<uint8_t>(
    (outline(a, b) ? 1 : 0) | (outline(b, c) ? 2 : 0) | (outline(c, a) ? 4 : 0));
}

// Polygons that are all triangles (a contour, a triangulated surface: the common case) read straight from the
// cell array's offsets and connectivity, on all cores: the triangles, cell ids and edge bits AddPolygons gives
// them. False (out untouched) when some cell is not a triangle or names no point: AddPolygons then runs. A cell's
// ids are read only once its size is known to be 3 (mixed sizes can add up to 3 per cell, as a quad and a
// two-point polygon do).
template <typename Id>
bool TrianglesOnly(const Id* offsets, const Id* conn, vtkIdType nc, vtkIdType np, vtkIdType firstId,
  TriangleList& out)
{
  whitted::LargeVector<glm::uvec3> tris(static_cast<size_t>(nc));
  std::vector<vtkIdType> ids(static_cast<size_t>(nc));
  const vtkIdType bad = vtkWhittedPolyData::ForPieces(nc,
    [&](vtkIdType b, vtkIdType e)
    {
      vtkIdType n = 0;
      for (vtkIdType i = b; i < e; ++i)
      {
        const vtkIdType o = static_cast<vtkIdType>(offsets[i]);
        if (static_cast<vtkIdType>(offsets[i + 1]) - o != 3)
        {
          ++n;
          continue;
        }
        const vtkIdType p0 = conn[o], p1 = conn[o + 1], p2 = conn[o + 2];
        n += p0 < 0 || p0 >= np || p1 < 0 || p1 >= np || p2 < 0 || p2 >= np;
        tris[i] = glm::uvec3(p0, p1, p2);
        ids[i] = firstId + i;
      }
      return n;
    });
  if (bad != 0)
  {
    return false;
  }
  out.Tris = std::move(tris);
  out.Cells = std::move(ids);
  out.Edges.assign(static_cast<size_t>(nc), 7); // PolygonEdges(0, 1, 2, 3): all three
  return true;
}

bool TrianglesOnly(const CellArrays& cells, vtkIdType np, TriangleList& out)
{
  vtkCellArray* ca = cells.Arrays[CellArrays::Polys];
  const vtkIdType nc = ca->GetNumberOfCells();
  if (nc == 0 || ca->GetNumberOfConnectivityIds() != 3 * nc)
  {
    return false;
  }
  const vtkIdType first = cells.FirstId[CellArrays::Polys];
  return ca->IsStorage64Bit()
    ? TrianglesOnly(ca->GetOffsetsArray64()->GetPointer(0), ca->GetConnectivityArray64()->GetPointer(0), nc,
        np, first, out)
    : TrianglesOnly(ca->GetOffsetsArray32()->GetPointer(0), ca->GetConnectivityArray32()->GetPointer(0), nc,
        np, first, out);
}

// Triangulate's polygons cell by cell (any cell sizes; cells naming no point skipped and counted).
void AddPolygons(
  vtkPoints* points, const CellArrays& cells, vtkIdType np, TriangleList& out, vtkIdType& invalid)
{
  vtkNew<vtkPolygon> polygon;
  vtkNew<vtkIdList> tris;
  // At least a triangle per polygon (exactly one for a triangle mesh): no regrowth
  const size_t polys = static_cast<size_t>(cells.Arrays[CellArrays::Polys]->GetNumberOfCells());
  out.Tris.reserve(polys);
  out.Cells.reserve(polys);
  out.Edges.reserve(polys);

  cells.ForEachValidCell(CellArrays::Polys, np, invalid,
    [&](vtkIdType n, const vtkIdType* ids, vtkIdType cellId)
    {
      if (n < 3)
      {
        return;
      }
      if (n == 3 || IsConvexPolygon(points, n, ids))
      {
        for (vtkIdType i = 1; i + 1 < n; ++i)
        {
          out.Add(glm::uvec3(ids[0], ids[i], ids[i + 1]), cellId, PolygonEdges(0, i, i + 1, n));
        }
        return;
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
        const vtkIdType a = tris->GetId(i), b = tris->GetId(i + 1), c = tris->GetId(i + 2);
        if (a >= 0 && a < n && b >= 0 && b < n && c >= 0 && c < n)
        {
          out.Add(glm::uvec3(ids[a], ids[b], ids[c]), cellId, PolygonEdges(a, b, c, n));
        }
      }
    });
}

void Triangulate(vtkPoints* points, const CellArrays& cells, TriangleList& out, vtkIdType& invalid)
{
  const vtkIdType np = points->GetNumberOfPoints();
  if (!TrianglesOnly(cells, np, out))
  {
    AddPolygons(points, cells, np, out, invalid);
  }

  // Strips: alternate winding as OpenGL does; VTK draws every edge of a strip's triangles
  cells.ForEachValidCell(CellArrays::Strips, np, invalid,
    [&](vtkIdType n, const vtkIdType* ids, vtkIdType cellId)
    {
      for (vtkIdType j = 0; j + 2 < n; ++j)
      {
        out.Add(glm::uvec3(ids[j], ids[j + 1 + j % 2], ids[j + 1 + (j + 1) % 2]), cellId, 7);
      }
    });
}

//------------------------------------------------------------------------------
// A per-point array usable as texture (or colour-map) coordinates: at least one tuple per point,
// 1 to 3 components. Null (and counted) otherwise.
vtkDataArray* UsableCoordinates(vtkDataArray* a, vtkIdType np, bool& shortArray)
{
  if (a &&
    (a->GetNumberOfTuples() < np || a->GetNumberOfComponents() < 1 ||
      a->GetNumberOfComponents() > 3))
  {
    shortArray = true;
    return nullptr;
  }
  return a;
}

//------------------------------------------------------------------------------
// Normals by VTK's rule: point normals unless the interpolation is flat, else cell normals, else
// none (facet normals). Arrays shorter than what they describe (or not 3 components) are ignored
// and counted in shortArray.
void ChooseNormals(const PrimitiveInput& in, vtkDataArray*& pointNormals,
  vtkDataArray*& cellNormals, bool& shortArray)
{
  pointNormals = in.Opts.Flat ? nullptr : in.Poly->GetPointData()->GetNormals();
  if (pointNormals &&
    (pointNormals->GetNumberOfTuples() < in.NumberOfPoints ||
      pointNormals->GetNumberOfComponents() != 3))
  {
    pointNormals = nullptr;
    shortArray = true;
  }
  cellNormals = pointNormals ? nullptr : in.Poly->GetCellData()->GetNormals();
  if (cellNormals &&
    (cellNormals->GetNumberOfTuples() < in.Cells.Total ||
      cellNormals->GetNumberOfComponents() != 3))
  {
    cellNormals = nullptr;
    shortArray = true;
  }
}

//------------------------------------------------------------------------------
// A normal of a normals array as the core takes it. Bad vectors (NaN, infinite, zero) are left to
// the core, which falls back to the facet normal, but counted.
// floats: the array's values when it is a vtkFloatArray (read directly: the floats GetTuple gives).
Vec3f NormalAt(vtkDataArray* normals, const float* floats, vtkIdType i, vtkIdType& bad)
{
  Vec3f v;
  if (floats)
  {
    v = Vec3f(floats[3 * i], floats[3 * i + 1], floats[3 * i + 2]);
  }
  else
  {
    double n[3];
    normals->GetTuple(i, n);
    v = Vec3f(static_cast<float>(n[0]), static_cast<float>(n[1]), static_cast<float>(n[2]));
  }
  if (!whitted::isFinite(v) || !(glm::dot(v, v) > 0.0f))
  {
    ++bad;
  }
  return v;
}

//------------------------------------------------------------------------------
// The per-point attributes a mesh vertex takes from its point: position, colour, texture
// coordinates of the actor's texture, or the colour-map coordinate (first component) of
// InterpolateScalarsBeforeMapping (the mapper gives one or the other, never both).
struct VertexAttributes
{
  const PrimitiveInput& In;
  vtkDataArray* TCoords;
  vtkDataArray* ColorCoords;

  VertexAttributes(const PrimitiveInput& in, vtkWhittedPolyDataConverter::Problems& issues)
    : In(in)
    , TCoords(UsableCoordinates(in.Opts.TCoords ? in.Poly->GetPointData()->GetTCoords() : nullptr,
        in.NumberOfPoints, issues.ShortTCoords))
    , ColorCoords(UsableCoordinates(in.Colors.Coordinates, in.NumberOfPoints, issues.ShortTCoords))
  {
  }

  void Resize(whitted::TriangleMesh& m, size_t n) const
  {
    m.positions.resize(n);
    m.vertexColors.resize(this->In.Colors.PointColors() ? n : 0);
    m.texcoords.resize(this->TCoords ? n : 0);
    m.colorCoords.resize(this->ColorCoords ? n : 0);
  }

  // Vertex v from point pid
  void Set(whitted::TriangleMesh& m, size_t v, vtkIdType pid) const
  {
    m.positions[v] = this->In.Point(pid);
    if (this->In.Colors.PointColors())
    {
      m.vertexColors[v] = this->In.Colors.Point(pid);
    }
    if (this->TCoords)
    {
      double t[3] = { 0.0, 0.0, 0.0 };
      this->TCoords->GetTuple(pid, t);
      m.texcoords[v] = Vec2f(static_cast<float>(t[0]),
        this->TCoords->GetNumberOfComponents() > 1 ? static_cast<float>(t[1]) : 0.5f);
    }
    if (this->ColorCoords)
    {
      m.colorCoords[v] = static_cast<float>(this->ColorCoords->GetComponent(pid, 0));
    }
  }
};

} // namespace

//------------------------------------------------------------------------------
void vtkWhittedPolyData::AddTriangles(const PrimitiveInput& in,
  vtkWhittedPolyDataConverter::Primitives& out, vtkWhittedPolyDataConverter::Problems& issues)
{
  TriangleList tl;
  Triangulate(in.Points, in.Cells, tl, issues.InvalidCells);
  if (tl.Tris.empty())
  {
    return;
  }
  vtkDataArray* pointNormals = nullptr;
  vtkDataArray* cellNormals = nullptr;
  ChooseNormals(in, pointNormals, cellNormals, issues.ShortNormals);
  const VertexAttributes attributes(in, issues);
  out.TCoords = attributes.TCoords != nullptr;

  whitted::TriangleMesh& m = out.Mesh;
  if (!cellNormals)
  {
    // Shared vertices
    const vtkIdType np = in.NumberOfPoints;
    attributes.Resize(m, static_cast<size_t>(np));
    vtkFloatArray* floatNormals = vtkFloatArray::FastDownCast(pointNormals);
    const float* nf = floatNormals ? floatNormals->GetPointer(0) : nullptr;
    if (pointNormals)
    {
      m.normals.resize(static_cast<size_t>(np));
    }
    issues.BadNormals += ForPieces(np,
      [&](vtkIdType b, vtkIdType e)
      {
        vtkIdType bad = 0;
        for (vtkIdType i = b; i < e; ++i)
        {
          attributes.Set(m, static_cast<size_t>(i), i);
          if (pointNormals)
          {
            m.normals[i] = NormalAt(pointNormals, nf, i, bad);
          }
        }
        return bad;
      });
    m.triangles = std::move(tl.Tris);
  }
  else
  {
    // Cell normals: the core interpolates per-vertex normals only, so each triangle gets its own
    // three vertices carrying its cell's normal
    const size_t nt = tl.Tris.size();
    attributes.Resize(m, nt * 3);
    m.normals.resize(nt * 3);
    m.triangles.resize(nt);
    vtkIdType lastCell = -1;
    Vec3f n(0.0f);
    for (size_t t = 0; t < nt; ++t)
    {
      if (tl.Cells[t] != lastCell)
      {
        lastCell = tl.Cells[t];
        n = NormalAt(cellNormals, nullptr, lastCell, issues.BadNormals);
      }
      for (int k = 0; k < 3; ++k)
      {
        attributes.Set(m, t * 3 + k, tl.Tris[t][k]);
        m.normals[t * 3 + k] = n;
      }
      m.triangles[t] = glm::uvec3(t * 3, t * 3 + 1, t * 3 + 2);
    }
  }
  m.edgeFlags = std::move(tl.Edges);
  if (in.Colors.CellColors())
  {
    m.triangleColors.resize(tl.Cells.size());
    for (size_t t = 0; t < tl.Cells.size(); ++t)
    {
      m.triangleColors[t] = in.Colors.CellColor(tl.Cells[t]);
    }
  }
}
