// Small helpers shared by the vtkWhittedPass tests: scene pieces built from VTK sources.
#ifndef WhittedTestUtilities_h
#define WhittedTestUtilities_h

#include "vtkActor.h"
#include "vtkCellData.h"
#include "vtkInformation.h"
#include "vtkNew.h"
#include "vtkPlaneSource.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"
#include "vtkSphereSource.h"
#include "vtkUnsignedCharArray.h"
#include "vtkWhittedPass.h"

#include <cmath>

namespace whittedtest
{

/// Offscreen window without multisampling (tests compare exact pixels).
inline vtkSmartPointer<vtkRenderWindow> MakeWindow(int w, int h)
{
  auto win = vtkSmartPointer<vtkRenderWindow>::New();
  win->SetMultiSamples(0);
  win->SetSize(w, h);
  win->SetOffScreenRendering(1);
  return win;
}

/// Whitted keys on a property; negative values leave a key unset.
inline void SetWhitted(vtkProperty* p, double kr, double kt = -1.0, double ior = -1.0)
{
  if (kr >= 0.0)
  {
    p->GetInformation()->Set(vtkWhittedPass::REFLECTANCE(), &kr, 1);
  }
  if (kt >= 0.0)
  {
    p->GetInformation()->Set(vtkWhittedPass::TRANSMITTANCE(), &kt, 1);
  }
  if (ior > 0.0)
  {
    p->GetInformation()->Set(vtkWhittedPass::INDEX_OF_REFRACTION(), ior);
  }
}

inline void SetTransmittance(vtkProperty* p, double r, double g, double b)
{
  double kt[3] = { r, g, b };
  p->GetInformation()->Set(vtkWhittedPass::TRANSMITTANCE(), kt, 3);
}

/// A plane whose cells alternate between two RGB colours (direct unsigned-char cell scalars).
inline vtkSmartPointer<vtkPolyData> Checkerboard(const double o[3], const double p1[3],
  const double p2[3], int nx, int ny, const double c0[3], const double c1[3])
{
  vtkNew<vtkPlaneSource> plane;
  plane->SetOrigin(o[0], o[1], o[2]);
  plane->SetPoint1(p1[0], p1[1], p1[2]);
  plane->SetPoint2(p2[0], p2[1], p2[2]);
  plane->SetResolution(nx, ny);
  plane->Update();
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->DeepCopy(plane->GetOutput());
  vtkNew<vtkUnsignedCharArray> colors;
  colors->SetName("checker");
  colors->SetNumberOfComponents(3);
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      const double* c = ((i + j) % 2 == 0) ? c0 : c1;
      colors->InsertNextTuple3(
        std::round(255 * c[0]), std::round(255 * c[1]), std::round(255 * c[2]));
    }
  }
  poly->GetCellData()->SetScalars(colors);
  return poly;
}

/// Actor of a checkerboard floor in the plane y = height, centred on the origin.
inline vtkSmartPointer<vtkActor> Floor(double size, int n, double height = 0.0)
{
  const double o[3] = { -size, height, size };
  const double p1[3] = { size, height, size };
  const double p2[3] = { -size, height, -size };
  const double c0[3] = { 0.9, 0.9, 0.9 };
  const double c1[3] = { 0.45, 0.45, 0.5 };
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(Checkerboard(o, p1, p2, n, n, c0, c1));
  mapper->SetScalarModeToUseCellData();
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  actor->GetProperty()->SetAmbient(0.2);
  actor->GetProperty()->SetDiffuse(0.8);
  return actor;
}

/// Sphere actor from vtkSphereSource (point normals).
inline vtkSmartPointer<vtkActor> Sphere(double x, double y, double z, double r, int res = 32)
{
  vtkNew<vtkSphereSource> source;
  source->SetCenter(x, y, z);
  source->SetRadius(r);
  source->SetThetaResolution(2 * res);
  source->SetPhiResolution(res);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputConnection(source->GetOutputPort());
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  return actor;
}

} // namespace whittedtest

#endif
