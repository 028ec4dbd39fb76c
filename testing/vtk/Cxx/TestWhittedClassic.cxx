// Whitted's classic scene (vtkWhittedClassicScene, from the core's one description of it):
// checkerboard floor, mirror sphere, glass sphere, one point light. The Python test
// TestWhittedPythonClassic renders it through the wrapping against the same baseline.
//
// Independent checks besides the baseline:
// - VTK's raster of the floor (CheckAgainstRaster): local shading, shadows between the ambient
//   term and the unshadowed value, the mirror sphere's umbra exactly the ambient term.
// - The mirror sphere, analytically: traced once more with its own colour off (ambient, diffuse,
//   specular 0), a mirror pixel shows only the reflected light; where the exact sphere's reflected
//   ray (from the pixel centre) meets the floor at a point the camera sees directly, or meets
//   nothing, that is REFLECTANCE (0.8) x VTK's raster colour of that floor point, or x the
//   background. And the sphere's own share -- the full image minus that -- is VTK's raster body
//   colour (ambient + diffuse, specular off) x (1 - REFLECTANCE) plus VTK's specular highlight
//   (the energy rule).
#include "WhittedTestUtilities.h"

#include "vtkMatrix4x4.h"
#include "vtkRegressionTestImage.h"
#include "vtkWhittedClassicScene.h"

#include <cstdio>
#include <iostream>

namespace
{
using namespace whittedtest;

// World <-> pixel through the camera's composite projection (pixel centres at integer + 0.5)
struct Projection
{
  vtkNew<vtkMatrix4x4> M, Inverse;
  int W, H;
  double Eye[3];
  Projection(vtkRenderer* ren, int w, int h)
    : W(w)
    , H(h)
  {
    vtkCamera* cam = ren->GetActiveCamera();
    M->DeepCopy(cam->GetCompositeProjectionTransformMatrix(double(w) / h, -1, 1));
    vtkMatrix4x4::Invert(M, Inverse);
    cam->GetPosition(Eye);
  }
  // Unit direction of the camera ray through pixel (x, y)'s centre
  void Ray(int x, int y, double d[3]) const
  {
    const double ndc[4] = { 2.0 * (x + 0.5) / W - 1.0, 2.0 * (y + 0.5) / H - 1.0, 0.0, 1.0 };
    double p[4];
    Inverse->MultiplyPoint(ndc, p);
    double n = 0.0;
    for (int i = 0; i < 3; ++i)
    {
      d[i] = p[i] / p[3] - Eye[i];
      n += d[i] * d[i];
    }
    for (int i = 0; i < 3; ++i)
    {
      d[i] /= std::sqrt(n);
    }
  }
  // Pixel containing world point q, and its window depth
  bool Pixel(const double q[3], int& x, int& y, double& depth) const
  {
    const double in[4] = { q[0], q[1], q[2], 1.0 };
    double p[4];
    M->MultiplyPoint(in, p);
    x = static_cast<int>(std::floor((p[0] / p[3] + 1.0) * 0.5 * W));
    y = static_cast<int>(std::floor((p[1] / p[3] + 1.0) * 0.5 * H));
    depth = 0.5 * p[2] / p[3] + 0.5;
    return x >= 0 && y >= 0 && x < W && y < H;
  }
};

// Nearest positive t where the ray o + t d meets the sphere (c, r) grown by margin; < 0 if none
double HitSphere(const double o[3], const double d[3], const double c[3], double r)
{
  double oc[3] = { o[0] - c[0], o[1] - c[1], o[2] - c[2] };
  const double b = oc[0] * d[0] + oc[1] * d[1] + oc[2] * d[2];
  const double q = oc[0] * oc[0] + oc[1] * oc[1] + oc[2] * oc[2] - r * r;
  const double disc = b * b - q;
  if (disc < 0.0)
  {
    return -1.0;
  }
  const double t0 = -b - std::sqrt(disc), t1 = -b + std::sqrt(disc);
  return t0 > 1e-9 ? t0 : (t1 > 1e-9 ? t1 : -1.0);
}

void SphereOf(vtkActor* a, double c[3], double& r)
{
  const double* b = a->GetBounds();
  for (int i = 0; i < 3; ++i)
  {
    c[i] = 0.5 * (b[2 * i] + b[2 * i + 1]);
  }
  r = 0.5 * (b[1] - b[0]);
}

bool CheckMirror(vtkRenderWindow* win, vtkRenderer* ren, vtkWhittedPass* pass,
  vtkWhittedClassicScene* scene)
{
  int* size = win->GetSize();
  const int w = size[0], h = size[1];
  vtkActor* mirror = scene->GetMirror();
  vtkProperty* mp = mirror->GetProperty();
  const double kr = mp->GetInformation()->Get(vtkWhittedMaterialKeys::REFLECTANCE())[0];
  const std::vector<unsigned char> traced = GrabPixels(win);

  // Traced with the mirror's own colour off: only the reflected light
  const double ambient = mp->GetAmbient(), diffuse = mp->GetDiffuse(), specular = mp->GetSpecular();
  mp->SetAmbient(0.0);
  mp->SetDiffuse(0.0);
  mp->SetSpecular(0.0);
  win->Render();
  const std::vector<unsigned char> reflected = GrabPixels(win);
  mp->SetAmbient(ambient);
  mp->SetDiffuse(diffuse);

  // VTK's raster: body only (specular off), then everything; depth with and without the mirror
  ren->SetPass(nullptr);
  std::vector<unsigned char> body, full, ignored;
  std::vector<float> zFull, zNoMirror;
  win->Render();
  GrabWithDepth(win, body, zFull);
  mp->SetSpecular(specular);
  win->Render();
  GrabWithDepth(win, full, zFull);
  mirror->SetVisibility(false);
  win->Render();
  GrabWithDepth(win, ignored, zNoMirror);
  mirror->SetVisibility(true);
  ren->SetPass(pass);
  win->Render();

  double c[3], r, cg[3], rg;
  SphereOf(mirror, c, r);
  SphereOf(scene->GetGlass(), cg, rg);
  const double* fb = scene->GetFloor()->GetBounds(); // y = 0, 10 x 14 unit cells
  const double* bg = ren->GetBackground();
  const Projection proj(ren, w, h);

  int mirrorPixels = 0, energyOff = 0, floorChecked = 0, floorOff = 0, skyChecked = 0, skyOff = 0;
  for (int y = 1; y < h - 1; ++y)
  {
    for (int x = 1; x < w - 1; ++x)
    {
      // Mirror pixels (and their neighbours): VTK's depth changes without the mirror
      bool inside = true;
      for (int dy = -1; dy <= 1; ++dy)
      {
        for (int dx = -1; dx <= 1; ++dx)
        {
          const int j = (y + dy) * w + x + dx;
          inside &= zFull[j] != zNoMirror[j];
        }
      }
      if (!inside)
      {
        continue;
      }
      const int i = y * w + x;
      ++mirrorPixels;

      // Energy rule: own share = (1 - kr) body + specular
      int d = 0;
      for (int k = 0; k < 3; ++k)
      {
        const double own = traced[3 * i + k] - double(reflected[3 * i + k]);
        const double expected =
          (1.0 - kr) * body[3 * i + k] + (double(full[3 * i + k]) - body[3 * i + k]);
        d = std::max(d, int(std::lround(std::abs(own - expected))));
      }
      energyOff += d > 3;

      // Reflected ray of the exact sphere
      double dir[3];
      proj.Ray(x, y, dir);
      const double t = HitSphere(proj.Eye, dir, c, r);
      if (t < 0.0)
      {
        continue;
      }
      double p[3], n[3], rd[3];
      for (int k = 0; k < 3; ++k)
      {
        p[k] = proj.Eye[k] + t * dir[k];
        n[k] = (p[k] - c[k]) / r;
      }
      const double dn = dir[0] * n[0] + dir[1] * n[1] + dir[2] * n[2];
      for (int k = 0; k < 3; ++k)
      {
        rd[k] = dir[k] - 2.0 * dn * n[k];
      }
      // Clear of the glass sphere by a margin
      if (HitSphere(p, rd, cg, rg + 0.1) > 0.0)
      {
        continue;
      }
      double expected[3];
      if (rd[1] < 0.0)
      {
        const double tf = -p[1] / rd[1];
        const double q[3] = { p[0] + tf * rd[0], 0.0, p[2] + tf * rd[2] };
        if (q[0] < fb[0] || q[0] > fb[1] || q[2] < fb[4] || q[2] > fb[5])
        {
          continue;
        }
        // Inside a checker cell by a margin, seen directly by the camera there, unshadowed (the
        // traced floor equals VTK's raster there)
        const double fx = q[0] - std::floor(q[0]), fz = q[2] - std::floor(q[2]);
        int qx, qy;
        double qz;
        if (std::min({ fx, 1.0 - fx, fz, 1.0 - fz }) < 0.1 || !proj.Pixel(q, qx, qy, qz))
        {
          continue;
        }
        const int j = qy * w + qx;
        if (std::abs(zFull[j] - qz) > 1e-4 || zFull[j] != zNoMirror[j] ||
          ChannelDifference({ traced[3 * j], traced[3 * j + 1], traced[3 * j + 2] },
            { full[3 * j], full[3 * j + 1], full[3 * j + 2] })[0] > 2)
        {
          continue;
        }
        for (int k = 0; k < 3; ++k)
        {
          expected[k] = kr * full[3 * j + k];
        }
        ++floorChecked;
      }
      else
      {
        for (int k = 0; k < 3; ++k)
        {
          expected[k] = kr * 255.0 * bg[k];
        }
        ++skyChecked;
      }
      int e = 0;
      for (int k = 0; k < 3; ++k)
      {
        e = std::max(e, int(std::lround(std::abs(reflected[3 * i + k] - expected[k]))));
      }
      (rd[1] < 0.0 ? floorOff : skyOff) += e > 3;
    }
  }
  const double energyShare = double(energyOff) / std::max(1, mirrorPixels);
  const double floorShare = double(floorOff) / std::max(1, floorChecked);
  const double skyShare = double(skyOff) / std::max(1, skyChecked);
  const bool ok = mirrorPixels > 1000 && floorChecked > 200 && skyChecked > 200 &&
    energyShare <= 0.02 && floorShare <= 0.05 && skyShare <= 0.02;
  std::printf("[mirror] %d mirror pixels; own share (traced - reflected only) off (1-kr) x VTK body "
              "+ VTK specular by >3/255: %.2f%% (allowed 2%%); reflected light off kr x VTK's floor "
              "colour by >3/255: %.2f%% of %d pixels (allowed 5%%), off kr x background: %.2f%% of "
              "%d pixels (allowed 2%%): %s\n",
    mirrorPixels, 100 * energyShare, 100 * floorShare, floorChecked, 100 * skyShare, skyChecked,
    ok ? "ok" : "FAILED");
  return ok;
}
} // namespace

int TestWhittedClassic(int argc, char* argv[])
{
  vtkNew<vtkRenderer> ren;
  auto win = MakeWindow(320, 240);
  win->AddRenderer(ren);

  vtkNew<vtkWhittedClassicScene> scene;
  scene->SetResolution(48);
  scene->AddToRenderer(ren);

  vtkNew<vtkWhittedPass> pass;
  ApplyTestSwitches(pass);
  ren->SetPass(pass);
  win->Render();
  std::cout << pass->GetLastFrameReport();
  const int baseline = CheckBaseline(win, argc, argv);

  // Independent: VTK's raster of the floor (the spheres left out; the mirror sphere's shadow is an
  // umbra), and the mirror sphere against the analytic reflection
  RasterOracle raster;
  raster.Excluded = { scene->GetMirror(), scene->GetGlass() };
  raster.MinShadowShare = 0.03;
  raster.MinUmbraShare = 0.1;
  bool independent = CheckAgainstRaster("Classic", win, pass, raster);
  independent &= CheckMirror(win, ren, pass, scene);
  return baseline == EXIT_SUCCESS && independent ? EXIT_SUCCESS : EXIT_FAILURE;
}
