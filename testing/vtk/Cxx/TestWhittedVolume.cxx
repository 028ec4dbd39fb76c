// Volumes traced by vtkWhittedPass (vtkWhittedVolumeConverter + the core's emission-absorption
// march). Independent references only:
//  1. Agreement with VTK's own vtkGPUVolumeRayCastMapper (the same scene drawn without the pass, at
//     the same sample distance; shadows, reflections, refractions off): MAE over covered pixels
//     <= 1/255 (issue 29 asks 3/255; measured at most 0.17/255), for a soft blob alone and for the
//     blob with an opaque (ambient-only) sphere inside.
//     The volume must be traced (no OpenGL prop left): OpenGL drawing it would agree trivially.
//     Then edits, each against VTK again: a transfer-function edit (no grid conversion, one
//     transfer update), new scalars (one conversion), the volume moved / rotated / scaled, an image
//     direction matrix.
//  2. A 45-degree mirror shows the volume: under a parallel camera, the mirror's pixel (i, j) equals
//     pixel (W-1-i, j) of the volume seen directly along the reflected direction (no mirror):
//     MAE <= 1/255 over covered pixels, and the mirror must show the volume (covered pixels).
//  3. A floor under a dense constant slab (opacity a per unit distance u, thickness t) lit from
//     straight above by a directional light: shadowed / lit = (1-a)^(t/u) = exp(-sigma t), sigma =
//     -ln(1-a)/u, within 1e-3 (the tracer's float frame).
//  4. Bad input (NaN scalars, zero spacing, a single point along an axis, an empty image): one
//     warning naming the problem, the rest of the scene as without the volume (within 1/255; NaN
//     scalars are traced as transparent), no NaN or infinite value in the frame, no error.
//  5. MIP blend: left to OpenGL with one warning naming the setting (Shade and gradient opacity are
//     traced: TestWhittedPythonVolumeShade).
#include "WhittedTestUtilities.h"

#include "vtkColorTransferFunction.h"
#include "vtkFloatArray.h"
#include "vtkGPUVolumeRayCastMapper.h"
#include "vtkPiecewiseFunction.h"
#include "vtkSOADataArrayTemplate.h"
#include "vtkSmartVolumeMapper.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <cmath>
#include <cstdio>
#include <limits>

namespace
{
using namespace whittedtest;

// A soft blob: scalar 1 - |p - c| / r (clamped at 0) on an n^3 float grid of the given spacing
// centred on c; point indices from first (an extent not starting at 0 puts the origin elsewhere)
vtkSmartPointer<vtkImageData> Blob(int n, double spacing, const double c[3], int first = 0)
{
  auto img = vtkSmartPointer<vtkImageData>::New();
  img->SetExtent(first, first + n - 1, first, first + n - 1, first, first + n - 1);
  img->SetSpacing(spacing, spacing, spacing);
  const double half = 0.5 * spacing * (n - 1) + spacing * first;
  img->SetOrigin(c[0] - half, c[1] - half, c[2] - half);
  img->AllocateScalars(VTK_FLOAT, 1);
  auto* s = static_cast<float*>(img->GetScalarPointer());
  for (int k = 0; k < n; ++k)
  {
    for (int j = 0; j < n; ++j)
    {
      for (int i = 0; i < n; ++i)
      {
        const double x = (i - 0.5 * (n - 1)) / (0.5 * (n - 1)), y = (j - 0.5 * (n - 1)) / (0.5 * (n - 1)),
                     z = (k - 0.5 * (n - 1)) / (0.5 * (n - 1));
        *s++ = static_cast<float>(std::max(0.0, 1.0 - std::sqrt(x * x + y * y + z * z)));
      }
    }
  }
  return img;
}

vtkSmartPointer<vtkVolume> MakeVolume(vtkImageData* img, double sampleDistance = 0.0)
{
  vtkNew<vtkGPUVolumeRayCastMapper> mapper;
  mapper->SetInputData(img);
  if (sampleDistance > 0.0)
  {
    mapper->AutoAdjustSampleDistancesOff();
    mapper->SetSampleDistance(static_cast<float>(sampleDistance));
  }
  vtkNew<vtkColorTransferFunction> ctf;
  ctf->AddRGBPoint(0.0, 0.1, 0.2, 0.9);
  ctf->AddRGBPoint(0.5, 0.9, 0.4, 0.1);
  ctf->AddRGBPoint(1.0, 1.0, 1.0, 0.8);
  vtkNew<vtkPiecewiseFunction> otf;
  otf->AddPoint(0.0, 0.0);
  otf->AddPoint(0.15, 0.02);
  otf->AddPoint(1.0, 0.5);
  vtkNew<vtkVolumeProperty> vp;
  vp->SetColor(ctf);
  vp->SetScalarOpacity(otf);
  vp->SetScalarOpacityUnitDistance(0.1);
  vp->SetInterpolationTypeToLinear();
  auto volume = vtkSmartPointer<vtkVolume>::New();
  volume->SetMapper(mapper);
  volume->SetProperty(vp);
  return volume;
}

vtkSmartPointer<vtkWhittedPass> MakePass()
{
  auto pass = vtkSmartPointer<vtkWhittedPass>::New();
  pass->SetShadows(false);
  pass->SetReflections(false);
  pass->SetRefractions(false);
  ApplyTestSwitches(pass);
  return pass;
}

// Mean absolute channel difference (8-bit steps) over the pixels where either image differs from
// the background colour bg by more than 1 step; covered gets their number
double CoveredMAE(const std::vector<unsigned char>& a, const std::vector<unsigned char>& b,
  const unsigned char bg[3], int& covered)
{
  double sum = 0.0;
  covered = 0;
  for (size_t i = 0; i + 2 < a.size() && i + 2 < b.size(); i += 3)
  {
    bool cov = false;
    for (int c = 0; c < 3; ++c)
    {
      cov = cov || std::abs(int(a[i + c]) - bg[c]) > 1 || std::abs(int(b[i + c]) - bg[c]) > 1;
    }
    if (!cov)
    {
      continue;
    }
    ++covered;
    for (int c = 0; c < 3; ++c)
    {
      sum += std::abs(int(a[i + c]) - int(b[i + c]));
    }
  }
  return covered ? sum / (3.0 * covered) : 0.0;
}

// NaN or infinite values in the pass's last frame (colour and depth); -1 without a frame
int FrameNonFinite(vtkWhittedPass* pass)
{
  vtkNew<vtkFloatArray> rgba;
  vtkNew<vtkFloatArray> depth;
  pass->GetLastFrame(rgba, depth);
  if (rgba->GetNumberOfTuples() == 0)
  {
    return -1;
  }
  int n = 0;
  for (vtkFloatArray* a : { rgba.Get(), depth.Get() })
  {
    for (vtkIdType i = 0; i < a->GetNumberOfValues(); ++i)
    {
      n += std::isfinite(a->GetValue(i)) ? 0 : 1;
    }
  }
  return n;
}

bool Check(bool ok, const char* what)
{
  std::printf("%-60s %s\n", what, ok ? "ok" : "FAILED");
  return ok;
}

//------------------------------------------------------------------------------
// 1. Traced against vtkGPUVolumeRayCastMapper: the pass's image and VTK's (the same renderer
// without the pass); MAE over covered pixels
double TracedVsRaster(vtkRenderWindow* win, vtkRenderer* ren, vtkWhittedPass* pass, int& covered,
  int& openGL, int& bad)
{
  ren->SetPass(pass);
  win->Render();
  const std::vector<unsigned char> traced = GrabPixels(win);
  openGL = pass->GetLastFrameStatistics()->GetNumberOfOpenGLProps();
  bad = NonFiniteValues(pass);
  ren->SetPass(nullptr);
  win->Render();
  const std::vector<unsigned char> raster = GrabPixels(win);
  const unsigned char bg[3] = { 26, 26, 38 };
  return CoveredMAE(traced, raster, bg, covered);
}

bool CheckAgreement(const char* name, vtkRenderWindow* win, vtkRenderer* ren, vtkWhittedPass* pass)
{
  int covered = 0, openGL = 0, bad = 0;
  const double mae = TracedVsRaster(win, ren, pass, covered, openGL, bad);
  std::printf("agreement (%s): covered %d pixels, MAE %.3f/255 (limit 1; issue 29: 3), OpenGL props %d, "
              "non-finite %d\n",
    name, covered, mae, openGL, bad);
  return Check(openGL == 0, "the volume is traced, not drawn by OpenGL") &&
    Check(covered > 3000, "the volume covers pixels") && Check(mae <= 1.0, "MAE <= 1/255") &&
    Check(bad == 0, "no NaN or infinite value");
}

bool Agreement(bool withSphere)
{
  auto win = MakeWindow(240, 200);
  vtkNew<vtkRenderer> ren;
  win->AddRenderer(ren);
  ren->SetBackground(0.1, 0.1, 0.15);
  const double c[3] = { 0.0, 0.0, 0.0 };
  auto volume = MakeVolume(Blob(41, 0.05, c), 0.025);
  ren->AddVolume(volume);
  if (withSphere)
  {
    auto ball = Sphere(0.15, 0.1, 0.2, 0.35, 48);
    ball->GetProperty()->SetColor(0.9, 0.3, 0.3);
    ball->GetProperty()->SetAmbient(1.0);
    ball->GetProperty()->SetDiffuse(0.0);
    ball->GetProperty()->SetSpecular(0.0);
    ren->AddActor(ball);
  }
  LookAt(ren, { 0.6, 0.8, 3.2 }, { 0.0, 0.0, 0.0 }, 40);
  auto pass = MakePass();
  return CheckAgreement(withSphere ? "sphere inside" : "blob", win, ren, pass);
}

// Edits between frames, each against VTK's image again: a transfer-function edit (no grid
// conversion), new scalars (converted again), the volume moved, rotated and scaled with an image
// direction matrix (world placement; the grid copied, not converted)
bool Edits()
{
  auto win = MakeWindow(240, 200);
  vtkNew<vtkRenderer> ren;
  win->AddRenderer(ren);
  ren->SetBackground(0.1, 0.1, 0.15);
  const double c[3] = { 0.0, 0.0, 0.0 };
  auto img = Blob(41, 0.05, c);
  auto volume = MakeVolume(img, 0.025);
  ren->AddVolume(volume);
  LookAt(ren, { 0.6, 0.8, 3.2 }, { 0.0, 0.0, 0.0 }, 40);
  auto pass = MakePass();
  vtkWhittedFrameStatistics* st = pass->GetLastFrameStatistics();
  auto counts = [&](const char* what, int converted, int transfers)
  {
    std::printf("  %s: %d converted, %d transfer updates (expected %d, %d)\n", what,
      st->GetNumberOfVolumesConverted(), st->GetNumberOfVolumeTransferUpdates(), converted, transfers);
    return Check(st->GetNumberOfVolumesConverted() == converted &&
        st->GetNumberOfVolumeTransferUpdates() == transfers,
      "volume grids converted / transfer updates as expected");
  };
  bool ok = CheckAgreement("first frame", win, ren, pass) && counts("first frame", 1, 0);
  ren->SetPass(pass);
  win->Render();
  ok = counts("unchanged", 0, 0) && ok;
  volume->GetProperty()->GetRGBTransferFunction(0)->AddRGBPoint(0.5, 0.2, 0.9, 0.2);
  volume->GetProperty()->GetScalarOpacity(0)->AddPoint(0.6, 0.05);
  ok = CheckAgreement("transfer edit", win, ren, pass) && counts("transfer edit", 0, 1) && ok;
  auto* s = static_cast<float*>(img->GetScalarPointer());
  for (vtkIdType i = 0; i < img->GetNumberOfPoints(); ++i)
  {
    s[i] = std::sqrt(s[i]);
  }
  img->Modified();
  ok = CheckAgreement("new scalars", win, ren, pass) && counts("new scalars", 1, 0) && ok;
  // The next "time step" of the same size in a structure-of-arrays array (no standard memory
  // layout: read component by component), written over the traced grid's memory
  {
    vtkNew<vtkSOADataArrayTemplate<float>> soa;
    soa->SetNumberOfComponents(1);
    soa->SetNumberOfTuples(img->GetNumberOfPoints());
    for (vtkIdType i = 0; i < img->GetNumberOfPoints(); ++i)
    {
      soa->SetValue(i, s[i] * s[i] * s[i]);
    }
    soa->SetName("cubed");
    img->GetPointData()->SetScalars(soa);
    ok = CheckAgreement("same-size step, SOA array", win, ren, pass) && counts("SOA step", 1, 0) && ok;
    vtkNew<vtkFloatArray> back; // and the same values again in an ordinary float array
    back->DeepCopy(soa);
    img->GetPointData()->SetScalars(back);
    ok = CheckAgreement("same-size step, float again", win, ren, pass) && counts("float step", 1, 0) && ok;
    s = back->GetPointer(0);
  }
  volume->SetPosition(0.2, -0.1, 0.1);
  volume->SetOrientation(20.0, 35.0, 0.0);
  volume->SetScale(1.0, 0.7, 1.2);
  ok = CheckAgreement("moved, rotated, scaled", win, ren, pass) && counts("moved", 0, 0) && ok;
  // Made lopsided along the index x axis (else a turn of the round blob would look the same)
  const int n = img->GetDimensions()[0];
  for (vtkIdType i = 0; i < img->GetNumberOfPoints(); ++i)
  {
    s[i] *= static_cast<float>(0.2 + 0.8 * double(i % n) / (n - 1));
  }
  img->SetDirectionMatrix(0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0); // 90 degrees about z
  img->SetOrigin(1.0, -1.0, -1.0); // the blob stays centred
  img->Modified();
  ok = CheckAgreement("image direction matrix", win, ren, pass) && ok;
  // A new input whose extent starts at -20 (as vtkRTAnalyticSource's): its origin is not its first point
  const double c2[3] = { 0.1, 0.2, 0.0 };
  vtkVolumeMapper::SafeDownCast(volume->GetMapper())->SetInputData(Blob(41, 0.05, c2, -20));
  ok = CheckAgreement("extent from -20", win, ren, pass) && counts("new input", 1, 0) && ok;
  return ok;
}

//------------------------------------------------------------------------------
// 2. A mirror shows the volume at the mirrored position
bool Mirror()
{
  const int w = 160, h = 160;
  const double c[3] = { 3.0, 0.0, 0.0 };
  auto render = [&](bool mirror)
  {
    auto win = MakeWindow(w, h);
    vtkNew<vtkRenderer> ren;
    win->AddRenderer(ren);
    ren->SetBackground(0.1, 0.1, 0.15);
    ren->AddVolume(MakeVolume(Blob(33, 0.05, c)));
    vtkCamera* cam = ren->GetActiveCamera();
    cam->ParallelProjectionOn();
    cam->SetParallelScale(1.0);
    if (mirror)
    {
      // The plane z = -x (normal (1, 0, 1)), seen from +z: rays going -z leave it along +x
      vtkNew<vtkPlaneSource> plane;
      plane->SetOrigin(-1.5, -1.5, 1.5);
      plane->SetPoint1(1.5, -1.5, -1.5);
      plane->SetPoint2(-1.5, 1.5, 1.5);
      vtkNew<vtkPolyDataMapper> pm;
      pm->SetInputConnection(plane->GetOutputPort());
      vtkNew<vtkActor> m;
      m->SetMapper(pm);
      m->GetProperty()->SetColor(0.0, 0.0, 0.0);
      m->GetProperty()->SetAmbient(0.0);
      m->GetProperty()->SetDiffuse(0.0);
      m->GetProperty()->SetSpecular(0.0);
      SetWhitted(m->GetProperty(), 1.0);
      ren->AddActor(m);
      cam->SetPosition(0.0, 0.0, 6.0);
      cam->SetFocalPoint(0.0, 0.0, 0.0);
    }
    else
    {
      // Along +x from beside the mirror: screen right is +z, the mirror's -u
      cam->SetPosition(-3.0, 0.0, 0.0);
      cam->SetFocalPoint(0.0, 0.0, 0.0);
    }
    cam->SetViewUp(0.0, 1.0, 0.0);
    ren->ResetCameraClippingRange(-8, 8, -8, 8, -8, 8);
    auto pass = MakePass();
    pass->SetReflections(true);
    ren->SetPass(pass);
    win->Render();
    return GrabPixels(win);
  };
  const std::vector<unsigned char> seen = render(true), direct = render(false);
  std::vector<unsigned char> flipped(direct.size());
  for (int j = 0; j < h; ++j)
  {
    for (int i = 0; i < w; ++i)
    {
      for (int k = 0; k < 3; ++k)
      {
        flipped[3 * (j * w + i) + k] = direct[3 * (j * w + (w - 1 - i)) + k];
      }
    }
  }
  const unsigned char bg[3] = { 26, 26, 38 };
  int covered = 0;
  const double mae = CoveredMAE(seen, flipped, bg, covered);
  int inMirror = 0;
  for (size_t i = 0; i + 2 < seen.size(); i += 3)
  {
    inMirror += std::abs(int(seen[i]) - bg[0]) > 1 || std::abs(int(seen[i + 1]) - bg[1]) > 1 ||
      std::abs(int(seen[i + 2]) - bg[2]) > 1;
  }
  std::printf("mirror: volume pixels in the mirror %d, MAE against the direct view flipped %.3f/255 "
              "(limit 1) over %d covered pixels\n",
    inMirror, mae, covered);
  return Check(inMirror > 2000, "the mirror shows the volume") &&
    Check(mae <= 1.0, "at the mirrored position, as seen directly");
}

//------------------------------------------------------------------------------
// 3. The floor under a dense slab: transmittance exp(-sigma t)
bool SlabShadow()
{
  const int w = 200, h = 150;
  auto win = MakeWindow(w, h);
  vtkNew<vtkRenderer> ren;
  win->AddRenderer(ren);
  ren->SetBackground(0.0, 0.0, 0.0);
  vtkNew<vtkPlaneSource> plane;
  plane->SetOrigin(-4.0, 0.0, 4.0);
  plane->SetPoint1(4.0, 0.0, 4.0);
  plane->SetPoint2(-4.0, 0.0, -4.0);
  vtkNew<vtkPolyDataMapper> pm;
  pm->SetInputConnection(plane->GetOutputPort());
  vtkNew<vtkActor> floor;
  floor->SetMapper(pm);
  floor->GetProperty()->SetColor(0.8, 0.8, 0.8);
  floor->GetProperty()->SetAmbient(0.0);
  floor->GetProperty()->SetDiffuse(1.0);
  floor->GetProperty()->SetSpecular(0.0);
  ren->AddActor(floor);
  // The slab: x, z in [-1, 1], y in [1, 1.5] (thickness 0.5), scalar 1 everywhere
  const double a = 0.3, u = 0.2, t = 0.5;
  vtkNew<vtkImageData> img;
  img->SetDimensions(11, 3, 11);
  img->SetSpacing(0.2, 0.25, 0.2);
  img->SetOrigin(-1.0, 1.0, -1.0);
  img->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  std::fill_n(static_cast<unsigned char*>(img->GetScalarPointer()), 11 * 3 * 11, 1);
  vtkNew<vtkSmartVolumeMapper> mapper;
  mapper->SetInputData(img);
  vtkNew<vtkPiecewiseFunction> otf;
  otf->AddPoint(0.0, a);
  otf->AddPoint(2.0, a);
  vtkNew<vtkVolumeProperty> vp;
  vp->SetScalarOpacity(otf);
  vp->SetScalarOpacityUnitDistance(u);
  vtkNew<vtkVolume> slab;
  slab->SetMapper(mapper);
  slab->SetProperty(vp);
  ren->AddVolume(slab);
  vtkNew<vtkLight> sun;
  sun->SetLightTypeToSceneLight();
  sun->SetPositional(false);
  sun->SetPosition(0.0, 1.0, 0.0);
  sun->SetFocalPoint(0.0, 0.0, 0.0);
  ren->AddLight(sun);
  // Camera rays to the floor points stay below y = 0.6: they never cross the slab
  LookAt(ren, { 0.0, 0.6, 4.0 }, { 0.0, 0.0, -0.3 }, 50);
  auto pass = MakePass();
  pass->SetShadows(true);
  ren->SetPass(pass);
  win->Render();
  vtkNew<vtkFloatArray> rgba;
  pass->GetLastFrame(rgba, nullptr);
  auto at = [&](double x, double z)
  {
    ren->SetWorldPoint(x, 0.0, z, 1.0);
    ren->WorldToDisplay();
    const double* d = ren->GetDisplayPoint();
    const int i = static_cast<int>(d[0]), j = static_cast<int>(d[1]);
    if (i < 0 || j < 0 || i >= w || j >= h || rgba->GetNumberOfTuples() != vtkIdType(w) * h)
    {
      return -1.0;
    }
    return static_cast<double>(rgba->GetComponent(vtkIdType(j) * w + i, 1));
  };
  const double shadowed = at(0.0, 0.0), lit = at(2.2, 0.0);
  const double expected = std::exp(std::log(1.0 - a) / u * t); // exp(-sigma t)
  const double ratio = lit > 0.0 ? shadowed / lit : -1.0;
  std::printf("slab shadow: lit %.5f, shadowed %.5f, ratio %.5f, exp(-sigma t) %.5f (sigma %.4f, t %.2f), "
              "error %.2e (limit 1e-3)\n",
    lit, shadowed, ratio, expected, -std::log(1.0 - a) / u, t, std::abs(ratio - expected));
  return Check(lit > 0.7, "the floor beside the slab is lit") &&
    Check(std::abs(ratio - expected) <= 1e-3, "under the slab: darkened by exp(-sigma t)") &&
    Check(NonFiniteValues(pass) == 0, "no NaN or infinite value");
}

//------------------------------------------------------------------------------
// 4. Bad input
bool BadInput(const char* name, const std::function<void(vtkImageData*)>& spoil, const char* expect,
  bool traced)
{
  auto render = [&](bool withVolume, MessageLog& log, int& nonFinite)
  {
    auto win = MakeWindow(160, 120);
    vtkNew<vtkRenderer> ren;
    win->AddRenderer(ren);
    ren->SetBackground(0.1, 0.1, 0.15);
    auto ball = Sphere(0.6, 0.0, 0.0, 0.5, 32);
    ren->AddActor(ball);
    if (withVolume)
    {
      const double c[3] = { -0.6, 0.0, 0.0 };
      auto img = Blob(9, 0.12, c);
      spoil(img);
      ren->AddVolume(MakeVolume(img));
    }
    LookAt(ren, { 0.0, 0.5, 4.0 }, { 0.0, 0.0, 0.0 }, 40);
    auto pass = MakePass();
    log.Observe(pass);
    ren->SetPass(pass);
    win->Render();
    win->Render();
    // NaN scalars are counted by the safety nets (samples read as transparent): there, only the
    // frame's own values count
    nonFinite = traced ? FrameNonFinite(pass) : NonFiniteValues(pass);
    return std::make_pair(GrabPixels(win), pass->GetLastFrameStatistics()->GetNumberOfOpenGLProps());
  };
  MessageLog log, refLog;
  int nonFinite = 0, refNonFinite = 0;
  const auto image = render(true, log, nonFinite);
  const auto reference = render(false, refLog, refNonFinite);
  const int differing = DifferingPixels(image.first, reference.first, 1);
  const bool named = log.Warnings.size() == 1 && log.Warnings[0].find(expect) != std::string::npos &&
    log.Warnings[0].find("vtkVolume") != std::string::npos;
  std::printf("bad input %s: warnings %zu (%s), errors %zu, non-finite %d, OpenGL props %d, pixels "
              "differing from the scene without it %d\n",
    name, log.Warnings.size(), log.Warnings.empty() ? "" : log.Warnings[0].c_str(), log.Errors.size(),
    nonFinite, image.second, differing);
  for (const std::string& m : log.Warnings)
  {
    std::printf("  warning: %s\n", m.c_str());
  }
  bool ok = Check(named, "one warning naming the volume and the problem");
  ok = Check(log.Errors.empty(), "no error") && ok;
  ok = Check(nonFinite == 0, "no NaN or infinite value") && ok;
  ok = Check(image.second == 0, "not left to OpenGL") && ok;
  if (!traced)
  {
    ok = Check(differing == 0, "the rest of the scene as without the volume") && ok;
  }
  else
  {
    ok = Check(differing > 100, "the volume is still drawn") && ok;
  }
  return ok;
}
// 5. Settings the tracer does not trace keep VTK's OpenGL drawing, with one warning naming them
bool Fallback(const char* name, const std::function<void(vtkVolume*)>& set, const char* expect)
{
  auto win = MakeWindow(160, 120);
  vtkNew<vtkRenderer> ren;
  win->AddRenderer(ren);
  const double c[3] = { 0.0, 0.0, 0.0 };
  auto volume = MakeVolume(Blob(9, 0.12, c));
  set(volume);
  ren->AddVolume(volume);
  LookAt(ren, { 0.0, 0.5, 4.0 }, { 0.0, 0.0, 0.0 }, 40);
  auto pass = MakePass();
  MessageLog log;
  log.Observe(pass);
  ren->SetPass(pass);
  win->Render();
  win->Render();
  const int openGL = pass->GetLastFrameStatistics()->GetNumberOfOpenGLProps();
  const bool named = log.Warnings.size() == 1 && log.Warnings[0].find(expect) != std::string::npos;
  std::printf("fallback %s: OpenGL props %d, warnings %zu%s", name, openGL, log.Warnings.size(),
    log.Warnings.empty() ? "\n" : (": " + log.Warnings[0]).c_str());
  return Check(openGL == 1 && named, "drawn by OpenGL, one warning naming the setting");
}
} // namespace

int TestWhittedVolume(int, char*[])
{
  bool ok = Agreement(false);
  ok = Agreement(true) && ok;
  ok = Edits() && ok;
  ok = Mirror() && ok;
  ok = SlabShadow() && ok;
  ok = BadInput(
         "NaN scalars",
         [](vtkImageData* img)
         {
           auto* s = static_cast<float*>(img->GetScalarPointer());
           for (int i = 0; i < 9 * 9 * 9; i += 50)
           {
             s[i] = std::numeric_limits<float>::quiet_NaN();
           }
         },
         "NaN or infinite: traced as transparent", true) &&
    ok;
  ok = BadInput(
         "zero spacing", [](vtkImageData* img) { img->SetSpacing(0.0, 0.12, 0.12); },
         "spacing along x is zero", false) &&
    ok;
  ok = BadInput(
         "single point along z",
         [](vtkImageData* img)
         {
           img->SetDimensions(9, 9, 1);
           img->AllocateScalars(VTK_FLOAT, 1);
           img->GetPointData()->GetScalars()->Fill(0.5);
         },
         "a single point along z", false) &&
    ok;
  ok = BadInput(
         "empty image", [](vtkImageData* img) { img->Initialize(); }, "empty image", false) &&
    ok;
  ok = Fallback(
         "MIP", [](vtkVolume* v)
         { vtkVolumeMapper::SafeDownCast(v->GetMapper())->SetBlendModeToMaximumIntensity(); },
         "blend mode") &&
    ok;
  return ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
