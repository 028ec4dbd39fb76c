// Depth composition with OpenGL geometry. Layer 0 (the pass): a traced floor, mirror and sphere,
// plus props the tracer leaves to OpenGL in the same renderer: an image slice cutting through the
// sphere, a volume the tracer does not take (vtkMultiBlockVolumeMapper of two blocks, one empty;
// traced volumes: TestWhittedVolume), and a wireframe actor. Layer 1 (plain OpenGL, PreserveDepthBuffer on, same
// camera): a cone that pierces the traced sphere. Everything must occlude correctly by depth.
#include "WhittedTestUtilities.h"

#include "vtkCamera.h"
#include "vtkColorTransferFunction.h"
#include "vtkConeSource.h"
#include "vtkImageActor.h"
#include "vtkImageData.h"
#include "vtkImageMapper3D.h"
#include "vtkLight.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkMultiBlockVolumeMapper.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkRegressionTestImage.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <cmath>
#include <iostream>

namespace
{
vtkSmartPointer<vtkImageData> Blob(int n, double spacing, const double origin[3])
{
  auto img = vtkSmartPointer<vtkImageData>::New();
  img->SetDimensions(n, n, n);
  img->SetSpacing(spacing, spacing, spacing);
  img->SetOrigin(origin[0], origin[1], origin[2]);
  img->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  for (int k = 0; k < n; ++k)
  {
    for (int j = 0; j < n; ++j)
    {
      for (int i = 0; i < n; ++i)
      {
        const double x = 2.0 * i / (n - 1) - 1, y = 2.0 * j / (n - 1) - 1,
                     z = 2.0 * k / (n - 1) - 1;
        const double v = 255.0 * std::max(0.0, 1.0 - std::sqrt(x * x + y * y + z * z));
        *static_cast<unsigned char*>(img->GetScalarPointer(i, j, k)) =
          static_cast<unsigned char>(v);
      }
    }
  }
  return img;
}
}

int TestWhittedLayers(int argc, char* argv[])
{
  using namespace whittedtest;
  auto win = MakeWindow(300, 240);
  win->SetNumberOfLayers(2);
  vtkNew<vtkRenderer> ren;
  ren->SetLayer(0);
  win->AddRenderer(ren);
  vtkNew<vtkRenderer> top;
  top->SetLayer(1);
  top->PreserveDepthBufferOn();
  top->SetActiveCamera(ren->GetActiveCamera());
  win->AddRenderer(top);

  // Traced
  ren->AddActor(Floor(3.0, 6));
  auto ball = Sphere(0.0, 0.9, 0.0, 0.9, 32);
  ball->GetProperty()->SetColor(0.9, 0.6, 0.3);
  ball->GetProperty()->SetSpecular(0.4);
  ball->GetProperty()->SetSpecularPower(30);
  ren->AddActor(ball);
  auto mirror = Sphere(2.1, 0.6, -1.0, 0.6, 32);
  mirror->GetProperty()->SetColor(0.2, 0.2, 0.2);
  SetWhitted(mirror->GetProperty(), 0.8);
  ren->AddActor(mirror);

  // OpenGL in the same renderer: an image slice through the sphere (plane z = 0.2)
  vtkNew<vtkImageData> plane;
  plane->SetDimensions(26, 20, 1);
  plane->SetSpacing(0.1, 0.1, 1);
  plane->SetOrigin(-1.3, 0.0, 0.2);
  plane->AllocateScalars(VTK_UNSIGNED_CHAR, 3);
  for (int j = 0; j < 20; ++j)
  {
    for (int i = 0; i < 26; ++i)
    {
      auto* p = static_cast<unsigned char*>(plane->GetScalarPointer(i, j, 0));
      p[0] = static_cast<unsigned char>(40 + 8 * i);
      p[1] = static_cast<unsigned char>(40 + 10 * j);
      p[2] = 200;
    }
  }
  vtkNew<vtkImageActor> image;
  image->GetMapper()->SetInputData(plane);
  image->SetOpacity(1.0);
  ren->AddActor(image);

  // A volume (a soft blob) at the front left
  const double o2[3] = { -2.0, 0.1, 0.9 };
  vtkNew<vtkMultiBlockDataSet> blocks;
  blocks->SetBlock(0, Blob(24, 0.04, o2));
  blocks->SetBlock(1, nullptr); // two blocks: the tracer takes one-block inputs only
  vtkNew<vtkMultiBlockVolumeMapper> volumeMapper;
  volumeMapper->SetInputDataObject(blocks);
  vtkNew<vtkColorTransferFunction> ctf;
  ctf->AddRGBPoint(0, 0.0, 0.0, 0.0);
  ctf->AddRGBPoint(255, 0.2, 1.0, 0.4);
  vtkNew<vtkPiecewiseFunction> otf;
  otf->AddPoint(0, 0.0);
  otf->AddPoint(40, 0.3);
  otf->AddPoint(255, 1.0);
  vtkNew<vtkVolumeProperty> vp;
  vp->SetColor(ctf);
  vp->SetScalarOpacity(otf);
  vtkNew<vtkVolume> volume;
  volume->SetMapper(volumeMapper);
  volume->SetProperty(vp);
  ren->AddVolume(volume);

  // A wireframe actor without tubes: OpenGL
  auto cage = Sphere(1.5, 1.6, 1.2, 0.4, 6);
  cage->GetProperty()->SetRepresentationToWireframe();
  cage->GetProperty()->SetColor(0.2, 1.0, 1.0);
  ren->AddActor(cage);

  // Layer 1: a plain OpenGL cone through the traced sphere
  vtkNew<vtkConeSource> cone;
  cone->SetCenter(0.6, 1.0, 0.6);
  cone->SetDirection(-1, 0.2, -1);
  cone->SetHeight(2.4);
  cone->SetRadius(0.25);
  cone->SetResolution(24);
  vtkNew<vtkPolyDataMapper> coneMapper;
  coneMapper->SetInputConnection(cone->GetOutputPort());
  vtkNew<vtkActor> coneActor;
  coneActor->SetMapper(coneMapper);
  coneActor->GetProperty()->SetColor(0.3, 0.4, 1.0);
  top->AddActor(coneActor);

  AddPointLight(ren, -1.0, 5.0, 4.0);
  ren->SetBackground(0.2, 0.2, 0.25);
  LookAt(ren, { 0.5, 2.8, 5.5 }, { 0.0, 0.7, 0.0 }, 40);

  vtkNew<vtkWhittedPass> pass;
  ApplyTestSwitches(pass);
  ren->SetPass(pass);
  win->Render();
  std::cout << pass->GetLastFrameReport();
  if (pass->GetLastFrameStatistics()->GetNumberOfOpenGLProps() != 3)
  {
    std::cerr << "expected the image slice, the volume and the wireframe drawn by OpenGL\n";
    return EXIT_FAILURE;
  }
  const int baseline = CheckBaseline(win, argc, argv);

  // Independent: VTK's raster of the same scene (CheckAgainstRaster) without the mirror sphere; the OpenGL props and layer are in both
  RasterOracle raster;
  raster.Excluded = { mirror };
  raster.MinShadowShare = 0.006;
  raster.MinUmbraShare = 0.5;
  const bool independent = CheckAgainstRaster("Layers", win, pass, raster);
  return baseline == EXIT_SUCCESS && independent ? EXIT_SUCCESS : EXIT_FAILURE;
}
