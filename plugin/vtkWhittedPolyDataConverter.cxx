#include "vtkWhittedPolyDataConverter.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCellData.h"
#include "vtkCharArray.h"
#include "vtkFloatArray.h"
#include "vtkIdList.h"
#include "vtkImageData.h"
#include "vtkMapper.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolygon.h"
#include "vtkScalarsToColors.h"
#include "vtkSmartPointer.h"
#include "vtkTexture.h"
#include "vtkUnsignedCharArray.h"

#include "util/parallel.h" // whitted::WorkerPool, whitted::hardwareThreads

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_set>
#include <vector>

namespace
{
using whitted::Color4;
using whitted::Vec2f;
using whitted::Vec3;
using whitted::Vec3f;

//------------------------------------------------------------------------------
// Calls fn(begin, end) over pieces of [0, n), on all cores when n is large (fn only reads VTK
// arrays: GetTuple into a caller's buffer, GetPointer), and returns the sum of what fn returns (a
// count). The pieces have a fixed size, so results do not depend on the number of threads.
template <typename Fn>
vtkIdType ForPieces(vtkIdType n, Fn&& fn)
{
  constexpr size_t piece = 16384;
  const size_t count = n > 0 ? static_cast<size_t>(n) : 0;
  whitted::WorkerPool pool(count >= 4 * piece ? whitted::hardwareThreads() : 1);
  std::vector<vtkIdType> sums((count + piece - 1) / piece, 0);
  whitted::forChunks(pool, count, piece, [&](size_t b, size_t e)
    { sums[b / piece] = fn(static_cast<vtkIdType>(b), static_cast<vtkIdType>(e)); });
  return std::accumulate(sums.begin(), sums.end(), vtkIdType(0));
}

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
// Whether every id of a cell names an existing point.
bool ValidCell(vtkIdType n, const vtkIdType* ids, vtkIdType np)
{
  for (vtkIdType i = 0; i < n; ++i)
  {
    if (ids[i] < 0 || ids[i] >= np)
    {
      return false;
    }
  }
  return true;
}

// The four cell arrays of a polydata, malformed ones (offsets not matching the connectivity)
// replaced by an empty array, and the id of the first cell of each (VTK's order: verts, lines,
// polys, strips).
struct CellArrays
{
  vtkNew<vtkCellArray> Empty;
  vtkCellArray* Arrays[4];
  vtkIdType FirstId[4];
  enum Kind
  {
    Verts = 0,
    Lines = 1,
    Polys = 2,
    Strips = 3
  };
  vtkIdType Total = 0;

  CellArrays(vtkPolyData* poly, int& malformed)
  {
    vtkCellArray* arrays[4] = { poly->GetVerts(), poly->GetLines(), poly->GetPolys(),
      poly->GetStrips() };
    for (int k = 0; k < 4; ++k)
    {
      this->FirstId[k] = this->Total;
      vtkCellArray* ca = arrays[k];
      if (ca)
      {
        this->Total += std::max<vtkIdType>(0, ca->GetNumberOfCells());
      }
      if (ca && !ca->IsValid())
      {
        ++malformed;
        ca = nullptr;
      }
      this->Arrays[k] = ca ? ca : this->Empty.Get();
    }
  }

  // Calls fn(n, ids, cellId) for every cell of array k whose ids all name a point; counts the
  // others in invalid.
  template <typename Fn>
  void ForEachValidCell(int k, vtkIdType np, vtkIdType& invalid, Fn&& fn) const
  {
    vtkIdType cellId = this->FirstId[k];
    auto it = vtk::TakeSmartPointer(this->Arrays[k]->NewIterator());
    for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell(), ++cellId)
    {
      vtkIdType n;
      const vtkIdType* ids;
      it->GetCurrentCell(n, ids);
      if (ValidCell(n, ids, np))
      {
        fn(n, ids, cellId);
      }
      else
      {
        ++invalid;
      }
    }
  }
};

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

void Triangulate(vtkPoints* points, const CellArrays& cells, TriangleList& out, vtkIdType& invalid)
{
  const vtkIdType np = points->GetNumberOfPoints();
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

void MapColors(vtkPolyData* poly, vtkIdType numCells, vtkMapper* mapper, bool actorTexture,
  ColorSource& out, bool& shortArray, bool& unusable)
{
  // Scalars used directly as colours need 1 to 4 components and must not be a char array: VTK
  // 9.1's vtkMapper::MapScalars dereferences the null its lookup table returns for anything else
  // (VTK's own OpenGL mapper crashes on such input)
  if (mapper->GetScalarVisibility())
  {
    int flag = 0;
    vtkDataArray* scalars = vtkArrayDownCast<vtkDataArray>(
      vtkAbstractMapper::GetAbstractScalars(poly, mapper->GetScalarMode(),
        mapper->GetArrayAccessMode(), mapper->GetArrayId(), mapper->GetArrayName(), flag));
    const int mode = mapper->GetColorMode();
    const bool direct = scalars &&
      ((mode == VTK_COLOR_MODE_DEFAULT && vtkArrayDownCast<vtkUnsignedCharArray>(scalars)) ||
        mode == VTK_COLOR_MODE_DIRECT_SCALARS);
    if (direct &&
      (vtkArrayDownCast<vtkCharArray>(scalars) || scalars->GetNumberOfComponents() < 1 ||
        scalars->GetNumberOfComponents() > 4))
    {
      unusable = true;
      return;
    }
  }

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
  // An array shorter than the points (cells) it colours: draw with the property colours
  const vtkIdType needed =
    out.Cell ? (out.FixedTuple >= 0 ? out.FixedTuple + 1 : numCells) : poly->GetNumberOfPoints();
  if (out.Colors->GetNumberOfTuples() < needed)
  {
    out.Colors = nullptr;
    shortArray = true;
  }
}

//------------------------------------------------------------------------------
// A value per point: a point array's component (its only one, or its magnitude when the component
// is -1 or out of range, as vtkPointGaussianMapper takes it; 1 without an array), through a
// piecewise function when given (clamped to its range, as the mapper's table is), times a factor.
struct PointValues
{
  vtkDataArray* Array = nullptr;
  int Component = -1;
  vtkPiecewiseFunction* Function = nullptr;
  double Factor = 1.0;
  bool Active = false; ///< Values are given per point (else the caller's uniform value applies).

  double At(vtkIdType pid) const
  {
    double v = 1.0;
    if (this->Array)
    {
      const int n = this->Array->GetNumberOfComponents();
      const int c = n == 1 ? 0 : this->Component;
      if (c >= 0 && c < n)
      {
        v = this->Array->GetComponent(pid, c);
      }
      else
      {
        v = 0.0;
        for (int k = 0; k < n; ++k)
        {
          const double x = this->Array->GetComponent(pid, k);
          v += x * x;
        }
        v = std::sqrt(v);
      }
    }
    if (this->Function)
    {
      double range[2];
      this->Function->GetRange(range);
      v = this->Function->GetValue(std::min(std::max(v, range[0]), range[1]));
    }
    return v * this->Factor;
  }
};

// The point array named name with at least one tuple per point, or null.
vtkDataArray* PointArray(vtkPolyData* poly, const std::string& name)
{
  vtkDataArray* a = name.empty() ? nullptr : poly->GetPointData()->GetArray(name.c_str());
  return a && a->GetNumberOfTuples() >= poly->GetNumberOfPoints() && a->GetNumberOfComponents() > 0
    ? a
    : nullptr;
}

//------------------------------------------------------------------------------
// What the primitive builders below share: the input's points, its valid cell arrays, its colours
// as the mapper maps them, and the actor's options.
struct PrimitiveInput
{
  vtkPolyData* Poly;
  vtkPoints* Points;
  vtkIdType NumberOfPoints;
  const CellArrays& Cells;
  const ColorSource& Colors;
  const vtkWhittedPolyDataConverter::Options& Opts;
  PointValues Radii;   ///< Per-point radii, when Radii.Active.
  PointValues Opacity; ///< Point Gaussian opacity array (alpha of mapped colours), when Active.

  Vec3 Point(vtkIdType i) const
  {
    double x[3];
    this->Points->GetPoint(i, x);
    return Vec3(x[0], x[1], x[2]);
  }
};

//------------------------------------------------------------------------------
// Points as spheres: every vertex of a vertex cell, or in points representation every point any
// cell uses (once). They need a positive finite radius (PointSize 0 or NaN gives none).
void AddSpheres(const PrimitiveInput& in, double radius, whitted::SphereSet& spheres,
  vtkWhittedPolyDataConverter::Problems& issues)
{
  const ColorSource& colors = in.Colors;
  auto addSphere = [&](vtkIdType pid, vtkIdType cell)
  {
    spheres.centers.push_back(in.Point(pid));
    if (in.Radii.Active)
    {
      spheres.radii.push_back(in.Radii.At(pid));
    }
    if (colors.PointColors())
    {
      spheres.colors.push_back(colors.Point(pid));
      if (in.Opacity.Active)
      {
        spheres.colors.back().a = static_cast<float>(in.Opacity.At(pid));
      }
    }
    else if (colors.CellColors())
    {
      spheres.colors.push_back(colors.CellColor(cell));
    }
  };
  const vtkIdType np = in.NumberOfPoints;
  if (in.Opts.Gaussian && in.Poly->GetNumberOfVerts() == 0)
  {
    // Point Gaussian without vertex cells: a splat at every point
    for (vtkIdType i = 0; i < np; ++i)
    {
      addSphere(i, -1);
    }
  }
  else if (in.Opts.Representation == VTK_POINTS)
  {
    std::vector<bool> seen(static_cast<size_t>(np), false);
    for (int k = 0; k < 4; ++k)
    {
      in.Cells.ForEachValidCell(k, np, issues.InvalidCells,
        [&](vtkIdType n, const vtkIdType* ids, vtkIdType cellId)
        {
          for (vtkIdType i = 0; i < n; ++i)
          {
            if (!seen[ids[i]])
            {
              seen[ids[i]] = true;
              addSphere(ids[i], cellId);
            }
          }
        });
    }
  }
  else
  {
    in.Cells.ForEachValidCell(CellArrays::Verts, np, issues.InvalidCells,
      [&](vtkIdType n, const vtkIdType* ids, vtkIdType cellId)
      {
        for (vtkIdType i = 0; i < n; ++i)
        {
          addSphere(ids[i], cellId);
        }
      });
  }
  if (!spheres.centers.empty() && !in.Radii.Active)
  {
    if (radius > 0.0 && std::isfinite(radius))
    {
      spheres.radii.assign(1, radius);
    }
    else
    {
      spheres = whitted::SphereSet();
      issues.NoSphereRadius = true;
    }
  }
}

//------------------------------------------------------------------------------
// Lines as tubes (tubes, so consecutive segments join seamlessly), and in wireframe
// representation every polygon and strip edge once. They need a positive finite radius (LineWidth
// 0 or NaN gives none).
void AddTubes(const PrimitiveInput& in, double radius, whitted::TubeSet& tubes,
  vtkWhittedPolyDataConverter::Problems& issues)
{
  const ColorSource& colors = in.Colors;
  auto addTube = [&](vtkIdType a, vtkIdType b, vtkIdType cell)
  {
    tubes.p0.push_back(in.Point(a));
    tubes.p1.push_back(in.Point(b));
    if (in.Radii.Active)
    {
      tubes.radii.push_back(0.5 * (in.Radii.At(a) + in.Radii.At(b)));
    }
    if (colors.PointColors())
    {
      tubes.colors0.push_back(colors.Point(a));
      tubes.colors1.push_back(colors.Point(b));
    }
    else if (colors.CellColors())
    {
      tubes.colors0.push_back(colors.CellColor(cell));
      tubes.colors1.push_back(colors.CellColor(cell));
    }
  };
  const vtkIdType np = in.NumberOfPoints;
  const int representation = in.Opts.Representation;
  if (representation != VTK_POINTS)
  {
    in.Cells.ForEachValidCell(CellArrays::Lines, np, issues.InvalidCells,
      [&](vtkIdType n, const vtkIdType* ids, vtkIdType cellId)
      {
        for (vtkIdType i = 0; i + 1 < n; ++i)
        {
          addTube(ids[i], ids[i + 1], cellId);
        }
      });
  }
  if (representation == VTK_WIREFRAME)
  {
    // Edges of polygons and strips, each once
    std::unordered_set<uint64_t> edges;
    auto addEdge = [&](vtkIdType a, vtkIdType b, vtkIdType cell)
    {
      const uint64_t key =
        (static_cast<uint64_t>(std::min(a, b)) << 32) | static_cast<uint64_t>(std::max(a, b));
      if (a != b && edges.insert(key).second)
      {
        addTube(a, b, cell);
      }
    };
    in.Cells.ForEachValidCell(CellArrays::Polys, np, issues.InvalidCells,
      [&](vtkIdType n, const vtkIdType* ids, vtkIdType cellId)
      {
        for (vtkIdType i = 0; i < n; ++i)
        {
          addEdge(ids[i], ids[(i + 1) % n], cellId);
        }
      });
    in.Cells.ForEachValidCell(CellArrays::Strips, np, issues.InvalidCells,
      [&](vtkIdType n, const vtkIdType* ids, vtkIdType cellId)
      {
        if (n >= 2)
        {
          addEdge(ids[0], ids[1], cellId);
        }
        for (vtkIdType j = 0; j + 2 < n; ++j)
        {
          addEdge(ids[j], ids[j + 2], cellId);
          addEdge(ids[j + 1], ids[j + 2], cellId);
        }
      });
  }
  if (!tubes.p0.empty() && !in.Radii.Active)
  {
    if (radius > 0.0 && std::isfinite(radius))
    {
      tubes.radii.assign(1, radius);
    }
    else
    {
      tubes = whitted::TubeSet();
      issues.NoTubeRadius = true;
    }
  }
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
Vec3f NormalAt(vtkDataArray* normals, vtkIdType i, vtkIdType& bad)
{
  double n[3];
  normals->GetTuple(i, n);
  const Vec3f v(static_cast<float>(n[0]), static_cast<float>(n[1]), static_cast<float>(n[2]));
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

//------------------------------------------------------------------------------
// Polygons and strips as a triangle mesh, with normals by VTK's rule, colours, texture coordinates
// (for the actor's texture) and colour-map coordinates (InterpolateScalarsBeforeMapping).
void AddTriangles(const PrimitiveInput& in, vtkWhittedPolyDataConverter::Primitives& out,
  vtkWhittedPolyDataConverter::Problems& issues)
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
            m.normals[i] = NormalAt(pointNormals, i, bad);
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
        n = NormalAt(cellNormals, lastCell, issues.BadNormals);
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

} // namespace

//------------------------------------------------------------------------------
void vtkWhittedPolyDataConverter::Recentre(Primitives& out)
{
  // Bounds of the finite points
  whitted::Bounds3 b;
  auto add = [&b](const auto& ps)
  {
    for (const Vec3& p : ps)
    {
      if (whitted::isFinite(p))
      {
        b.extend(p);
      }
    }
  };
  add(out.Mesh.positions);
  add(out.Spheres.centers);
  add(out.Tubes.p0);
  add(out.Tubes.p1);
  const double diagonal = b.diagonal();
  const double farthest = b.maxAbs();
  // Single-precision bounds near the data are spaced farthest * 2^-23 apart: keep that below
  // diagonal * 2^-17 (a BVH of 1 e7-offset data would otherwise test nearly every primitive)
  if (!b.valid() || !std::isfinite(diagonal) || !std::isfinite(farthest) ||
    farthest <= 64.0 * diagonal)
  {
    return;
  }
  const Vec3 origin = b.center();
  auto shift = [&origin](auto& ps)
  {
    for (Vec3& p : ps)
    {
      p -= origin;
    }
  };
  shift(out.Mesh.positions);
  shift(out.Spheres.centers);
  shift(out.Tubes.p0);
  shift(out.Tubes.p1);
  out.Origin = origin;
}

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
  ConvertPrimitives(poly, mapper, o, radiusScale, out);
  Recentre(out);
}

//------------------------------------------------------------------------------
void vtkWhittedPolyDataConverter::ConvertPrimitives(
  vtkPolyData* poly, vtkMapper* mapper, const Options& o, double radiusScale, Primitives& out)
{
  vtkPoints* points = poly->GetPoints();
  const vtkIdType np = points ? points->GetNumberOfPoints() : 0;
  if (np == 0)
  {
    return;
  }
  Problems& issues = out.Issues;
  issues.NumberOfPoints = np;
  const CellArrays cells(poly, issues.MalformedCellArrays);

  // Non-finite points are left in (the core skips every primitive using one) but counted
  vtkDataArray* coords = points->GetData();
  issues.NonFinitePoints += ForPieces(np,
    [coords](vtkIdType b, vtkIdType e)
    {
      vtkIdType nonFinite = 0;
      for (vtkIdType i = b; i < e; ++i)
      {
        double x[3];
        coords->GetTuple(i, x);
        nonFinite += !(std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]));
      }
      return nonFinite;
    });

  ColorSource colors;
  MapColors(
    poly, cells.Total, mapper, o.TCoords, colors, issues.ShortScalars, issues.UnusableColors);
  out.ScalarColors = colors.Colors != nullptr;
  if (colors.TextureMap)
  {
    out.HasColorTexture = true;
    out.ColorTexture =
      ConvertImage(colors.TextureMap, colors.TextureMap->GetPointData()->GetScalars(), nullptr);
    out.ColorTexture.repeat = false;
    out.ColorTexture.interpolate = false;
  }

  PrimitiveInput in{ poly, points, np, cells, colors, o, {}, {} };
  // Per-point radii: Point Gaussian splats (radius 1 through the function without an array), or a
  // radius array when the points have it
  vtkDataArray* radii = PointArray(poly, o.RadiusArray);
  if (o.Gaussian || radii)
  {
    in.Radii = PointValues{ radii, o.Gaussian ? o.RadiusComponent : -1,
      o.Gaussian && o.RadiusArray.empty() ? nullptr : o.RadiusFunction, o.RadiusFactor, true };
  }
  if (o.Gaussian)
  {
    if (vtkDataArray* opacities = PointArray(poly, o.OpacityArray))
    {
      in.Opacity = PointValues{ opacities, o.OpacityComponent, o.OpacityFunction, 1.0, true };
    }
    AddSpheres(in, 0.0, out.Spheres, issues);
    return; // splats only
  }
  AddSpheres(in, o.PointSize * radiusScale, out.Spheres, issues);
  AddTubes(in, o.LineWidth * radiusScale, out.Tubes, issues);
  if (o.Representation == VTK_SURFACE)
  {
    AddTriangles(in, out, issues);
  }
}
