#include "vtkWhittedPolyDataPrimitives.h"

//------------------------------------------------------------------------------
void vtkWhittedPolyData::AddSpheres(const PrimitiveInput& in,
  const std::function<double()>& radius, whitted::SphereSet& spheres, vtkWhittedPolyDataConverter::Problems& issues)
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
    UniformRadius(radius(), spheres, issues.NoSphereRadius);
  }
}
