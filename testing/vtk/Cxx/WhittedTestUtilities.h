// Small helpers shared by the vtkWhittedPass tests: scene pieces built from VTK sources.
#ifndef WhittedTestUtilities_h
#define WhittedTestUtilities_h

#include "vtkActor.h"
#include "vtkCallbackCommand.h"
#include "vtkCamera.h"
#include "vtkCellData.h"
#include "vtkCommand.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkLight.h"
#include "vtkNew.h"
#include "vtkPlaneSource.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"
#include "vtkSphereSource.h"
#include "vtkUnsignedCharArray.h"
#include "vtkWhittedClassicScene.h"
#include "vtkWhittedFrameStatistics.h"
#include "vtkWhittedPass.h"
#include "vtkWindowToImageFilter.h"

#include <array>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

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

/// A positional scene light shining in every direction (cone 180 degrees) from (x, y, z).
inline void AddPointLight(vtkRenderer* ren, double x, double y, double z)
{
  vtkNew<vtkLight> light;
  light->SetLightTypeToSceneLight();
  light->SetPositional(true);
  light->SetPosition(x, y, z);
  light->SetConeAngle(180.0);
  ren->AddLight(light);
}

/// Perspective camera at eye looking at focal point, +y up, with the given view angle; clipping
/// range reset.
inline void LookAt(vtkRenderer* ren, const std::array<double, 3>& eye,
  const std::array<double, 3>& focal, double viewAngle)
{
  vtkCamera* cam = ren->GetActiveCamera();
  cam->SetPosition(eye.data());
  cam->SetFocalPoint(focal.data());
  cam->SetViewUp(0.0, 1.0, 0.0);
  cam->SetViewAngle(viewAngle);
  ren->ResetCameraClippingRange();
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
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  vtkWhittedClassicScene::MakeCheckerboard(poly, o, p1, p2, nx, ny, c0, c1);
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

/// The window's RGB pixels after the last render (rows bottom to top), without rendering again.
inline std::vector<unsigned char> GrabPixels(vtkRenderWindow* win)
{
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(win);
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->ShouldRerenderOff();
  grab->Update();
  vtkDataArray* a = grab->GetOutput()->GetPointData()->GetScalars();
  auto* p = static_cast<unsigned char*>(a->GetVoidPointer(0));
  return std::vector<unsigned char>(p, p + a->GetNumberOfValues());
}

/// Pixels (RGB triples) whose colour differs by more than tol 8-bit steps in any channel.
inline int DifferingPixels(
  const std::vector<unsigned char>& a, const std::vector<unsigned char>& b, int tol)
{
  if (a.size() != b.size())
  {
    return static_cast<int>(std::max(a.size(), b.size()) / 3);
  }
  int n = 0;
  for (size_t i = 0; i + 2 < a.size(); i += 3)
  {
    for (int c = 0; c < 3; ++c)
    {
      if (std::abs(int(a[i + c]) - int(b[i + c])) > tol)
      {
        ++n;
        break;
      }
    }
  }
  return n;
}

/// Values of the pass's last traced frame (colour and depth) that are NaN or infinite, plus what
/// the tracer's safety nets caught in that frame; -1 if the pass kept no frame.
inline int NonFiniteValues(vtkWhittedPass* pass)
{
  vtkNew<vtkFloatArray> rgba;
  vtkNew<vtkFloatArray> depth;
  pass->GetLastFrame(rgba, depth);
  if (rgba->GetNumberOfTuples() == 0)
  {
    return -1;
  }
  // What the tracer's safety nets caught (and zeroed or clamped) counts too: otherwise the nets
  // would hide from this check the very values it looks for
  int n = static_cast<int>(pass->GetLastFrameStatistics()->GetNumberOfSafetyNetCatches());
  for (vtkFloatArray* a : { rgba.Get(), depth.Get() })
  {
    for (vtkIdType i = 0; i < a->GetNumberOfValues(); ++i)
    {
      n += std::isfinite(a->GetValue(i)) ? 0 : 1;
    }
  }
  return n;
}

/// Collects the warning and error messages an object emits (vtkWarningMacro / vtkErrorMacro).
class MessageLog
{
public:
  MessageLog()
  {
    this->Callback->SetCallback(&MessageLog::OnEvent);
    this->Callback->SetClientData(this);
  }
  void Observe(vtkObject* o)
  {
    o->AddObserver(vtkCommand::WarningEvent, this->Callback);
    o->AddObserver(vtkCommand::ErrorEvent, this->Callback);
  }
  std::vector<std::string> Warnings, Errors;

private:
  static void OnEvent(vtkObject*, unsigned long event, void* clientData, void* callData)
  {
    auto* self = static_cast<MessageLog*>(clientData);
    const std::string text = callData ? static_cast<const char*>(callData) : "";
    (event == vtkCommand::ErrorEvent ? self->Errors : self->Warnings).push_back(text);
  }
  vtkNew<vtkCallbackCommand> Callback;
};

} // namespace whittedtest

#endif
