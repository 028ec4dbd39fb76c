#include "vtkWhittedClassicScene.h"

#include "vtkWhittedMaterialKeys.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkCellData.h"
#include "vtkInformation.h"
#include "vtkLight.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPlaneSource.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"
#include "vtkSphereSource.h"
#include "vtkUnsignedCharArray.h"

#include "scenes/scenes.h"

#include <cmath>

vtkStandardNewMacro(vtkWhittedClassicScene);

struct vtkWhittedClassicScene::vtkInternals
{
  vtkSmartPointer<vtkActor> Floor, Mirror, Glass;
  vtkSmartPointer<vtkLight> Light;
};

namespace
{
using Description = whitted::ClassicSceneDescription;

vtkSmartPointer<vtkActor> FloorActor(const Description::Floor& f)
{
  vtkNew<vtkPolyData> poly;
  const double color0[3] = { f.color0.x, f.color0.y, f.color0.z };
  const double color1[3] = { f.color1.x, f.color1.y, f.color1.z };
  vtkWhittedClassicScene::MakeCheckerboard(
    poly, &f.origin.x, &f.point1.x, &f.point2.x, f.cellsX, f.cellsY, color0, color1);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(poly);
  mapper->SetScalarModeToUseCellData();
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  actor->GetProperty()->SetAmbient(f.ambient);
  actor->GetProperty()->SetDiffuse(f.diffuse);
  return actor;
}

vtkSmartPointer<vtkActor> BallActor(const Description::Ball& b, int resolution)
{
  // Geometry: a UV sphere (point normals)
  vtkNew<vtkSphereSource> source;
  source->SetCenter(b.center.x, b.center.y, b.center.z);
  source->SetRadius(b.radius);
  source->SetThetaResolution(2 * resolution);
  source->SetPhiResolution(resolution);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputConnection(source->GetOutputPort());
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);

  // Material: VTK's coefficients, then the Whitted keys (kt and IOR only on a transmissive ball)
  vtkProperty* p = actor->GetProperty();
  p->SetColor(b.color.x, b.color.y, b.color.z);
  p->SetAmbient(b.ambient);
  p->SetDiffuse(b.diffuse);
  p->SetSpecular(b.specular);
  p->SetSpecularPower(b.specularPower);
  vtkInformation* info = p->GetInformation();
  info->Set(vtkWhittedMaterialKeys::REFLECTANCE(), &b.reflectance, 1);
  if (b.transmittance > 0.0)
  {
    info->Set(vtkWhittedMaterialKeys::TRANSMITTANCE(), &b.transmittance, 1);
    info->Set(vtkWhittedMaterialKeys::INDEX_OF_REFRACTION(), b.ior);
  }
  return actor;
}
} // namespace

//------------------------------------------------------------------------------
vtkWhittedClassicScene::vtkWhittedClassicScene()
  : Internals(new vtkInternals)
{
}

//------------------------------------------------------------------------------
vtkWhittedClassicScene::~vtkWhittedClassicScene()
{
  delete this->Internals;
}

//------------------------------------------------------------------------------
void vtkWhittedClassicScene::AddToRenderer(vtkRenderer* renderer)
{
  const Description& d = whitted::classicSceneDescription();
  vtkInternals& in = *this->Internals;

  // Actors: floor, mirror, glass
  in.Floor = FloorActor(d.floor);
  in.Mirror = BallActor(d.mirror, this->Resolution);
  in.Glass = BallActor(d.glass, this->Resolution);
  for (vtkActor* actor : { in.Floor.Get(), in.Mirror.Get(), in.Glass.Get() })
  {
    renderer->AddActor(actor);
  }

  // A positional scene light shining in every direction
  in.Light = vtkSmartPointer<vtkLight>::New();
  in.Light->SetLightTypeToSceneLight();
  in.Light->SetPositional(true);
  in.Light->SetPosition(d.lightPosition.x, d.lightPosition.y, d.lightPosition.z);
  in.Light->SetFocalPoint(0.0, 0.0, 0.0);
  in.Light->SetConeAngle(180.0);
  renderer->AddLight(in.Light);
  renderer->SetBackground(d.background.x, d.background.y, d.background.z);

  // Camera
  vtkCamera* cam = renderer->GetActiveCamera();
  cam->SetPosition(d.camera.eye.x, d.camera.eye.y, d.camera.eye.z);
  cam->SetFocalPoint(d.camera.focal.x, d.camera.focal.y, d.camera.focal.z);
  cam->SetViewUp(d.camera.up.x, d.camera.up.y, d.camera.up.z);
  cam->SetViewAngle(d.camera.viewAngle);
  renderer->ResetCameraClippingRange();
  this->Modified();
}

//------------------------------------------------------------------------------
vtkActor* vtkWhittedClassicScene::GetFloor()
{
  return this->Internals->Floor;
}
vtkActor* vtkWhittedClassicScene::GetMirror()
{
  return this->Internals->Mirror;
}
vtkActor* vtkWhittedClassicScene::GetGlass()
{
  return this->Internals->Glass;
}
vtkLight* vtkWhittedClassicScene::GetLight()
{
  return this->Internals->Light;
}

//------------------------------------------------------------------------------
void vtkWhittedClassicScene::MakeCheckerboard(vtkPolyData* output, const double origin[3],
  const double point1[3], const double point2[3], int nx, int ny, const double color0[3],
  const double color1[3])
{
  vtkNew<vtkPlaneSource> plane;
  plane->SetOrigin(origin[0], origin[1], origin[2]);
  plane->SetPoint1(point1[0], point1[1], point1[2]);
  plane->SetPoint2(point2[0], point2[1], point2[2]);
  plane->SetResolution(nx, ny);
  plane->Update();
  output->DeepCopy(plane->GetOutput());
  vtkNew<vtkUnsignedCharArray> colors;
  colors->SetName("checker");
  colors->SetNumberOfComponents(3);
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      const double* c = ((i + j) % 2 == 0) ? color0 : color1;
      colors->InsertNextTuple3(
        std::round(255 * c[0]), std::round(255 * c[1]), std::round(255 * c[2]));
    }
  }
  output->GetCellData()->SetScalars(colors);
}

//------------------------------------------------------------------------------
void vtkWhittedClassicScene::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Resolution: " << this->Resolution << "\n";
}
