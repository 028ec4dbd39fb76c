#include "vtkWhittedPolyDataPrimitives.h"

#include "vtkCharArray.h"
#include "vtkMapper.h"
#include "vtkPointData.h"
#include "vtkScalarsToColors.h"

//------------------------------------------------------------------------------
void vtkWhittedPolyData::MapColors(vtkPolyData* poly, vtkIdType numCells, vtkMapper* mapper,
  bool actorTexture, ColorSource& out, bool& shortArray, bool& unusable)
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
