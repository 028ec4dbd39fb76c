// Agreement with VTK's own OpenGL rendering: with shadows, reflections and refractions off, the
// pass's image of a lit multi-actor scene must equal VTK's OpenGL image of the same scene (same
// camera, lights, properties) within a tight tolerance, and the depth buffers must agree. Run for
// each VTK light complexity (one headlight; several directional lights; positional and spot lights)
// and for a parallel camera.
#include "WhittedTestUtilities.h"

#include "vtkActorCollection.h"
#include "vtkCamera.h"
#include "vtkConeSource.h"
#include "vtkCubeSource.h"
#include "vtkCylinderSource.h"
#include "vtkElevationFilter.h"
#include "vtkImageData.h"
#include "vtkLight.h"
#include "vtkLightKit.h"
#include "vtkLookupTable.h"
#include "vtkPNGWriter.h"
#include "vtkPolyDataNormals.h"
#include "vtkTesting.h"
#include "vtkTransform.h"
#include "vtkWindowToImageFilter.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

namespace
{
using namespace whittedtest;

vtkSmartPointer<vtkActor> MakeActor(vtkAlgorithm* source)
{
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputConnection(source->GetOutputPort());
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  return actor;
}

// Several actors covering VTK's shading paths: point normals, facet normals, flat interpolation,
// cell normals, point scalars through a lookup table, specular highlights, unlit, an actor
// transform with scaling.
void BuildScene(vtkRenderer* ren)
{
  ren->AddActor(Floor(3.0, 6, -1.0));

  auto sphere = Sphere(-1.2, 0.0, 0.0, 0.8, 24);
  sphere->GetProperty()->SetColor(0.9, 0.3, 0.2);
  sphere->GetProperty()->SetAmbient(0.1);
  sphere->GetProperty()->SetSpecular(0.5);
  sphere->GetProperty()->SetSpecularPower(20);
  ren->AddActor(sphere);

  // Cone: no normals at all (facet normals from derivatives in VTK)
  vtkNew<vtkConeSource> cone;
  cone->SetResolution(24);
  cone->SetHeight(1.4);
  cone->SetRadius(0.6);
  cone->SetDirection(0, 1, 0);
  cone->SetCenter(1.2, -0.2, 0.3);
  auto coneActor = MakeActor(cone);
  coneActor->GetProperty()->SetColor(0.2, 0.7, 0.3);
  coneActor->GetProperty()->SetSpecular(0.3);
  coneActor->GetProperty()->SetSpecularPower(40);
  coneActor->GetProperty()->SetSpecularColor(1.0, 1.0, 0.6);
  ren->AddActor(coneActor);

  // Cube with point normals, drawn flat; rotated and scaled by the actor
  vtkNew<vtkCubeSource> cube;
  auto cubeActor = MakeActor(cube);
  cubeActor->GetProperty()->SetInterpolationToFlat();
  cubeActor->GetProperty()->SetColor(0.3, 0.4, 0.9);
  cubeActor->GetProperty()->SetAmbient(0.2);
  cubeActor->GetProperty()->SetDiffuse(0.7);
  cubeActor->GetProperty()->SetSpecular(0.2);
  cubeActor->SetPosition(0.1, -0.4, -1.3);
  cubeActor->SetOrientation(15, 35, 5);
  cubeActor->SetScale(0.9, 0.6, 0.7);
  ren->AddActor(cubeActor);

  // Cylinder with cell normals only
  vtkNew<vtkCylinderSource> cyl;
  cyl->SetResolution(16);
  cyl->SetCenter(0.2, 0.1, 1.2);
  cyl->SetRadius(0.35);
  cyl->SetHeight(1.2);
  vtkNew<vtkPolyDataNormals> cellNormals;
  cellNormals->SetInputConnection(cyl->GetOutputPort());
  cellNormals->ComputePointNormalsOff();
  cellNormals->ComputeCellNormalsOn();
  auto cylActor = MakeActor(cellNormals);
  cylActor->GetProperty()->SetColor(0.8, 0.8, 0.3);
  cylActor->GetProperty()->SetSpecular(0.4);
  cylActor->GetProperty()->SetSpecularPower(10);
  ren->AddActor(cylActor);

  // Elevation-coloured sphere through a lookup table (point scalars, colours interpolated)
  vtkNew<vtkSphereSource> ball;
  ball->SetCenter(-0.2, 0.9, 0.6);
  ball->SetRadius(0.45);
  ball->SetThetaResolution(32);
  ball->SetPhiResolution(16);
  vtkNew<vtkElevationFilter> elevation;
  elevation->SetInputConnection(ball->GetOutputPort());
  elevation->SetLowPoint(0, 0.45, 0);
  elevation->SetHighPoint(0, 1.35, 0);
  auto ballActor = MakeActor(elevation);
  ballActor->GetProperty()->SetAmbient(0.1);
  ballActor->GetProperty()->SetSpecular(0.3);
  ren->AddActor(ballActor);

  // Unlit actor
  auto flat = Sphere(1.6, 1.0, -0.8, 0.3, 12);
  flat->GetProperty()->SetLighting(false);
  flat->GetProperty()->SetColor(0.6, 0.2, 0.7);
  ren->AddActor(flat);

  ren->SetBackground(0.1, 0.15, 0.25);
  LookAt(ren, { 1.5, 2.5, 6.5 }, { 0.0, 0.0, 0.0 }, 35);
}

struct Capture
{
  int W = 0, H = 0;
  std::vector<unsigned char> Rgb;
  std::vector<float> Depth;
};

Capture Grab(vtkRenderWindow* win)
{
  Capture c;
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(win);
  grab->ReadFrontBufferOff();
  grab->SetInputBufferTypeToRGB();
  grab->Update();
  vtkImageData* img = grab->GetOutput();
  int dims[3];
  img->GetDimensions(dims);
  c.W = dims[0];
  c.H = dims[1];
  auto* p = static_cast<unsigned char*>(img->GetScalarPointer());
  c.Rgb.assign(p, p + 3 * c.W * c.H);
  c.Depth.resize(static_cast<size_t>(c.W) * c.H);
  win->GetZbufferData(0, 0, c.W - 1, c.H - 1, c.Depth.data());
  return c;
}

void WritePng(const Capture& c, const std::string& path)
{
  vtkNew<vtkImageData> img;
  img->SetDimensions(c.W, c.H, 1);
  img->AllocateScalars(VTK_UNSIGNED_CHAR, 3);
  std::copy(c.Rgb.begin(), c.Rgb.end(), static_cast<unsigned char*>(img->GetScalarPointer()));
  vtkNew<vtkPNGWriter> w;
  w->SetFileName(path.c_str());
  w->SetInputData(img);
  w->Write();
}

// Lights: 1 = VTK's automatic headlight; 2 = a light kit (camera lights + headlight); 3 =
// positional + spot
void AddLights(vtkRenderer* ren, int complexity)
{
  if (complexity == 2)
  {
    vtkNew<vtkLightKit> kit;
    kit->AddLightsToRenderer(ren);
  }
  else if (complexity == 3)
  {
    vtkNew<vtkLight> point;
    point->SetPositional(true);
    point->SetPosition(3.0, 4.0, 3.0);
    point->SetConeAngle(180);
    point->SetAttenuationValues(
      1.0, 0.02, 0.0); // never above 1 (the tracer clamps attenuation to 1)
    point->SetColor(1.0, 0.95, 0.85);
    ren->AddLight(point);
    vtkNew<vtkLight> spot;
    spot->SetPositional(true);
    spot->SetPosition(-2.5, 3.0, 2.0);
    spot->SetFocalPoint(-1.2, 0.0, 0.0);
    spot->SetConeAngle(25);
    spot->SetExponent(2);
    spot->SetIntensity(0.6);
    spot->SetColor(0.5, 0.6, 1.0);
    ren->AddLight(spot);
    vtkNew<vtkLight> sun;
    sun->SetPosition(-1, 1, 0.5);
    sun->SetFocalPoint(0, 0, 0);
    sun->SetIntensity(0.3);
    ren->AddLight(sun);
  }
}

bool Compare(const char* name, int complexity, bool parallel, const std::string& tmp)
{
  vtkNew<vtkRenderer> ren;
  auto win = MakeWindow(240, 200);
  win->AddRenderer(ren);
  BuildScene(ren);
  AddLights(ren, complexity);
  ren->GetActiveCamera()->SetParallelProjection(parallel);
  ren->GetActiveCamera()->SetParallelScale(2.6);
  // With a parallel camera VTK's specular term uses V = normalize(eye - P) (the camera position, as
  // if perspective); the pass does the same (IntegratorSettings::viewFromEye), so specular stays on
  // here.

  // VTK's OpenGL image
  win->Render();
  Capture gl = Grab(win);

  // The same scene through the pass, local shading only
  vtkNew<vtkWhittedPass> pass;
  pass->SetShadows(false);
  pass->SetReflections(false);
  pass->SetRefractions(false);
  ren->SetPass(pass);
  win->Render();
  Capture rt = Grab(win);

  // Colour: count pixels by largest channel difference
  const size_t n = static_cast<size_t>(gl.W) * gl.H;
  size_t over1 = 0, over3 = 0;
  double sum = 0.0;
  int worst = 0;
  for (size_t i = 0; i < n; ++i)
  {
    int d = 0;
    for (int k = 0; k < 3; ++k)
    {
      d = std::max(d, std::abs(int(gl.Rgb[3 * i + k]) - int(rt.Rgb[3 * i + k])));
    }
    sum += d;
    worst = std::max(worst, d);
    over1 += d > 1;
    over3 += d > 3;
  }
  // Depth: where both hit something
  size_t depthBoth = 0, depthOff = 0, coverageMismatch = 0;
  double depthWorst = 0.0;
  for (size_t i = 0; i < n; ++i)
  {
    const bool hg = gl.Depth[i] < 1.0f, hr = rt.Depth[i] < 1.0f;
    if (hg != hr)
    {
      ++coverageMismatch;
      continue;
    }
    if (!hg)
    {
      continue;
    }
    ++depthBoth;
    const double dd = std::abs(double(gl.Depth[i]) - double(rt.Depth[i]));
    depthWorst = std::max(depthWorst, dd);
    depthOff += dd > 1e-3;
  }
  const double fracOver3 = double(over3) / n, fracOver1 = double(over1) / n;
  const double fracCoverage = double(coverageMismatch) / n;
  std::printf(
    "%-28s mean |d| %.4f, worst %d, >1: %.3f%%, >3: %.3f%%, coverage mismatch %.3f%%, depth worst "
    "%.2e (%zu of %zu > 1e-3); %s\n",
    name, sum / n, worst, 100 * fracOver1, 100 * fracOver3, 100 * fracCoverage, depthWorst,
    depthOff, depthBoth, complexity == 1 ? "headlight shading" : "general shading");

  // Tolerances: float32 shader versus double tracer gives +-1 LSB; a pixel whose centre lies
  // exactly on a shared edge or silhouette may pick the other triangle. Anything more is a shading
  // difference.
  const bool ok = fracOver1 < 0.005 && fracOver3 < 0.002 && fracCoverage < 0.002 &&
    double(depthOff) / std::max<size_t>(1, depthBoth) < 0.001;
  if (!ok)
  {
    WritePng(gl, tmp + "/" + name + "_opengl.png");
    WritePng(rt, tmp + "/" + name + "_whitted.png");
    std::cerr << name << ": images differ; wrote " << tmp << "/" << name
              << "_{opengl,whitted}.png\n";
  }
  return ok;
}

} // namespace

int TestWhittedAgreement(int argc, char* argv[])
{
  vtkNew<vtkTesting> testing;
  for (int i = 0; i < argc; ++i)
  {
    testing->AddArgument(argv[i]);
  }
  const std::string tmp = testing->GetTempDirectory() ? testing->GetTempDirectory() : ".";
  bool ok = true;
  ok &= Compare("AgreementHeadlight", 1, false, tmp);
  ok &= Compare("AgreementLightKit", 2, false, tmp);
  ok &= Compare("AgreementPositional", 3, false, tmp);
  ok &= Compare("AgreementParallel", 2, true, tmp);
  return ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
