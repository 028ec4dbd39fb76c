// Textures: a plane with a vtkTexture (nearest, repeated twice through its texture coordinates) and
// a textured sphere (interpolated) that casts a shadow on it and is seen in a mirror sphere.
#include "WhittedTestUtilities.h"

#include "vtkCamera.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkLight.h"
#include "vtkPointData.h"
#include "vtkRegressionTestImage.h"
#include "vtkTexture.h"
#include "vtkTexturedSphereSource.h"
#include "vtkTransformTextureCoords.h"

#include <iostream>

namespace
{
// 8 x 8 RGB image: a coloured checkerboard with a gradient
vtkSmartPointer<vtkImageData> MakeImage()
{
  auto img = vtkSmartPointer<vtkImageData>::New();
  img->SetDimensions(8, 8, 1);
  img->AllocateScalars(VTK_UNSIGNED_CHAR, 3);
  for (int j = 0; j < 8; ++j)
  {
    for (int i = 0; i < 8; ++i)
    {
      auto* p = static_cast<unsigned char*>(img->GetScalarPointer(i, j, 0));
      const bool dark = (i + j) % 2 == 0;
      p[0] = static_cast<unsigned char>(dark ? 30 : 200 + 7 * i);
      p[1] = static_cast<unsigned char>(dark ? 60 + 20 * j : 200);
      p[2] = static_cast<unsigned char>(dark ? 120 : 60);
    }
  }
  return img;
}
}

int TestWhittedTexture(int argc, char* argv[])
{
  using namespace whittedtest;
  vtkNew<vtkRenderer> ren;
  auto win = MakeWindow(300, 240);
  win->AddRenderer(ren);
  auto image = MakeImage();

  vtkNew<vtkPlaneSource> plane;
  plane->SetOrigin(-3, 0, 3);
  plane->SetPoint1(3, 0, 3);
  plane->SetPoint2(-3, 0, -3);
  vtkNew<vtkTransformTextureCoords> repeat;
  repeat->SetInputConnection(plane->GetOutputPort());
  repeat->SetScale(2, 2, 1);
  vtkNew<vtkPolyDataMapper> planeMapper;
  planeMapper->SetInputConnection(repeat->GetOutputPort());
  vtkNew<vtkTexture> nearest;
  nearest->SetInputData(image);
  nearest->InterpolateOff();
  nearest->RepeatOn();
  vtkNew<vtkActor> floor;
  floor->SetMapper(planeMapper);
  floor->SetTexture(nearest);
  floor->GetProperty()->SetAmbient(0.2);
  floor->GetProperty()->SetDiffuse(0.8);
  ren->AddActor(floor);

  vtkNew<vtkTexturedSphereSource> ball;
  ball->SetRadius(0.8);
  ball->SetThetaResolution(48);
  ball->SetPhiResolution(24);
  vtkNew<vtkPolyDataMapper> ballMapper;
  ballMapper->SetInputConnection(ball->GetOutputPort());
  vtkNew<vtkTexture> smooth;
  smooth->SetInputData(image);
  smooth->InterpolateOn();
  vtkNew<vtkActor> globe;
  globe->SetMapper(ballMapper);
  globe->SetTexture(smooth);
  globe->SetPosition(-0.6, 0.9, 0.4);
  globe->GetProperty()->SetSpecular(0.3);
  ren->AddActor(globe);

  auto mirror = Sphere(1.2, 0.7, -1.0, 0.7, 32);
  mirror->GetProperty()->SetColor(0.2, 0.2, 0.2);
  mirror->GetProperty()->SetSpecular(0.8);
  mirror->GetProperty()->SetSpecularPower(80);
  SetWhitted(mirror->GetProperty(), 0.8);
  ren->AddActor(mirror);

  AddPointLight(ren, -2.0, 5.0, 3.0);
  ren->SetBackground(0.3, 0.35, 0.45);
  LookAt(ren, { 0.5, 3.0, 5.5 }, { 0.0, 0.5, 0.0 }, 40);

  vtkNew<vtkWhittedPass> pass;
  ApplyTestSwitches(pass);
  ren->SetPass(pass);
  win->Render();
  std::cout << pass->GetLastFrameReport();
  const int baseline = CheckBaseline(win, argc, argv);

  // Independent: VTK's raster of the same scene (CheckAgainstRaster) without the mirror sphere
  RasterOracle raster;
  raster.Excluded = { mirror };
  raster.MinShadowShare = 0.04;
  raster.MinUmbraShare = 0.5;
  const bool independent = CheckAgainstRaster("Texture", win, pass, raster);
  return baseline == EXIT_SUCCESS && independent ? EXIT_SUCCESS : EXIT_FAILURE;
}
