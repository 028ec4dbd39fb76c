#include "vtkWhittedPolyDataPrimitives.h"

#include <unordered_set>

//------------------------------------------------------------------------------
void vtkWhittedPolyData::AddTubes(const PrimitiveInput& in,
  const std::function<double()>& radius, whitted::TubeSet& tubes,
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
    UniformRadius(radius(), tubes, issues.NoTubeRadius);
  }
}
