/**
 * @file    vtkWhittedPolyDataPrimitives.h
 * @brief   internal: the primitive builders of vtkWhittedPolyDataConverter and what they share
 *
 * Private to the Whitted module, included only by the conversion of one polydata, which is split
 * by primitive:
 *
 * - vtkWhittedPolyDataConverter.cxx: the steps (points, cells, colours, per-point radii, then the
 *   builders), recentring far data, image textures.
 * - vtkWhittedPolyDataTriangles.cxx: polygons and strips -> a triangle mesh (fan or ear cutting,
 *   normals, texture and colour-map coordinates).
 * - vtkWhittedPolyDataSpheres.cxx: vertices, or every point -> spheres.
 * - vtkWhittedPolyDataTubes.cxx: lines, and in wireframe the polygon edges -> tubes.
 * - vtkWhittedPolyDataColors.cxx: the mapper's colours, per point or per cell.
 *
 * Below: what they share (the valid cell arrays, the colours, per-point values) and the builders.
 *
 * @sa vtkWhittedPolyDataConverter
 */

#ifndef vtkWhittedPolyDataPrimitives_h
#define vtkWhittedPolyDataPrimitives_h

#include "vtkWhittedPolyDataConverter.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"

#include "util/parallel.h" // whitted::WorkerPool, whitted::hardwareThreads

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

class vtkMapper;

namespace vtkWhittedPolyData
{
using whitted::Color4;
using whitted::Vec3;

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
  whitted::forChunks(pool, count, piece,
    [&](size_t b, size_t e)
    { sums[b / piece] = fn(static_cast<vtkIdType>(b), static_cast<vtkIdType>(e)); });
  return std::accumulate(sums.begin(), sums.end(), vtkIdType(0));
}

// A colour tuple of 1 to 4 unsigned chars (luminance, luminance + alpha, RGB, RGBA) as RGBA.
inline Color4 ColorFromTuple(const unsigned char* c, int nc)
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
// Whether every id of a cell names an existing point.
inline bool ValidCell(vtkIdType n, const vtkIdType* ids, vtkIdType np)
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
// Colours as the mapper maps them, per point or per cell (MapColors).
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

//------------------------------------------------------------------------------
// Colours exactly as the mapper maps them (scalar visibility, scalar mode, lookup table and range,
// direct colours), decided per point or per cell with the rule of VTK's OpenGL mapper.
// Sets shortArray for an array shorter than the points (cells) it colours, unusable for scalars
// that cannot be used directly as colours (a char array, or not 1 to 4 components); both leave
// the colours out.
void MapColors(vtkPolyData* poly, vtkIdType numCells, vtkMapper* mapper, bool actorTexture,
  ColorSource& out, bool& shortArray, bool& unusable);

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

//------------------------------------------------------------------------------
// What the primitive builders share: the input's points, its valid cell arrays, its colours
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
  /// The points' floats when they are a vtkFloatArray (VTK's default): read directly, the values GetPoint gives.
  const float* FloatPoints = nullptr;

  Vec3 Point(vtkIdType i) const
  {
    if (this->FloatPoints)
    {
      const float* p = this->FloatPoints + 3 * i;
      return Vec3(p[0], p[1], p[2]);
    }
    double x[3];
    this->Points->GetPoint(i, x);
    return Vec3(x[0], x[1], x[2]);
  }
};

//------------------------------------------------------------------------------
// Gives the spheres or tubes of set (without per-point radii) the one radius, if it is positive
// and finite; else leaves them all out and sets noRadius.
template <typename Set>
void UniformRadius(double radius, Set& set, bool& noRadius)
{
  if (radius > 0.0 && std::isfinite(radius))
  {
    set.radii.assign(1, radius);
  }
  else
  {
    set = Set();
    noRadius = true;
  }
}

//------------------------------------------------------------------------------
// Points as spheres: every vertex of a vertex cell, or in points representation every point any
// cell uses (once). They need a positive finite radius (PointSize 0 or NaN gives none); radius is
// called once there are spheres without per-point radii.
void AddSpheres(const PrimitiveInput& in, const std::function<double()>& radius,
  whitted::SphereSet& spheres,
  vtkWhittedPolyDataConverter::Problems& issues);

//------------------------------------------------------------------------------
// Lines as tubes (tubes, so consecutive segments join seamlessly), and in wireframe
// representation every polygon and strip edge once. They need a positive finite radius (LineWidth
// 0 or NaN gives none); radius is called once there are tubes without per-point radii.
void AddTubes(const PrimitiveInput& in, const std::function<double()>& radius,
  whitted::TubeSet& tubes,
  vtkWhittedPolyDataConverter::Problems& issues);

//------------------------------------------------------------------------------
// Polygons and strips as a triangle mesh, with normals by VTK's rule, colours, texture coordinates
// (for the actor's texture) and colour-map coordinates (InterpolateScalarsBeforeMapping).
void AddTriangles(const PrimitiveInput& in, vtkWhittedPolyDataConverter::Primitives& out,
  vtkWhittedPolyDataConverter::Problems& issues);
}

#endif
// VTK-HeaderTest-Exclude: vtkWhittedPolyDataPrimitives.h
