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
#include "vtkLightCollection.h"
#include "vtkPNGReader.h"
#include "vtkPlaneSource.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkRegressionTestImage.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkRendererCollection.h"
#include "vtkSmartPointer.h"
#include "vtkSphereSource.h"
#include "vtkUnsignedCharArray.h"
#include "vtkWhittedClassicScene.h"
#include "vtkWhittedFrameStatistics.h"
#include "vtkWhittedMaterialKeys.h"
#include "vtkWhittedPass.h"
#include "vtkWindowToImageFilter.h"

#include <iostream>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <map>
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
    p->GetInformation()->Set(vtkWhittedMaterialKeys::REFLECTANCE(), &kr, 1);
  }
  if (kt >= 0.0)
  {
    p->GetInformation()->Set(vtkWhittedMaterialKeys::TRANSMITTANCE(), &kt, 1);
  }
  if (ior > 0.0)
  {
    p->GetInformation()->Set(vtkWhittedMaterialKeys::INDEX_OF_REFRACTION(), ior);
  }
}

inline void SetTransmittance(vtkProperty* p, double r, double g, double b)
{
  double kt[3] = { r, g, b };
  p->GetInformation()->Set(vtkWhittedMaterialKeys::TRANSMITTANCE(), kt, 3);
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

/// The negative control's switch (testing/vtk/CMakeLists.txt, *.PerturbedShadingFails): with the
/// environment variable WHITTED_TEST_PERTURB_SHADING set, the pass draws 1% of its pixels off by
/// 10/255 (vtkWhittedPass::SetShadingErrorForTesting), and the image checks must fail.
inline void ApplyTestSwitches(vtkWhittedPass* pass)
{
  if (std::getenv("WHITTED_TEST_PERTURB_SHADING"))
  {
    std::cout << "[switch] vtkWhittedPass::ShadingErrorForTesting 10\n";
    pass->SetShadingErrorForTesting(10);
  }
}

/// Largest channel difference per pixel of two RGB images of the same size.
inline std::vector<int> ChannelDifference(
  const std::vector<unsigned char>& a, const std::vector<unsigned char>& b)
{
  std::vector<int> d(a.size() / 3, 255);
  for (size_t i = 0; i < d.size() && 3 * i + 2 < b.size(); ++i)
  {
    int m = 0;
    for (int c = 0; c < 3; ++c)
    {
      m = std::max(m, std::abs(int(a[3 * i + c]) - int(b[3 * i + c])));
    }
    d[i] = m;
  }
  return d;
}

/// Tolerance of the direct baseline check: a pixel counts as changed if a channel differs by
/// more than kBaselinePixelTolerance 8-bit steps, and at most kBaselineChangedShare of the image
/// may change. Measured on llvmpipe (Debian 12): every image test differs from its baseline by 0
/// pixels. VTK's own comparison (vtkImageDifference, threshold 105 per pixel summed over the
/// channels, neighbourhood averaging) passes a 29/255 change of 1% of the pixels; this does not:
/// a 10/255 change of 0.1% of the pixels fails.
constexpr int kBaselinePixelTolerance = 3;
constexpr double kBaselineChangedShare = 0.0005;

/// The image test's regression check: VTK's comparison with the -V baseline
/// (vtkRegressionTestImage: writes the test and difference images to -T on failure), then a direct
/// count of the pixels that differ from the baseline by more than kBaselinePixelTolerance.
/// Returns EXIT_SUCCESS or EXIT_FAILURE.
inline int CheckBaseline(vtkRenderWindow* win, int argc, char* argv[])
{
  const std::vector<unsigned char> image = GrabPixels(win);
  int* size = win->GetSize();
  const int retVal = vtkRegressionTestImage(win);
  if (retVal == vtkTesting::FAILED)
  {
    return EXIT_FAILURE;
  }
  vtkNew<vtkTesting> testing;
  for (int i = 0; i < argc; ++i)
  {
    testing->AddArgument(argv[i]);
  }
  if (!testing->IsValidImageSpecified())
  {
    return retVal == vtkTesting::PASSED ? EXIT_SUCCESS : EXIT_FAILURE;
  }
  vtkNew<vtkPNGReader> reader;
  reader->SetFileName(testing->GetValidImageFileName());
  reader->Update();
  vtkImageData* png = reader->GetOutput();
  int dims[3];
  png->GetDimensions(dims);
  const int nc = png->GetNumberOfScalarComponents();
  std::vector<unsigned char> baseline;
  if (dims[0] == size[0] && dims[1] == size[1] && nc >= 3)
  {
    auto* p = static_cast<unsigned char*>(png->GetScalarPointer());
    for (int i = 0; i < dims[0] * dims[1]; ++i)
    {
      baseline.insert(baseline.end(), p + nc * i, p + nc * i + 3);
    }
  }
  const std::vector<int> d = ChannelDifference(image, baseline);
  const int changed = static_cast<int>(
    std::count_if(d.begin(), d.end(), [](int v) { return v > kBaselinePixelTolerance; }));
  const int worst = d.empty() ? 255 : *std::max_element(d.begin(), d.end());
  const int allowed = static_cast<int>(kBaselineChangedShare * size[0] * size[1]);
  std::printf("[baseline] %d of %d pixels differ from the baseline by more than %d/255 (allowed "
              "%d), largest difference %d/255\n",
    changed, size[0] * size[1], kBaselinePixelTolerance, allowed, worst);
  if (baseline.empty() || changed > allowed)
  {
    std::printf("Baseline pixel check failed: %d pixels differ by more than %d/255 (allowed %d)\n",
      changed, kBaselinePixelTolerance, allowed);
    return EXIT_FAILURE;
  }
  return EXIT_SUCCESS;
}

/// What CheckAgainstRaster compares, and what it asks of the shadows.
struct RasterOracle
{
  /// Props left out of the comparison (their pixels, grown by one): those whose traced look VTK's
  /// raster cannot show (Whitted keys, Opacity < 1, points as spheres, lines as tubes).
  std::vector<vtkProp*> Excluded;
  /// Optional: hides (true) or shows again (false) further excluded parts, e.g. composite blocks.
  std::function<void(bool)> Hide;
  /// Shadows: at least this share of the compared pixels must be darker (by more than 8/255 in
  /// some channel) with the tracer's effects on than off.
  double MinShadowShare = 0.0;
  /// Of those shadow pixels, at least this share must show exactly the ambient term (VTK's image
  /// with every light at intensity 0, within 3/255): full shadow of an opaque occluder.
  double MinUmbraShare = 0.0;
};

/// Full-window RGB and depth after the last render, without rendering again.
inline void GrabWithDepth(
  vtkRenderWindow* win, std::vector<unsigned char>& rgb, std::vector<float>& depth)
{
  rgb = GrabPixels(win);
  int* size = win->GetSize();
  depth.resize(static_cast<size_t>(size[0]) * size[1]);
  win->GetZbufferData(0, 0, size[0] - 1, size[1] - 1, depth.data());
}

/// Independent oracle of an image test: VTK's own OpenGL image of the same scene.
/// - Local shading: with shadows, reflections and refractions off, the traced image equals VTK's
///   image of the same renderers (no pass) at every pixel not covered by an excluded prop (and
///   not next to one): more than 3/255 off at most 0.2% of them, more than 1/255 at most 1%
///   (float shader versus double tracer: +-1; a pixel centre on a shared edge may pick the other
///   triangle) -- the agreement tests' tolerances.
/// - Shadows: at those pixels the effects can only remove light, and never more than all of it:
///   with effects on, every channel lies between VTK's ambient-only image (all lights at intensity
///   0) and the traced image without effects, within 2/255 (at most 0.2% of the pixels outside);
///   shadows exist (MinShadowShare) and an opaque occluder's umbra is exactly the ambient term
///   (MinUmbraShare).
/// The window must just have been rendered with the pass (the image under test). Every renderer
/// of the window that uses the pass is switched to VTK's raster for the reference images; all is
/// restored and rendered again before returning. Returns true if every check holds.
inline bool CheckAgainstRaster(
  const char* name, vtkRenderWindow* win, vtkWhittedPass* pass, const RasterOracle& o)
{
  std::vector<unsigned char> traced, plain, gl, glRest, ambient;
  std::vector<float> zGl, zRest, zIgnored;
  traced = GrabPixels(win);

  // Traced, effects off
  const bool shadows = pass->GetShadows(), reflections = pass->GetReflections(),
             refractions = pass->GetRefractions();
  pass->SetShadows(false);
  pass->SetReflections(false);
  pass->SetRefractions(false);
  win->Render();
  plain = GrabPixels(win);
  pass->SetShadows(shadows);
  pass->SetReflections(reflections);
  pass->SetRefractions(refractions);

  // VTK's raster: as is, without the excluded props, with every light at intensity 0
  std::vector<vtkRenderer*> renderers;
  vtkRendererCollection* rc = win->GetRenderers();
  rc->InitTraversal();
  while (vtkRenderer* ren = rc->GetNextItem())
  {
    if (ren->GetPass() == pass)
    {
      renderers.push_back(ren);
      ren->SetPass(nullptr);
    }
  }
  win->Render();
  GrabWithDepth(win, gl, zGl);
  std::vector<int> visibility;
  for (vtkProp* p : o.Excluded)
  {
    visibility.push_back(p->GetVisibility());
    p->SetVisibility(false);
  }
  if (o.Hide)
  {
    o.Hide(true);
  }
  win->Render();
  GrabWithDepth(win, glRest, zRest);
  for (size_t i = 0; i < o.Excluded.size(); ++i)
  {
    o.Excluded[i]->SetVisibility(visibility[i]);
  }
  if (o.Hide)
  {
    o.Hide(false);
  }
  std::map<vtkLight*, double> intensity;
  for (vtkRenderer* ren : renderers)
  {
    vtkLightCollection* lights = ren->GetLights();
    lights->InitTraversal();
    while (vtkLight* light = lights->GetNextItem())
    {
      intensity[light] = light->GetIntensity();
      light->SetIntensity(0.0);
    }
  }
  win->Render();
  ambient = GrabPixels(win);
  for (const auto& li : intensity)
  {
    li.first->SetIntensity(li.second);
  }
  for (vtkRenderer* ren : renderers)
  {
    ren->SetPass(pass);
  }
  win->Render();

  // Compared pixels: a surface in VTK's image, not covered by an excluded prop, nor next to one
  int* size = win->GetSize();
  const int w = size[0], h = size[1];
  std::vector<char> covered(static_cast<size_t>(w) * h, 0);
  for (int i = 0; i < w * h; ++i)
  {
    covered[i] = zGl[i] != zRest[i] || gl[3 * i] != glRest[3 * i] ||
      gl[3 * i + 1] != glRest[3 * i + 1] || gl[3 * i + 2] != glRest[3 * i + 2];
  }
  std::vector<int> compared;
  for (int y = 0; y < h; ++y)
  {
    for (int x = 0; x < w; ++x)
    {
      bool near = zGl[y * w + x] >= 1.0f;
      for (int dy = -1; dy <= 1 && !near; ++dy)
      {
        for (int dx = -1; dx <= 1 && !near; ++dx)
        {
          const int xx = std::min(std::max(x + dx, 0), w - 1), yy = std::min(std::max(y + dy, 0), h - 1);
          near = covered[yy * w + xx] != 0;
        }
      }
      if (!near)
      {
        compared.push_back(y * w + x);
      }
    }
  }
  const double n = std::max<size_t>(1, compared.size());
  int over1 = 0, over3 = 0, outside = 0, shadow = 0, umbra = 0;
  for (int i : compared)
  {
    int d = 0, dAmbient = 0, darker = 0;
    bool inside = true;
    for (int c = 0; c < 3; ++c)
    {
      const int t = traced[3 * i + c], p = plain[3 * i + c], g = gl[3 * i + c], a = ambient[3 * i + c];
      d = std::max(d, std::abs(p - g));
      dAmbient = std::max(dAmbient, std::abs(t - a));
      darker = std::max(darker, p - t);
      inside &= t <= p + 2 && t >= a - 2;
    }
    over1 += d > 1;
    over3 += d > 3;
    outside += !inside;
    if (darker > 8)
    {
      ++shadow;
      umbra += dAmbient <= 3;
    }
  }
  const double shadowShare = shadow / n, umbraShare = double(umbra) / std::max(1, shadow);
  const bool ok = compared.size() > static_cast<size_t>(w * h / 20) && over3 / n <= 0.002 &&
    over1 / n <= 0.01 && outside / n <= 0.002 && shadowShare >= o.MinShadowShare &&
    umbraShare >= o.MinUmbraShare;
  std::printf("[raster] %s: %zu pixels compared (%.1f%% of the image); effects off vs VTK: >1/255 "
              "%.3f%%, >3/255 %.3f%% (allowed 1%%, 0.2%%); effects on outside [ambient, effects "
              "off] by >2/255: %.3f%% (allowed 0.2%%); shadow pixels %.2f%% (at least %.2f%%), of "
              "them umbra = ambient term %.1f%% (at least %.1f%%): %s\n",
    name, compared.size(), 100.0 * compared.size() / (w * h), 100 * over1 / n, 100 * over3 / n,
    100 * outside / n, 100 * shadowShare, 100 * o.MinShadowShare, 100 * umbraShare,
    100 * o.MinUmbraShare, ok ? "ok" : "FAILED");
  return ok;
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
