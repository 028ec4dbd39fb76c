// Colour-map and texture edits rebuild nothing. Three unlit actors: a sphere coloured through a
// lookup table with InterpolateScalarsBeforeMapping (the map becomes a texture), a sphere coloured
// through a lookup table per vertex, and a plane with a vtkTexture. 100 times: both lookup tables
// get a new hue and a new range, the texture image a new colour, and the scene is rendered again.
// After the first frame every frame must build 0 object BVHs and keep the top-level BVH, the
// texture memory must stay that of the first frame, and each actor's centre pixel must show the
// colour of this edit. Then textures no longer used (actor removed, colour map switched off) must
// be freed.
#include "WhittedTestUtilities.h"

#include "vtkCamera.h"
#include "vtkElevationFilter.h"
#include "vtkImageData.h"
#include "vtkLookupTable.h"
#include "vtkTexture.h"

#include <cstdio>
#include <cstdlib>

namespace
{
// Window pixel (8-bit RGB) under the world point p.
std::array<int, 3> PixelAt(
  vtkRenderer* ren, const std::vector<unsigned char>& pixels, const int size[2], const double p[3])
{
  ren->SetWorldPoint(p[0], p[1], p[2], 1.0);
  ren->WorldToDisplay();
  double d[3];
  ren->GetDisplayPoint(d);
  const int x = static_cast<int>(d[0]), y = static_cast<int>(d[1]);
  const size_t i = 3 * (static_cast<size_t>(y) * size[0] + x);
  return { pixels[i], pixels[i + 1], pixels[i + 2] };
}

// Largest difference in 8-bit steps between a pixel and a colour in [0,1].
int Difference(const std::array<int, 3>& px, const double c[3])
{
  int worst = 0;
  for (int k = 0; k < 3; ++k)
  {
    worst = std::max(worst, std::abs(px[k] - static_cast<int>(std::lround(255.0 * c[k]))));
  }
  return worst;
}

// An unlit actor: its pixels are exactly its (mapped) colour.
void Unlit(vtkActor* a)
{
  a->GetProperty()->LightingOff();
  a->GetProperty()->SetAmbient(0.0);
  a->GetProperty()->SetDiffuse(1.0);
}

// Lookup table mapping every value in range to one fully saturated hue.
void SetHue(vtkLookupTable* lut, double hue, double lo, double hi)
{
  lut->SetHueRange(hue, hue);
  lut->SetSaturationRange(1.0, 1.0);
  lut->SetValueRange(1.0, 1.0);
  lut->SetRange(lo, hi);
  lut->Build();
}
}

int TestWhittedColorMapEdits(int, char*[])
{
  using namespace whittedtest;
  const int size[2] = { 160, 120 };
  vtkNew<vtkRenderer> ren;
  auto win = MakeWindow(size[0], size[1]);
  win->AddRenderer(ren);

  vtkNew<vtkSphereSource> source;
  source->SetThetaResolution(32);
  source->SetPhiResolution(16);
  source->SetRadius(0.8);
  vtkNew<vtkElevationFilter> elevation; // point scalars 0 (bottom) .. 1 (top)
  elevation->SetInputConnection(source->GetOutputPort());
  elevation->SetLowPoint(0, -0.8, 0);
  elevation->SetHighPoint(0, 0.8, 0);

  // Left: InterpolateScalarsBeforeMapping (the tracer gets the map as a colour texture)
  vtkNew<vtkLookupTable> lutTexture;
  SetHue(lutTexture, 0.0, 0.0, 1.0);
  vtkNew<vtkPolyDataMapper> m1;
  m1->SetInputConnection(elevation->GetOutputPort());
  m1->SetLookupTable(lutTexture);
  m1->UseLookupTableScalarRangeOn();
  m1->InterpolateScalarsBeforeMappingOn();
  vtkNew<vtkActor> a1;
  a1->SetMapper(m1);
  a1->SetPosition(-1.0, 0.5, 0.0);
  Unlit(a1);
  ren->AddActor(a1);

  // Right: colours mapped per vertex
  vtkNew<vtkLookupTable> lutVertex;
  SetHue(lutVertex, 0.5, 0.0, 1.0);
  vtkNew<vtkPolyDataMapper> m2;
  m2->SetInputConnection(elevation->GetOutputPort());
  m2->SetLookupTable(lutVertex);
  m2->UseLookupTableScalarRangeOn();
  vtkNew<vtkActor> a2;
  a2->SetMapper(m2);
  a2->SetPosition(1.0, 0.5, 0.0);
  Unlit(a2);
  ren->AddActor(a2);

  // Bottom: a textured plane whose 4 x 4 image is refilled with one colour per edit
  vtkNew<vtkImageData> image;
  image->SetDimensions(4, 4, 1);
  image->AllocateScalars(VTK_UNSIGNED_CHAR, 3);
  auto fill = [&](int r, int g, int b)
  {
    auto* p = static_cast<unsigned char*>(image->GetScalarPointer());
    for (int i = 0; i < 16; ++i)
    {
      p[3 * i] = static_cast<unsigned char>(r);
      p[3 * i + 1] = static_cast<unsigned char>(g);
      p[3 * i + 2] = static_cast<unsigned char>(b);
    }
    image->Modified();
  };
  fill(200, 100, 50);
  vtkNew<vtkPlaneSource> plane;
  plane->SetOrigin(-1.5, -1.4, 0);
  plane->SetPoint1(1.5, -1.4, 0);
  plane->SetPoint2(-1.5, -0.6, 0);
  vtkNew<vtkPolyDataMapper> m3;
  m3->SetInputConnection(plane->GetOutputPort());
  vtkNew<vtkTexture> texture;
  texture->SetInputData(image);
  vtkNew<vtkActor> a3;
  a3->SetMapper(m3);
  a3->SetTexture(texture);
  Unlit(a3);
  ren->AddActor(a3);

  ren->SetBackground(0.1, 0.1, 0.1);
  LookAt(ren, { 0, 0, 6 }, { 0, 0, 0 }, 40);
  vtkNew<vtkWhittedPass> pass;
  vtkWhittedFrameStatistics* stats = pass->GetLastFrameStatistics();
  ren->SetPass(pass);
  win->Render();
  const vtkTypeUInt64 firstTextureBytes = stats->GetTextureBytes();
  const vtkTypeUInt64 firstTextures = stats->GetNumberOfTextures();
  std::printf("first frame: %d object BVHs, %d geometries converted, %llu textures, %llu texture "
              "bytes\n",
    stats->GetNumberOfObjectsRebuilt(), stats->GetNumberOfGeometriesConverted(),
    static_cast<unsigned long long>(firstTextures),
    static_cast<unsigned long long>(firstTextureBytes));

  // Centre of each actor as the camera sees it (front of the spheres, middle of the plane)
  const double c1[3] = { -1.0, 0.5, 0.8 }, c2[3] = { 1.0, 0.5, 0.8 }, c3[3] = { 0.0, -1.0, 0.0 };
  int objectsRebuilt = 0, topLevelRebuilt = 0, converted = 0, worstColour = 0;
  vtkTypeUInt64 maxTextureBytes = firstTextureBytes, maxTextures = firstTextures;
  bool ok = true;
  for (int edit = 1; edit <= 100; ++edit)
  {
    const double hue = std::fmod(0.37 * edit, 1.0);
    const double hi = 1.0 + 0.05 * edit; // new range too: new colour-map coordinates
    SetHue(lutTexture, hue, -0.02 * edit, hi);
    SetHue(lutVertex, std::fmod(hue + 0.5, 1.0), -0.01 * edit, hi);
    const int r = (37 * edit) % 256, g = (101 * edit) % 256, b = (173 * edit) % 256;
    fill(r, g, b);
    win->Render();

    objectsRebuilt += stats->GetNumberOfObjectsRebuilt();
    topLevelRebuilt += stats->GetTopLevelRebuilt() ? 1 : 0;
    converted += stats->GetNumberOfGeometriesConverted();
    maxTextureBytes = std::max(maxTextureBytes, stats->GetTextureBytes());
    maxTextures = std::max(maxTextures, stats->GetNumberOfTextures());

    const std::vector<unsigned char> pixels = GrabPixels(win);
    double want1[3], want2[3];
    lutTexture->GetColor(0.5, want1);
    lutVertex->GetColor(0.5, want2);
    const double want3[3] = { r / 255.0, g / 255.0, b / 255.0 };
    const int d1 = Difference(PixelAt(ren, pixels, size, c1), want1);
    const int d2 = Difference(PixelAt(ren, pixels, size, c2), want2);
    const int d3 = Difference(PixelAt(ren, pixels, size, c3), want3);
    worstColour = std::max(worstColour, std::max(d1, std::max(d2, d3)));
    if (std::max(d1, std::max(d2, d3)) > 2)
    {
      std::printf("edit %d: centre pixels differ from the map colours by %d, %d, %d (of 255)   "
                  "<-- FAIL\n",
        edit, d1, d2, d3);
      ok = false;
    }
  }
  std::printf("100 edits: %d object BVHs built (want 0), top level rebuilt %d times (want 0), %d "
              "geometries converted; textures at most %llu (first frame %llu), texture bytes at "
              "most %llu (first frame %llu); centre pixels off by at most %d/255 (want <= 2)\n",
    objectsRebuilt, topLevelRebuilt, converted, static_cast<unsigned long long>(maxTextures),
    static_cast<unsigned long long>(firstTextures),
    static_cast<unsigned long long>(maxTextureBytes),
    static_cast<unsigned long long>(firstTextureBytes), worstColour);
  ok &= objectsRebuilt == 0 && topLevelRebuilt == 0 && maxTextureBytes <= firstTextureBytes &&
    maxTextures <= firstTextures && firstTextures == 2;

  // Unused textures are freed: the textured actor removed, then the colour map no longer needed
  ren->RemoveActor(a3);
  win->Render();
  const vtkTypeUInt64 withoutPlane = stats->GetNumberOfTextures();
  m1->InterpolateScalarsBeforeMappingOff();
  win->Render();
  const vtkTypeUInt64 withoutMap = stats->GetNumberOfTextures();
  std::printf("textures held: %llu after removing the textured actor (want 1), %llu after "
              "InterpolateScalarsBeforeMappingOff (want 0), %llu bytes\n",
    static_cast<unsigned long long>(withoutPlane), static_cast<unsigned long long>(withoutMap),
    static_cast<unsigned long long>(stats->GetTextureBytes()));
  ok &= withoutPlane == 1 && withoutMap == 0 && stats->GetTextureBytes() == 0;
  return ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
