#include "vtkWhittedGlyphPlacement.h"

#include "vtkBitArray.h"
#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkGlyph3DMapper.h"
#include "vtkMath.h"
#include "vtkQuaternion.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <cmath>

namespace
{
// The mapper's array getters (mask, source index, orientation, scale) are protected; this class
// only names them, so that their member pointers can be taken (a standard-conforming access to
// what vtkOpenGLGlyph3DMapper calls itself, keeping the mapper's own choice of array, association
// and Masking / SourceIndexing / Orient / Scaling switches).
class GlyphArrays : public vtkGlyph3DMapper
{
public:
  using vtkGlyph3DMapper::GetMaskArray;
  using vtkGlyph3DMapper::GetOrientationArray;
  using vtkGlyph3DMapper::GetScaleArray;
  using vtkGlyph3DMapper::GetSourceIndexArray;
};
using ArrayGetter = vtkDataArray* (vtkGlyph3DMapper::*)(vtkDataSet*);

vtkDataArray* Get(vtkGlyph3DMapper* mapper, ArrayGetter getter, vtkDataSet* points)
{
  return (mapper->*getter)(points);
}

//------------------------------------------------------------------------------
// The rotation of one glyph (vtkOpenGLGlyph3DMapper::RebuildStructures).
vtkQuaterniond Orientation(int mode, const double o[4])
{
  vtkQuaterniond q; // identity
  switch (mode)
  {
    case vtkGlyph3DMapper::ROTATION:
    {
      // vtkProp3D's order: z, then x, then y
      auto about = [](double degrees, int axis)
      {
        const double half = 0.5 * vtkMath::RadiansFromDegrees(degrees);
        double v[3] = { 0.0, 0.0, 0.0 };
        v[axis] = std::sin(half);
        return vtkQuaterniond(std::cos(half), v[0], v[1], v[2]);
      };
      q = about(o[2], 2) * about(o[0], 0) * about(o[1], 1);
      break;
    }
    case vtkGlyph3DMapper::DIRECTION:
      if (o[1] == 0.0 && o[2] == 0.0)
      {
        if (o[0] < 0.0)
        {
          q.Set(0.0, 0.0, 1.0, 0.0); // half turn about y
        }
      }
      else
      {
        // Half-way between x and the direction: a half turn about it maps x onto the direction
        const double norm = std::sqrt(o[0] * o[0] + o[1] * o[1] + o[2] * o[2]);
        double h[3] = { (o[0] + norm) / 2.0, o[1] / 2.0, o[2] / 2.0 };
        const double f = 1.0 / std::sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
        q.Set(0.0, h[0] * f, h[1] * f, h[2] * f);
      }
      break;
    default: // QUATERNION
      q.Set(o[0], o[1], o[2], o[3]);
      break;
  }
  return q;
}
} // namespace

//------------------------------------------------------------------------------
vtkWhittedGlyphPlacement::Problem vtkWhittedGlyphPlacement::ForEachGlyph(vtkGlyph3DMapper* mapper,
  vtkDataSet* points, int numberOfSources,
  const std::function<void(int, vtkIdType, const whitted::Mat4&)>& place)
{
  const vtkIdType numberOfPoints = points->GetNumberOfPoints();
  if (numberOfPoints < 1 || numberOfSources < 1)
  {
    return None;
  }

  // The arrays, checked as VTK checks them
  const int orientationMode = mapper->GetOrientationMode();
  vtkDataArray* orientations = Get(mapper, &GlyphArrays::GetOrientationArray, points);
  if (orientations &&
    orientations->GetNumberOfComponents() !=
      (orientationMode == vtkGlyph3DMapper::QUATERNION ? 4 : 3))
  {
    return OrientationComponents;
  }
  vtkBitArray* mask =
    vtkArrayDownCast<vtkBitArray>(Get(mapper, &GlyphArrays::GetMaskArray, points));
  if (mask && mask->GetNumberOfComponents() != 1)
  {
    return MaskComponents;
  }
  vtkDataArray* indices = Get(mapper, &GlyphArrays::GetSourceIndexArray, points);
  vtkDataArray* scales = Get(mapper, &GlyphArrays::GetScaleArray, points);
  // An array shorter than the point list (an inconsistent dataset) would be read past its end
  for (vtkDataArray* a : { orientations, static_cast<vtkDataArray*>(mask), indices, scales })
  {
    if (a && (a->GetNumberOfTuples() < numberOfPoints || a->GetNumberOfComponents() < 1))
    {
      return ShortArray;
    }
  }
  const int scaleMode = mapper->GetScaleMode();
  Problem problem = None;
  if (scales && scaleMode == vtkGlyph3DMapper::SCALE_BY_COMPONENTS &&
    scales->GetNumberOfComponents() != 3)
  {
    problem = ScaleComponents;
  }
  const double* range = mapper->GetRange();
  const double span = range[1] - range[0] != 0.0 ? range[1] - range[0] : 1.0;
  const bool clamp = mapper->GetClamping() && scaleMode != vtkGlyph3DMapper::NO_DATA_SCALING;

  for (vtkIdType i = 0; i < numberOfPoints; ++i)
  {
    if (mask && mask->GetValue(i) == 0)
    {
      continue;
    }
    int source = 0;
    if (indices)
    {
      // Clamped before the cast (a NaN or huge norm would not fit an int): NaN takes source 0,
      // as VTK's cast gives on x86-64
      const double value = vtkMath::Norm(indices->GetTuple(i), indices->GetNumberOfComponents());
      const double last = numberOfSources - 1;
      source = static_cast<int>(value >= 0.0 ? std::min(value, last) : 0.0);
    }

    // Scale: by magnitude or components, clamped to Range and mapped to [0, 1] when clamping
    double scale[3] = { 1.0, 1.0, 1.0 };
    if (scales)
    {
      const double* tuple = scales->GetTuple(i);
      if (scaleMode == vtkGlyph3DMapper::SCALE_BY_MAGNITUDE)
      {
        scale[0] = scale[1] = scale[2] = vtkMath::Norm(tuple, scales->GetNumberOfComponents());
      }
      else if (scaleMode == vtkGlyph3DMapper::SCALE_BY_COMPONENTS && problem == None)
      {
        std::copy(tuple, tuple + 3, scale);
      }
      if (clamp)
      {
        for (double& s : scale)
        {
          s = (std::min(std::max(s, range[0]), range[1]) - range[0]) / span;
        }
      }
    }

    // Matrix: translate to the point, rotate, scale (column k of the rotation times scale k)
    whitted::Mat4 m(1.0);
    double x[3];
    points->GetPoint(i, x);
    m[3] = whitted::Vec4(x[0], x[1], x[2], 1.0);
    if (orientations)
    {
      double o[4] = { 0.0, 0.0, 0.0, 0.0 };
      orientations->GetTuple(i, o);
      double r[3][3];
      Orientation(orientationMode, o).ToMatrix3x3(r);
      for (int row = 0; row < 3; ++row)
      {
        for (int col = 0; col < 3; ++col)
        {
          m[col][row] = r[row][col];
        }
      }
    }
    if (mapper->GetScaling())
    {
      for (int col = 0; col < 3; ++col)
      {
        double s = scale[col] * mapper->GetScaleFactor();
        s = s == 0.0 ? 1.0e-10 : s;
        m[col] = m[col] * s;
      }
    }
    place(source, i, m);
  }
  return problem;
}

//------------------------------------------------------------------------------
vtkUnsignedCharArray* vtkWhittedGlyphPlacement::MapColors(
  vtkGlyph3DMapper* mapper, vtkMapper* colorMapper, vtkDataSet* points)
{
  colorMapper->ShallowCopy(mapper);
  colorMapper->ClearColorArrays();
  vtkUnsignedCharArray* colors = colorMapper->MapScalars(points, 1.0);
  if (!colors || colors->GetNumberOfComponents() != 4 ||
    colors->GetNumberOfTuples() < points->GetNumberOfPoints())
  {
    return nullptr;
  }
  return colors;
}
