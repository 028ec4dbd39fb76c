#include "vtkWhittedPolyDataConverter.h"

#include "vtkWhittedPolyDataPrimitives.h"

#include "vtkMapper.h"
#include "vtkPointData.h"
#include "vtkTexture.h"

using namespace vtkWhittedPolyData;

namespace
{
// The point array named name with at least one tuple per point, or null.
vtkDataArray* PointArray(vtkPolyData* poly, const std::string& name)
{
  vtkDataArray* a = name.empty() ? nullptr : poly->GetPointData()->GetArray(name.c_str());
  return a && a->GetNumberOfTuples() >= poly->GetNumberOfPoints() && a->GetNumberOfComponents() > 0
    ? a
    : nullptr;
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
void vtkWhittedPolyDataConverter::Convert(vtkPolyData* poly, vtkMapper* mapper, const Options& o,
  const std::function<double()>& radiusScale, Primitives& out)
{
  ConvertPrimitives(poly, mapper, o, radiusScale, out);
  Recentre(out);
}

//------------------------------------------------------------------------------
void vtkWhittedPolyDataConverter::ConvertPrimitives(vtkPolyData* poly, vtkMapper* mapper,
  const Options& o, const std::function<double()>& radiusScale, Primitives& out)
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

  // Non-finite points are left in (the core skips every primitive using one) but counted. The
  // floats of a vtkFloatArray (VTK's default) are read directly, the values GetPoint gives
  vtkDataArray* coords = points->GetData();
  vtkFloatArray* floatCoords = vtkFloatArray::FastDownCast(coords);
  const float* floats =
    floatCoords && floatCoords->GetNumberOfComponents() == 3 ? floatCoords->GetPointer(0) : nullptr;
  issues.NonFinitePoints += ForPieces(np,
    [coords, floats](vtkIdType b, vtkIdType e)
    {
      vtkIdType nonFinite = 0;
      for (vtkIdType i = b; i < e; ++i)
      {
        double x[3];
        if (floats)
        {
          x[0] = floats[3 * i], x[1] = floats[3 * i + 1], x[2] = floats[3 * i + 2];
        }
        else
        {
          coords->GetTuple(i, x);
        }
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
  in.FloatPoints = floats;
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
    AddSpheres(in, [] { return 0.0; }, out.Spheres, issues);
    return; // splats only
  }
  AddSpheres(in, [&] { return o.PointSize * radiusScale(); }, out.Spheres, issues);
  AddTubes(in, [&] { return o.LineWidth * radiusScale(); }, out.Tubes, issues);
  if (o.Representation == VTK_SURFACE)
  {
    AddTriangles(in, out, issues);
  }
}
