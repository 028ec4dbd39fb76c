#include "vtkWhittedActorPieces.h"

#include "vtkWhittedGeometryCache.h"

#include "vtkActor.h"
#include "vtkBoundingBox.h"
#include "vtkCompositeDataDisplayAttributes.h"
#include "vtkCompositePolyDataMapper2.h"
#include "vtkDataObjectTree.h"
#include "vtkDataObjectTreeIterator.h"
#include "vtkDataSetMapper.h"
#include "vtkPointGaussianMapper.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkProperty.h"

#include <cmath>

using vtkWhittedActorPieces::Piece;

namespace
{
//------------------------------------------------------------------------------
// Appends the visible polydata leaves of obj (a block of a composite input) with their inherited
// display attributes.
void CollectBlocks(vtkDataObject* obj, vtkCompositeDataDisplayAttributes* attrs, bool visible,
  const vtkWhittedMaterials::BlockAttributes& inherited, std::vector<Piece>& out)
{
  if (!obj)
  {
    return;
  }
  vtkWhittedMaterials::BlockAttributes block = inherited;
  if (attrs)
  {
    if (attrs->HasBlockVisibility(obj))
    {
      visible = attrs->GetBlockVisibility(obj);
    }
    if (attrs->HasBlockColor(obj))
    {
      block.HasColor = true;
      attrs->GetBlockColor(obj, block.Color);
    }
    if (attrs->HasBlockOpacity(obj))
    {
      block.HasOpacity = true;
      block.Opacity = attrs->GetBlockOpacity(obj);
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
      CollectBlocks(iter->GetCurrentDataObject(), attrs, visible, block, out);
    }
  }
  else if (auto* poly = vtkPolyData::SafeDownCast(obj))
  {
    if (visible)
    {
      out.push_back(Piece{ poly, block });
    }
  }
}
} // namespace

//------------------------------------------------------------------------------
bool vtkWhittedActorPieces::Collect(
  vtkActor* actor, vtkWhittedGeometryCache& geometries, std::vector<Piece>& pieces)
{
  vtkMapper* mapper = actor->GetMapper();
  if (!mapper->GetStatic())
  {
    mapper->Update();
  }
  vtkDataObject* input = mapper->GetInputDataObject(0, 0);
  if (!input)
  {
    return false;
  }
  if (vtkDataSetMapper::SafeDownCast(mapper) && !vtkPolyData::SafeDownCast(input))
  {
    // vtkDataSetMapper draws the outer surface of other datasets
    auto* dataset = vtkDataSet::SafeDownCast(input);
    if (!dataset)
    {
      return false;
    }
    input = geometries.GetSurface(mapper, dataset);
  }
  if (auto* poly = vtkPolyData::SafeDownCast(input))
  {
    pieces.push_back(Piece{ poly, {} });
  }
  else
  {
    auto* cpdm = vtkCompositePolyDataMapper2::SafeDownCast(mapper);
    CollectBlocks(
      input, cpdm ? cpdm->GetCompositeDataDisplayAttributes() : nullptr, true, {}, pieces);
  }
  return true;
}

//------------------------------------------------------------------------------
bool vtkWhittedActorPieces::OnlyPlainPointsOrLines(
  const std::vector<Piece>& pieces, vtkProperty* p, vtkMapper* mapper)
{
  if (p->GetRepresentation() != VTK_SURFACE || vtkPointGaussianMapper::SafeDownCast(mapper))
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

//------------------------------------------------------------------------------
// The diagonal is that of the points, never the mapper's cell bounds: those read points through
// connectivity that may be invalid.
double vtkWhittedActorPieces::RadiusScale(const std::vector<Piece>& pieces)
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
  return (length > 0.0 && std::isfinite(length) ? length : 1.0) / 1000.0;
}
