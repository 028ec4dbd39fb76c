// Bad input through the pass, case by case. Each case adds one actor built from bad input to a
// small scene (checkerboard floor, diffuse sphere, shadow-casting light) and renders it twice with
// a fresh pass; the same scene with the actor's clean equivalent (or without it, when nothing of
// it can be drawn) is the reference. Each case must:
//  - not crash, and leave no NaN or infinite value in the traced frame;
//  - emit the expected warnings through the pass: exactly once over the two frames, naming the
//    actor (its address and class) and the problem; input that is valid VTK (polygons, concave
//    polygons, strips, empty data, scalars outside the range or NaN scalars, which VTK maps to the
//    lookup table's colours) must emit none; no case may emit an error;
//  - render the rest of the scene unchanged: the image equals the reference (no pixel differs by
//    more than 1/255).
// Figures printed per case: warnings, non-finite values, differing pixels.
#include "WhittedTestUtilities.h"

#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkCompositeDataDisplayAttributes.h"
#include "vtkCompositePolyDataMapper2.h"
#include "vtkDoubleArray.h"
#include "vtkLight.h"
#include "vtkLookupTable.h"
#include "vtkMath.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkPoints.h"

#include <array>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

namespace
{
using whittedtest::SetWhitted;

// A polydata from points and cells of one kind (polys, strips, lines or verts)
enum CellKind
{
  Polys,
  Strips,
  Lines,
  Verts
};

vtkSmartPointer<vtkPolyData> MakePoly(const std::vector<std::array<double, 3>>& pts,
  const std::vector<std::vector<vtkIdType>>& cells, CellKind kind = Polys)
{
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  for (const auto& p : pts)
  {
    points->InsertNextPoint(p.data());
  }
  vtkNew<vtkCellArray> ca;
  for (const auto& c : cells)
  {
    ca->InsertNextCell(static_cast<vtkIdType>(c.size()), c.data());
  }
  poly->SetPoints(points);
  switch (kind)
  {
    case Polys:
      poly->SetPolys(ca);
      break;
    case Strips:
      poly->SetStrips(ca);
      break;
    case Lines:
      poly->SetLines(ca);
      break;
    case Verts:
      poly->SetVerts(ca);
      break;
  }
  return poly;
}

vtkSmartPointer<vtkActor> ActorOf(vtkDataObject* data)
{
  auto actor = vtkSmartPointer<vtkActor>::New();
  if (auto* poly = vtkPolyData::SafeDownCast(data))
  {
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputData(poly);
    actor->SetMapper(mapper);
  }
  else
  {
    vtkNew<vtkCompositePolyDataMapper2> mapper;
    mapper->SetInputDataObject(data);
    actor->SetMapper(mapper);
  }
  actor->GetProperty()->SetColor(0.3, 0.8, 0.4);
  return actor;
}

// The same polydata with float points and 32-bit cell arrays: the converter reads those directly (a mesh of
// triangles only is taken from the offsets and connectivity at once), the double / 64-bit inputs the general way
vtkSmartPointer<vtkPolyData> FloatAnd32Bit(vtkSmartPointer<vtkPolyData> poly)
{
  vtkNew<vtkPoints> points;
  points->SetDataTypeToFloat();
  points->SetNumberOfPoints(poly->GetNumberOfPoints());
  for (vtkIdType i = 0; i < poly->GetNumberOfPoints(); ++i)
  {
    points->SetPoint(i, poly->GetPoint(i));
  }
  poly->SetPoints(points);
  for (vtkCellArray* ca : { poly->GetVerts(), poly->GetLines(), poly->GetPolys(), poly->GetStrips() })
  {
    if (ca)
    {
      ca->ConvertTo32BitStorage();
    }
  }
  return poly;
}

// A vertical quad (two triangles) standing on the floor at x in [0.6, 1.6], z = 0.3
std::vector<std::array<double, 3>> QuadPoints()
{
  return { { 0.6, 0.0, 0.3 }, { 1.6, 0.0, 0.3 }, { 1.6, 1.0, 0.3 }, { 0.6, 1.0, 0.3 } };
}
const std::vector<std::vector<vtkIdType>> QuadTris = { { 0, 1, 2 }, { 0, 2, 3 } };

// A 4 x 4 grid of quads in the same plane with point normals (facing +z), for the normals cases
vtkSmartPointer<vtkPolyData> NormalGrid(const std::function<void(vtkIdType, double[3])>& normal)
{
  std::vector<std::array<double, 3>> pts;
  std::vector<std::vector<vtkIdType>> quads;
  for (int j = 0; j <= 4; ++j)
  {
    for (int i = 0; i <= 4; ++i)
    {
      pts.push_back({ 0.6 + 0.25 * i, 0.25 * j, 0.3 });
    }
  }
  for (int j = 0; j < 4; ++j)
  {
    for (int i = 0; i < 4; ++i)
    {
      const vtkIdType a = j * 5 + i;
      quads.push_back({ a, a + 1, a + 6, a + 5 });
    }
  }
  auto poly = MakePoly(pts, quads);
  vtkNew<vtkDoubleArray> normals;
  normals->SetNumberOfComponents(3);
  normals->SetNumberOfTuples(poly->GetNumberOfPoints());
  for (vtkIdType i = 0; i < poly->GetNumberOfPoints(); ++i)
  {
    double n[3] = { 0.0, 0.0, 1.0 };
    normal(i, n);
    normals->SetTuple(i, n);
  }
  poly->GetPointData()->SetNormals(normals);
  return poly;
}

// A quad split in 4 x 1 cells carrying float cell scalars, mapped through a two-colour table
// with range [0, 1] whose NaN colour is the colour of 0
vtkSmartPointer<vtkActor> ScalarStrip(const double values[4])
{
  std::vector<std::array<double, 3>> pts;
  std::vector<std::vector<vtkIdType>> quads;
  for (int i = 0; i <= 4; ++i)
  {
    pts.push_back({ 0.6 + 0.25 * i, 0.0, 0.3 });
    pts.push_back({ 0.6 + 0.25 * i, 1.0, 0.3 });
  }
  for (int i = 0; i < 4; ++i)
  {
    quads.push_back({ 2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1 });
  }
  auto poly = MakePoly(pts, quads);
  vtkNew<vtkDoubleArray> s;
  s->SetName("s");
  for (int i = 0; i < 4; ++i)
  {
    s->InsertNextValue(values[i]);
  }
  poly->GetCellData()->SetScalars(s);
  auto actor = ActorOf(poly);
  vtkNew<vtkLookupTable> lut;
  lut->SetNumberOfTableValues(2);
  lut->SetTableValue(0, 0.9, 0.2, 0.1, 1.0);
  lut->SetTableValue(1, 0.1, 0.3, 0.9, 1.0);
  lut->SetNanColor(0.9, 0.2, 0.1, 1.0);
  lut->SetTableRange(0.0, 1.0);
  lut->Build();
  auto* mapper = vtkPolyDataMapper::SafeDownCast(actor->GetMapper());
  mapper->SetLookupTable(lut);
  mapper->SetScalarRange(0.0, 1.0);
  mapper->SetScalarModeToUseCellData();
  mapper->ScalarVisibilityOn();
  return actor;
}

// A small glass-like sphere (for material cases)
vtkSmartPointer<vtkActor> MaterialSphere()
{
  auto actor = whittedtest::Sphere(1.1, 0.45, 0.6, 0.45, 24);
  actor->GetProperty()->SetColor(0.8, 0.5, 0.2);
  actor->GetProperty()->SetSpecular(0.4);
  actor->GetProperty()->SetSpecularPower(30);
  return actor;
}

vtkSmartPointer<vtkActor> BlockOpacityActor(double opacity)
{
  vtkNew<vtkMultiBlockDataSet> mb;
  mb->SetNumberOfBlocks(1);
  mb->SetBlock(0, MakePoly(QuadPoints(), QuadTris));
  auto actor = ActorOf(mb);
  auto* mapper = vtkCompositePolyDataMapper2::SafeDownCast(actor->GetMapper());
  vtkNew<vtkCompositeDataDisplayAttributes> attrs;
  mapper->SetCompositeDataDisplayAttributes(attrs);
  mapper->SetBlockOpacity(1, opacity);
  return actor;
}

struct Case
{
  const char* Name;
  std::function<vtkSmartPointer<vtkActor>()> Bad;
  std::function<vtkSmartPointer<vtkActor>()> Clean; // empty: the reference has no such actor
  std::vector<const char*> Expected;                // one warning per entry, containing it
};

std::vector<Case> Cases()
{
  const double nan = vtkMath::Nan(), inf = vtkMath::Inf();
  std::vector<Case> c;
  auto quad = [] { return ActorOf(MakePoly(QuadPoints(), QuadTris)); };

  // Coordinates -----------------------------------------------------------------------------
  c.push_back({ "NaN point coordinates",
    [=]
    {
      auto pts = QuadPoints();
      pts.push_back({ nan, 0.5, 0.3 });
      pts.push_back({ 1.0, nan, nan });
      return ActorOf(MakePoly(pts, { { 0, 1, 2 }, { 0, 2, 3 }, { 1, 4, 2 }, { 3, 2, 5 } }));
    },
    quad, { "2 of 6 points have NaN or infinite coordinates" } });
  c.push_back({ "infinite point coordinates",
    [=]
    {
      auto pts = QuadPoints();
      pts.push_back({ inf, 0.5, 0.3 });
      pts.push_back({ 1.0, -inf, 0.3 });
      return ActorOf(MakePoly(pts, { { 0, 1, 2 }, { 0, 2, 3 }, { 1, 4, 2 }, { 3, 2, 5 } }));
    },
    quad, { "2 of 6 points have NaN or infinite coordinates" } });
  c.push_back({ "actor matrix with NaN",
    [=]
    {
      auto a = quad();
      a->SetPosition(nan, 0.0, 0.0);
      return a;
    },
    nullptr, { "matrix (Position, Orientation, Scale, Origin, UserMatrix) has NaN" } });
  c.push_back({ "actor with a zero Scale (singular matrix)",
    [=]
    {
      auto a = quad();
      a->SetScale(1.0, 1.0, 0.0);
      return a;
    },
    nullptr, { "its matrix is singular" } });

  // Degenerate and unusual cells (valid VTK: no warning) -----------------------------------
  c.push_back({ "zero-area and zero-length-edge triangles",
    []
    {
      auto pts = QuadPoints();
      pts.push_back({ 1.1, 0.5, 0.3 }); // 4: on the diagonal 0-2, collinear
      return ActorOf(
        MakePoly(pts, { { 0, 1, 2 }, { 0, 2, 3 }, { 0, 4, 2 }, { 1, 1, 3 }, { 2, 2, 2 } }));
    },
    quad, {} });
  c.push_back({ "convex polygon with 6 vertices",
    []
    {
      return ActorOf(MakePoly({ { 0.6, 0.0, 0.3 }, { 1.6, 0.0, 0.3 }, { 1.8, 0.5, 0.3 },
                                { 1.6, 1.0, 0.3 }, { 0.6, 1.0, 0.3 }, { 0.4, 0.5, 0.3 } },
        { { 0, 1, 2, 3, 4, 5 } }));
    },
    []
    {
      return ActorOf(MakePoly({ { 0.6, 0.0, 0.3 }, { 1.6, 0.0, 0.3 }, { 1.8, 0.5, 0.3 },
                                { 1.6, 1.0, 0.3 }, { 0.6, 1.0, 0.3 }, { 0.4, 0.5, 0.3 } },
        { { 0, 1, 2 }, { 0, 2, 3 }, { 0, 3, 4 }, { 0, 4, 5 } }));
    },
    {} });
  c.push_back({ "concave polygon (L shape)",
    []
    {
      return ActorOf(MakePoly({ { 0.6, 0.0, 0.3 }, { 1.6, 0.0, 0.3 }, { 1.6, 0.4, 0.3 },
                                { 1.0, 0.4, 0.3 }, { 1.0, 1.2, 0.3 }, { 0.6, 1.2, 0.3 } },
        { { 0, 1, 2, 3, 4, 5 } }));
    },
    []
    {
      return ActorOf(MakePoly({ { 0.6, 0.0, 0.3 }, { 1.6, 0.0, 0.3 }, { 1.6, 0.4, 0.3 },
                                { 1.0, 0.4, 0.3 }, { 1.0, 1.2, 0.3 }, { 0.6, 1.2, 0.3 } },
        { { 0, 1, 2 }, { 0, 2, 3 }, { 0, 3, 4 }, { 0, 4, 5 } }));
    },
    {} });
  c.push_back({ "triangle strip",
    []
    {
      return ActorOf(MakePoly({ { 0.6, 0.0, 0.3 }, { 0.6, 1.0, 0.3 }, { 1.0, 0.0, 0.3 },
                                { 1.0, 1.0, 0.3 }, { 1.6, 0.0, 0.3 }, { 1.6, 1.0, 0.3 } },
        { { 0, 1, 2, 3, 4, 5 } }, Strips));
    },
    []
    {
      return ActorOf(MakePoly({ { 0.6, 0.0, 0.3 }, { 0.6, 1.0, 0.3 }, { 1.0, 0.0, 0.3 },
                                { 1.0, 1.0, 0.3 }, { 1.6, 0.0, 0.3 }, { 1.6, 1.0, 0.3 } },
        { { 0, 1, 2 }, { 1, 3, 2 }, { 2, 3, 4 }, { 3, 5, 4 } }));
    },
    {} });
  c.push_back({ "NaN float point coordinates, triangles only, 32-bit cells",
    [=]
    {
      auto pts = QuadPoints();
      pts.push_back({ nan, 0.5, 0.3 });
      pts.push_back({ 1.0, nan, nan });
      return ActorOf(
        FloatAnd32Bit(MakePoly(pts, { { 0, 1, 2 }, { 0, 2, 3 }, { 1, 4, 2 }, { 3, 2, 5 } })));
    },
    quad, { "2 of 6 points have NaN or infinite coordinates" } });
  // Triangles only, so the converter first tries the whole connectivity at once, and must then fall
  // back to the cell-by-cell way that skips and counts the bad cells; the reference (a valid
  // triangle mesh) takes the direct way: the same image from both
  c.push_back({ "point ids out of range, triangles only",
    []
    {
      return ActorOf(MakePoly(QuadPoints(), { { 0, 1, 2 }, { 3, 2, 4 }, { 0, 2, 3 }, { 1, 4, 2 } }));
    },
    quad, { "2 cells use point ids outside [0, 4)" } });
  c.push_back({ "point ids out of range, triangles only, float points, 32-bit cells",
    []
    {
      return ActorOf(FloatAnd32Bit(
        MakePoly(QuadPoints(), { { 0, 1, 2 }, { 3, 2, 4 }, { 0, 2, 3 }, { 1, 4, 2 } })));
    },
    quad, { "2 cells use point ids outside [0, 4)" } });
  // Cells of mixed sizes whose ids still add up to three per cell (a quad and a two-point polygon):
  // not a triangle mesh, drawn cell by cell (the two-point polygon draws nothing)
  c.push_back({ "a quad and a two-point polygon",
    [] { return ActorOf(MakePoly(QuadPoints(), { { 0, 1, 2, 3 }, { 0, 2 } })); }, quad, {} });
  c.push_back({ "point ids out of range",
    []
    {
      return ActorOf(
        MakePoly(QuadPoints(), { { 0, 1, 2 }, { 0, 2, 3 }, { 1, 4, 2 }, { 3, 2, 1, 7 } }));
    },
    quad, { "2 cells use point ids outside [0, 4)" } });

  // Empty data (valid: no warning) ----------------------------------------------------------
  c.push_back(
    { "empty polydata", [] { return ActorOf(vtkSmartPointer<vtkPolyData>::New()); }, nullptr, {} });
  c.push_back({ "points but no cells",
    []
    {
      auto poly = MakePoly(QuadPoints(), {});
      return ActorOf(poly);
    },
    nullptr, {} });
  c.push_back({ "multiblock with empty leaves",
    [=]
    {
      vtkNew<vtkMultiBlockDataSet> mb;
      mb->SetNumberOfBlocks(4);
      mb->SetBlock(0, nullptr);
      mb->SetBlock(1, vtkSmartPointer<vtkPolyData>::New());
      vtkNew<vtkMultiBlockDataSet> inner;
      inner->SetNumberOfBlocks(2);
      inner->SetBlock(1, vtkSmartPointer<vtkMultiBlockDataSet>::New());
      mb->SetBlock(2, inner);
      mb->SetBlock(3, MakePoly(QuadPoints(), QuadTris));
      return ActorOf(mb);
    },
    quad, {} });

  // Normals ---------------------------------------------------------------------------------
  c.push_back({ "NaN and infinite normals",
    []
    {
      return ActorOf(NormalGrid(
        [](vtkIdType i, double n[3])
        {
          if (i == 6 || i == 12)
          {
            n[0] = vtkMath::Nan();
          }
          if (i == 18)
          {
            n[2] = vtkMath::Inf();
          }
        }));
    },
    [] { return ActorOf(NormalGrid([](vtkIdType, double*) {})); },
    { "3 normals are NaN, infinite or zero-length" } });
  c.push_back({ "zero-length normals",
    []
    {
      return ActorOf(NormalGrid(
        [](vtkIdType i, double n[3])
        {
          if (i == 7 || i == 0)
          {
            n[0] = n[1] = n[2] = 0.0;
          }
        }));
    },
    [] { return ActorOf(NormalGrid([](vtkIdType, double*) {})); },
    { "2 normals are NaN, infinite or zero-length" } });
  c.push_back({ "normals array shorter than the points",
    []
    {
      auto poly = NormalGrid([](vtkIdType, double*) {});
      poly->GetPointData()->GetNormals()->SetNumberOfTuples(10);
      return ActorOf(poly);
    },
    [] { return ActorOf(NormalGrid([](vtkIdType, double*) {})); },
    { "normals array has fewer tuples" } });

  // Scalars (NaN and out-of-range scalars are valid VTK: mapped to the table's colours) ----
  c.push_back({ "NaN and infinite scalars",
    [=]
    {
      const double v[4] = { nan, inf, -inf, 1.0 };
      return ScalarStrip(v);
    },
    []
    {
      const double v[4] = { 0.0, 1.0, 0.0, 1.0 };
      return ScalarStrip(v);
    },
    {} });
  c.push_back({ "scalars outside the lookup table range",
    []
    {
      const double v[4] = { -5.0, 7.0, 1e300, -1e300 };
      return ScalarStrip(v);
    },
    []
    {
      const double v[4] = { 0.0, 1.0, 1.0, 0.0 };
      return ScalarStrip(v);
    },
    {} });
  c.push_back({ "scalar array shorter than the cells",
    []
    {
      const double v[4] = { 0.0, 1.0, 0.0, 1.0 };
      auto a = ScalarStrip(v);
      vtkPolyData::SafeDownCast(a->GetMapper()->GetInput())
        ->GetCellData()
        ->GetScalars()
        ->SetNumberOfTuples(2);
      return a;
    },
    []
    {
      const double v[4] = { 0.0, 1.0, 0.0, 1.0 };
      auto a = ScalarStrip(v);
      a->GetMapper()->ScalarVisibilityOff();
      return a;
    },
    { "colour array has fewer tuples" } });

  c.push_back({ "5-component unsigned char scalars (direct colours)",
    []
    {
      auto poly = MakePoly(QuadPoints(), QuadTris);
      vtkNew<vtkUnsignedCharArray> rgbax;
      rgbax->SetNumberOfComponents(5);
      for (int i = 0; i < 4; ++i)
      {
        const unsigned char v[5] = { 200, 30, 30, 255, 7 };
        rgbax->InsertNextTypedTuple(v);
      }
      poly->GetPointData()->SetScalars(rgbax);
      return ActorOf(poly); // VTK's own OpenGL mapper crashes on this actor (found by fuzzing)
    },
    []
    {
      auto a = ActorOf(MakePoly(QuadPoints(), QuadTris));
      a->GetMapper()->ScalarVisibilityOff();
      return a;
    },
    { "no 1 to 4 components" } });

  // Point size and line width for spheres and tubes ----------------------------------------
  c.push_back({ "PointSize 0 (set negative) with RenderPointsAsSpheres",
    []
    {
      auto a = ActorOf(MakePoly(QuadPoints(), { { 0 }, { 1 }, { 2 }, { 3 } }, Verts));
      a->GetProperty()->SetRenderPointsAsSpheres(true);
      a->GetProperty()->SetPointSize(-4.0f); // vtkProperty clamps to 0
      return a;
    },
    nullptr, { "PointSize 0" } });
  c.push_back({ "LineWidth 0 with RenderLinesAsTubes",
    []
    {
      auto a = ActorOf(MakePoly(QuadPoints(), { { 0, 1, 2, 3, 0 } }, Lines));
      a->GetProperty()->SetRenderLinesAsTubes(true);
      a->GetProperty()->SetLineWidth(0.0f);
      return a;
    },
    nullptr, { "LineWidth 0" } });
  c.push_back({ "NaN PointSize with RenderPointsAsSpheres",
    []
    {
      auto a = ActorOf(MakePoly(QuadPoints(), { { 0 }, { 1 }, { 2 }, { 3 } }, Verts));
      a->GetProperty()->SetRenderPointsAsSpheres(true);
      a->GetProperty()->SetPointSize(static_cast<float>(vtkMath::Nan()));
      return a;
    },
    nullptr, { "PointSize nan" } });

  // Materials -------------------------------------------------------------------------------
  c.push_back({ "INDEX_OF_REFRACTION <= 0",
    []
    {
      auto a = MaterialSphere();
      SetWhitted(a->GetProperty(), 0.1, 0.6);
      a->GetProperty()->GetInformation()->Set(vtkWhittedMaterialKeys::INDEX_OF_REFRACTION(), -1.5);
      return a;
    },
    []
    {
      auto a = MaterialSphere();
      SetWhitted(a->GetProperty(), 0.1, 0.6, 1.0);
      return a;
    },
    { "INDEX_OF_REFRACTION out of range" } });
  c.push_back({ "INDEX_OF_REFRACTION NaN",
    [=]
    {
      auto a = MaterialSphere();
      SetWhitted(a->GetProperty(), 0.1, 0.6);
      a->GetProperty()->GetInformation()->Set(vtkWhittedMaterialKeys::INDEX_OF_REFRACTION(), nan);
      return a;
    },
    []
    {
      auto a = MaterialSphere();
      SetWhitted(a->GetProperty(), 0.1, 0.6, 1.0);
      return a;
    },
    { "INDEX_OF_REFRACTION out of range" } });
  c.push_back({ "REFLECTANCE above 1, TRANSMITTANCE negative",
    []
    {
      auto a = MaterialSphere();
      SetWhitted(a->GetProperty(), 2.0);
      double kt[3] = { -1.0, 0.5, 0.5 };
      a->GetProperty()->GetInformation()->Set(vtkWhittedMaterialKeys::TRANSMITTANCE(), kt, 3);
      return a;
    },
    []
    {
      // Clamped to kr 1, kt (0, 0.5, 0.5): kr + kt reaches 1.5, so both are scaled by 1/1.5
      auto a = MaterialSphere();
      SetWhitted(a->GetProperty(), 1.0 / 1.5);
      double kt[3] = { 0.0, 0.5 / 1.5, 0.5 / 1.5 };
      a->GetProperty()->GetInformation()->Set(vtkWhittedMaterialKeys::TRANSMITTANCE(), kt, 3);
      return a;
    },
    { "REFLECTANCE, TRANSMITTANCE out of range", "REFLECTANCE + TRANSMITTANCE is above 1" } });
  c.push_back({ "REFLECTANCE + TRANSMITTANCE above 1",
    []
    {
      auto a = MaterialSphere();
      SetWhitted(a->GetProperty(), 0.8, 0.6);
      return a;
    },
    []
    {
      auto a = MaterialSphere();
      SetWhitted(a->GetProperty(), 0.8 / 1.4, 0.6 / 1.4);
      return a;
    },
    { "REFLECTANCE + TRANSMITTANCE is above 1 (largest channel sum 1.4)" } });
  c.push_back({ "negative SpecularPower (vtkProperty clamps it)",
    []
    {
      auto a = MaterialSphere();
      a->GetProperty()->SetSpecularPower(-20.0);
      return a;
    },
    []
    {
      auto a = MaterialSphere();
      a->GetProperty()->SetSpecularPower(0.0);
      return a;
    },
    {} });
  c.push_back({ "NaN SpecularPower",
    [=]
    {
      auto a = MaterialSphere();
      a->GetProperty()->SetSpecularPower(nan);
      return a;
    },
    []
    {
      auto a = MaterialSphere();
      a->GetProperty()->SetSpecularPower(1.0);
      return a;
    },
    { "SpecularPower out of range" } });
  c.push_back({ "NaN Opacity",
    [=]
    {
      auto a = MaterialSphere();
      a->GetProperty()->SetOpacity(nan);
      return a;
    },
    [] { return MaterialSphere(); }, { "Opacity out of range" } });
  c.push_back({ "block opacity above 1", [] { return BlockOpacityActor(3.0); }, quad,
    { "Opacity out of range" } });
  c.push_back({ "NaN colour",
    [=]
    {
      auto a = MaterialSphere();
      a->GetProperty()->SetColor(nan, 0.5, 0.5);
      return a;
    },
    []
    {
      auto a = MaterialSphere();
      a->GetProperty()->SetColor(0.0, 0.5, 0.5);
      return a;
    },
    { "a colour out of range" } });
  return c;
}

struct Outcome
{
  std::vector<unsigned char> Pixels;
  std::vector<std::string> Warnings, Errors;
  int NonFinite = 0;
  std::string Report;
};

Outcome RenderScene(vtkRenderWindow* win, vtkActor* extra)
{
  vtkNew<vtkRenderer> ren;
  win->AddRenderer(ren);
  ren->AddActor(whittedtest::Floor(3.0, 6));
  auto ball = whittedtest::Sphere(-0.8, 0.6, 0.0, 0.6, 24);
  ball->GetProperty()->SetColor(0.9, 0.9, 0.95);
  ball->GetProperty()->SetSpecular(0.5);
  ball->GetProperty()->SetSpecularPower(40);
  ren->AddActor(ball);
  if (extra)
  {
    ren->AddActor(extra);
  }
  whittedtest::AddPointLight(ren, 2.0, 5.0, 4.0);
  ren->SetBackground(0.25, 0.35, 0.5);
  vtkCamera* cam = ren->GetActiveCamera();
  cam->SetPosition(0.5, 2.2, 5.0);
  cam->SetFocalPoint(0.3, 0.5, 0.0);
  cam->SetViewUp(0.0, 1.0, 0.0);
  cam->SetClippingRange(0.5, 30.0);

  vtkNew<vtkWhittedPass> pass;
  ren->SetPass(pass);
  whittedtest::MessageLog log;
  log.Observe(pass);
  win->Render();
  Outcome out;
  out.NonFinite = whittedtest::NonFiniteValues(pass);
  out.Report = pass->GetLastFrameReport();
  win->Render(); // the second frame must not warn again
  out.NonFinite = std::max(out.NonFinite, whittedtest::NonFiniteValues(pass));
  out.Pixels = whittedtest::GrabPixels(win);
  out.Warnings = log.Warnings;
  out.Errors = log.Errors;
  win->RemoveRenderer(ren);
  return out;
}
}

int TestWhittedBadInputCases(int, char*[])
{
  auto win = whittedtest::MakeWindow(160, 120);
  bool ok = true;
  int cases = 0, warnings = 0;
  for (const Case& c : Cases())
  {
    ++cases;
    vtkSmartPointer<vtkActor> bad = c.Bad();
    std::ostringstream name;
    name << "Actor " << static_cast<void*>(bad.Get()) << " (" << bad->GetClassName() << ")";
    const Outcome got = RenderScene(win, bad);
    vtkSmartPointer<vtkActor> clean = c.Clean ? c.Clean() : nullptr;
    const Outcome ref = RenderScene(win, clean);
    const int diff = whittedtest::DifferingPixels(ref.Pixels, got.Pixels, 1);
    const int diffAny = whittedtest::DifferingPixels(ref.Pixels, got.Pixels, 0);

    bool caseOk = got.NonFinite == 0 && got.Errors.empty() && diff == 0 &&
      got.Warnings.size() == c.Expected.size() && ref.Warnings.empty() && ref.Errors.empty();
    for (size_t i = 0; caseOk && i < c.Expected.size(); ++i)
    {
      bool found = false;
      for (const std::string& w : got.Warnings)
      {
        found |=
          w.find(c.Expected[i]) != std::string::npos && w.find(name.str()) != std::string::npos;
      }
      caseOk &= found;
    }
    warnings += static_cast<int>(got.Warnings.size());
    std::printf("[bad input] %-55s warnings %zu (expected %zu), errors %zu, non-finite values %d, "
                "pixels differing from the reference: %d (>1/255: %d)%s\n",
      c.Name, got.Warnings.size(), c.Expected.size(), got.Errors.size(), got.NonFinite, diffAny,
      diff, caseOk ? "" : "  FAILED");
    if (!caseOk)
    {
      for (const std::string& w : got.Warnings)
      {
        std::printf("    warning: %s", w.c_str());
      }
      for (const std::string& e : got.Errors)
      {
        std::printf("    error: %s", e.c_str());
      }
      std::printf("    report: %s", got.Report.c_str());
    }
    else
    {
      for (const std::string& w : got.Warnings)
      {
        const size_t at = w.find("Actor ");
        std::printf("    %s", at == std::string::npos ? w.c_str() : w.c_str() + at);
      }
    }
    ok &= caseOk;
  }
  std::printf(
    "[bad input] %d cases, %d warnings in total (each once over two frames)\n", cases, warnings);
  return ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
