// libFuzzer target: random VTK input through the pass's scene conversion (vtkWhittedSceneConverter
// and vtkWhittedPolyDataConverter, compiled into this target with the sanitizers), then committed
// and rendered by the core at 8x8 -- the same calls vtkWhittedPass makes, without a render window
// (so no X display is needed and an input runs in well under a millisecond).
//
// The input drives: points (float or double, small values, NaN, +-Inf, huge, denormal, offset to
// 1e7); verts / lines / polys / strips with ids in range, just out of range, negative or huge, and
// malformed cell arrays (offsets that do not fit the connectivity); point, cell and field data
// arrays of many types, component counts and tuple counts (too short too) used as scalars,
// normals, texture coordinates or colour-by arrays; the mapper (plain, composite over a multiblock
// with empty leaves and block attributes, dataset mapper) and its colouring settings and lookup
// table; the vtkProperty (representation, spheres / tubes, sizes, interpolation, colours and
// coefficients with any values), the Whitted information keys with any length and values; actor
// transforms, a texture, instancing, lights, background; a second conversion after a change.
// Invariant: no crash, no sanitizer report, and the frame checks of fuzz_checks.h: no safety net catches
// anything (the depth net: with the camera fitted to the scene's bounds, where those are finite, at most 1e30 and
// at least 1e-6 of their distance from the origin), colours finite and >= 0, depths finite in [0, 1], exactly 1
// where a pixel's camera ray hits nothing and (fitted camera) the hit's GL depth where it hits.
#include "vtkWhittedMaterialKeys.h"  // a conversion source, compiled into this target
#include "vtkWhittedMatrix.h"
#include "vtkWhittedSceneConverter.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCompositeDataDisplayAttributes.h"
#include "vtkCompositePolyDataMapper2.h"
#include "vtkDataArray.h"
#include "vtkDataSetMapper.h"
#include "vtkGlyph3DMapper.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationDoubleKey.h"
#include "vtkInformationDoubleVectorKey.h"
#include "vtkLight.h"
#include "vtkLookupTable.h"
#include "vtkMatrix4x4.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkInformationObjectBaseKey.h"
#include "vtkInformationStringKey.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointGaussianMapper.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"
#include "vtkTexture.h"

#include "shading/camera.h"
#include "image/renderer.h"
#include "scene/scene.h"
#include "fuzz_bytes.h"
#include "fuzz_checks.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace {
struct Reader : whitted_fuzz::Bytes {
  using Bytes::Bytes;

  // A coordinate or property value: mostly ordinary, sometimes extreme
  double value() {
    static const double special[] = {std::numeric_limits<double>::quiet_NaN(),
                                     std::numeric_limits<double>::infinity(),
                                     -std::numeric_limits<double>::infinity(),
                                     0.0,
                                     -0.0,
                                     1e-310,
                                     1e308,
                                     -1e308,
                                     1e7,
                                     -1e-7,
                                     3.5e38,
                                     1e20,
                                     1e-30,
                                     1.0,
                                     -1.0,
                                     0.5};
    switch (u8() % 10) {
      case 0:
      case 1:
      case 2:
      case 3:
      case 4:
        return get<int8_t>() / 16.0;
      case 5:
        return get<int16_t>() / 256.0;
      case 6:
        return special[u8() % (sizeof special / sizeof special[0])];
      case 7:
        return 1e7 + get<int16_t>() / 256.0;
      case 8:
        return get<int16_t>() * 1e-6;
      default:
        return get<double>();
    }
  }
  // A point id: mostly valid, sometimes just outside, negative or huge
  vtkIdType id(vtkIdType np) {
    const uint8_t b = u8();
    if (b == 255) {
      return get<int64_t>();
    }
    return static_cast<vtkIdType>(b % (np + 3)) - 1;
  }
};

void RandomCells(Reader& r, vtkIdType np, vtkCellArray* cells) {
  if (r.u8() % 8 == 0) {
    // Malformed: offsets that need not be monotonic or match the connectivity
    vtkNew<vtkIdTypeArray> offsets, connectivity;
    const int no = r.u8() % 5, nc = r.u8() % 8;
    for (int i = 0; i < no; ++i) {
      offsets->InsertNextValue(static_cast<vtkIdType>(r.u8() % 10) - 1);
    }
    for (int i = 0; i < nc; ++i) {
      connectivity->InsertNextValue(r.id(np));
    }
    cells->SetData(offsets, connectivity);
    return;
  }
  const int count = r.u8() % 8;
  for (int c = 0; c < count; ++c) {
    const int n = r.u8() % 9;
    std::vector<vtkIdType> ids(static_cast<size_t>(n));
    for (vtkIdType& id : ids) {
      id = r.id(np);
    }
    cells->InsertNextCell(n, ids.data());
  }
}

vtkSmartPointer<vtkDataArray> RandomArray(Reader& r, vtkIdType expected, int index) {
  static const int types[] = {VTK_FLOAT, VTK_DOUBLE,  VTK_UNSIGNED_CHAR, VTK_INT,
                              VTK_SHORT, VTK_ID_TYPE, VTK_SIGNED_CHAR,   VTK_UNSIGNED_SHORT};
  const int type = types[r.u8() % 8];
  auto a = vtk::TakeSmartPointer(vtkDataArray::CreateDataArray(type));
  const int comps = 1 + r.u8() % 5;
  const vtkIdType tuples = std::max<vtkIdType>(0, expected + (r.u8() % 5) - 3);
  a->SetNumberOfComponents(comps);
  a->SetNumberOfTuples(tuples);
  const bool real = type == VTK_FLOAT || type == VTK_DOUBLE;
  for (vtkIdType t = 0; t < tuples; ++t) {
    for (int c = 0; c < comps; ++c) {
      double v = real ? r.value() : static_cast<double>(r.u8());
      if (type == VTK_FLOAT && std::isfinite(v) && std::abs(v) > 3e38) {
        v = std::copysign(std::numeric_limits<double>::infinity(), v);
      }
      a->SetComponent(t, c, v);
    }
  }
  a->SetName(("a" + std::to_string(index)).c_str());
  return a;
}

// Attaches random arrays to attribute data as scalars / normals / tcoords / plain arrays
void RandomAttributes(Reader& r, vtkDataSetAttributes* attrs, vtkIdType expected, int base) {
  const int count = r.u8() % 4;
  for (int i = 0; i < count; ++i) {
    auto a = RandomArray(r, expected, base + i);
    switch (r.u8() % 4) {
      case 0:
        attrs->SetScalars(a);
        break;
      case 1:
        attrs->SetNormals(a);  // refused (with an error) unless 3 components
        break;
      case 2:
        attrs->SetTCoords(a);  // refused unless 1 to 3 components
        break;
      default:
        attrs->AddArray(a);
        break;
    }
  }
}

vtkSmartPointer<vtkPolyData> RandomPolyData(Reader& r) {
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  const vtkIdType np = r.u8() % 48;
  vtkNew<vtkPoints> points;
  points->SetDataType(r.bit() ? VTK_DOUBLE : VTK_FLOAT);
  points->SetNumberOfPoints(np);
  for (vtkIdType i = 0; i < np; ++i) {
    double x[3];
    for (double& c : x) {
      c = r.value();
      if (points->GetDataType() == VTK_FLOAT && std::isfinite(c) && std::abs(c) > 3e38) {
        c = std::copysign(std::numeric_limits<double>::infinity(), c);  // as a float store would
      }
    }
    points->SetPoint(i, x);
  }
  poly->SetPoints(points);
  vtkNew<vtkCellArray> verts, lines, polys, strips;
  RandomCells(r, np, verts);
  RandomCells(r, np, lines);
  RandomCells(r, np, polys);
  RandomCells(r, np, strips);
  poly->SetVerts(verts);
  poly->SetLines(lines);
  poly->SetPolys(polys);
  poly->SetStrips(strips);
  // Attribute arrays sized from the counts (a malformed cell array may report any count)
  const vtkIdType nc =
      std::max<vtkIdType>(0, std::min<vtkIdType>(64, verts->GetNumberOfCells() + lines->GetNumberOfCells() +
                                                         polys->GetNumberOfCells() + strips->GetNumberOfCells()));
  RandomAttributes(r, poly->GetPointData(), np, 0);
  RandomAttributes(r, poly->GetCellData(), nc, 4);
  if (r.bit()) {
    poly->GetFieldData()->AddArray(RandomArray(r, 1 + r.u8() % 3, 8));
  }
  return poly;
}

void RandomMapperSettings(Reader& r, vtkMapper* m) {
  m->SetScalarVisibility(r.bit());
  m->SetScalarMode(r.u8() % 6);
  m->SetColorMode(r.u8() % 3);
  m->SetInterpolateScalarsBeforeMapping(r.bit());
  const double lo = r.value(), hi = r.value();
  m->SetScalarRange(lo, hi);
  m->SetUseLookupTableScalarRange(r.bit());
  m->SetFieldDataTupleId(static_cast<vtkIdType>(r.u8() % 5) - 1);
  if (r.bit()) {
    const std::string name = "a" + std::to_string(r.u8() % 10);
    m->SelectColorArray(name.c_str());
    m->SetArrayAccessMode(VTK_GET_ARRAY_BY_NAME);
    m->SetArrayComponent(r.u8() % 6);
  } else if (r.bit()) {
    m->SelectColorArray(r.u8() % 10);
    m->SetArrayAccessMode(VTK_GET_ARRAY_BY_ID);
  }
  if (r.bit()) {
    vtkNew<vtkLookupTable> lut;
    lut->SetNumberOfTableValues(1 + r.u8() % 64);
    const double a = r.value(), b = r.value();
    if (a < b) {
      lut->SetTableRange(a, b);
    }
    lut->SetScale(r.u8() % 4 == 0 ? VTK_SCALE_LOG10 : VTK_SCALE_LINEAR);
    lut->SetUseAboveRangeColor(r.bit());
    lut->SetUseBelowRangeColor(r.bit());
    lut->SetNanColor(r.value(), r.value(), r.value(), r.value());
    lut->SetVectorMode(r.u8() % 3);
    lut->Build();
    m->SetLookupTable(lut);
  }
}

void RandomProperty(Reader& r, vtkProperty* p) {
  p->SetRepresentation(r.u8() % 3);
  p->SetRenderPointsAsSpheres(r.bit());
  p->SetRenderLinesAsTubes(r.bit());
  p->SetPointSize(static_cast<float>(r.value()));
  p->SetLineWidth(static_cast<float>(r.value()));
  p->SetInterpolation(r.u8() % 4);
  p->SetOpacity(r.value());
  p->SetAmbient(r.value());
  p->SetDiffuse(r.value());
  p->SetSpecular(r.value());
  p->SetSpecularPower(r.value());
  if (r.bit()) {
    p->SetColor(r.value(), r.value(), r.value());
  }
  if (r.bit()) {
    p->SetAmbientColor(r.value(), r.value(), r.value());
    p->SetDiffuseColor(r.value(), r.value(), r.value());
    p->SetSpecularColor(r.value(), r.value(), r.value());
  }
  p->SetLighting(r.u8() % 8 != 0);
  p->SetBackfaceCulling(r.u8() % 8 == 0);
  vtkInformation* info = p->GetInformation();
  for (vtkInformationDoubleVectorKey* key :
       {vtkWhittedMaterialKeys::REFLECTANCE(), vtkWhittedMaterialKeys::TRANSMITTANCE(),
        vtkWhittedMaterialKeys::ATTENUATION_COLOR()}) {
    const int n = r.u8() % 6;  // 0 = not set
    if (n > 0) {
      double v[4] = {0.0, 0.0, 0.0, 0.0};
      for (int i = 0; i < n - 1; ++i) {
        v[i] = r.value();
      }
      info->Set(key, v, n - 1);
    }
  }
  if (r.bit()) {
    info->Set(vtkWhittedMaterialKeys::INDEX_OF_REFRACTION(), r.value());
  }
  if (r.bit()) {
    info->Set(vtkWhittedMaterialKeys::ATTENUATION_DISTANCE(), r.value());
  }
}

void RandomTransform(Reader& r, vtkActor* a) {
  switch (r.u8() % 4) {
    case 0:
      break;
    case 1:
      a->SetPosition(r.value(), r.value(), r.value());
      a->SetScale(r.value(), r.value(), r.value());
      break;
    case 2:
      a->SetOrientation(r.value(), r.value(), r.value());
      a->SetOrigin(r.value(), r.value(), r.value());
      break;
    default: {
      vtkNew<vtkMatrix4x4> m;
      for (int i = 0; i < 16; ++i) {
        m->SetElement(i / 4, i % 4, r.u8() % 3 == 0 ? r.value() : (i % 5 == 0 ? 1.0 : 0.0));
      }
      a->SetUserMatrix(m);
      break;
    }
  }
}

vtkSmartPointer<vtkTexture> RandomTexture(Reader& r) {
  vtkNew<vtkImageData> image;
  const int w = r.u8() % 5, h = r.u8() % 5;
  image->SetDimensions(w, h, 1);
  const vtkIdType n = static_cast<vtkIdType>(w) * h;
  image->GetPointData()->SetScalars(RandomArray(r, n, 9));
  auto t = vtkSmartPointer<vtkTexture>::New();
  t->SetInputData(image);
  t->SetInterpolate(r.bit());
  t->SetRepeat(r.bit());
  t->SetColorMode(r.u8() % 3);
  return t;
}

void RandomLights(Reader& r, vtkRenderer* ren) {
  const int n = r.u8() % 3;
  for (int i = 0; i < n; ++i) {
    vtkNew<vtkLight> l;
    l->SetLightType(1 + r.u8() % 3);
    l->SetPositional(r.bit());
    l->SetPosition(r.value(), r.value(), r.value());
    l->SetFocalPoint(r.value(), r.value(), r.value());
    l->SetDiffuseColor(r.value(), r.value(), r.value());
    l->SetIntensity(r.value());
    l->SetConeAngle(r.value());
    l->SetExponent(r.value());
    l->SetAttenuationValues(r.value(), r.value(), r.value());
    l->SetSwitch(r.u8() % 4 != 0);
    l->SetShadowAttenuation(static_cast<float>(r.value()));
    ren->AddLight(l);
  }
}
extern "C" int LLVMFuzzerInitialize(int*, char***) {
  vtkObject::GlobalWarningDisplayOff();  // conversion warnings and VTK's own errors: not printed
  return 0;
}

/// A glyph mapper over poly's points: one or two sources (poly itself, an empty polydata), and the
/// placement settings with arrays chosen by name (a0..a9: any array RandomPolyData made, or none).
vtkSmartPointer<vtkMapper> RandomGlyphMapper(Reader& r, vtkPolyData* poly) {
  auto glyphs = vtkSmartPointer<vtkGlyph3DMapper>::New();
  glyphs->SetInputData(poly);
  const vtkSmartPointer<vtkPolyData> source = r.bit() ? RandomPolyData(r) : vtkSmartPointer<vtkPolyData>(poly);
  glyphs->SetSourceData(0, source);
  if (r.bit()) {
    glyphs->SetSourceData(1, vtkSmartPointer<vtkPolyData>::New());
  }
  auto name = [&r]() { return "a" + std::to_string(r.u8() % 10); };
  glyphs->SetScaling(r.bit());
  glyphs->SetScaleMode(r.u8() % 3);
  glyphs->SetScaleFactor(r.value());
  glyphs->SetRange(r.value(), r.value());
  glyphs->SetClamping(r.bit());
  glyphs->SetScaleArray(name().c_str());
  glyphs->SetOrient(r.bit());
  glyphs->SetOrientationMode(r.u8() % 3);
  glyphs->SetOrientationArray(name().c_str());
  glyphs->SetSourceIndexing(r.bit());
  glyphs->SetSourceIndexArray(name().c_str());
  glyphs->SetMasking(r.bit());
  glyphs->SetMaskArray(name().c_str());
  return glyphs;
}

/// A piecewise function of 0 to 3 random points.
vtkSmartPointer<vtkPiecewiseFunction> RandomFunction(Reader& r) {
  auto f = vtkSmartPointer<vtkPiecewiseFunction>::New();
  for (int i = r.u8() % 4; i > 0; --i) {
    f->AddPoint(r.value(), r.value());
  }
  return f;
}

/// Per-point radius keys on a property: an array by name, maybe a function.
void RandomRadiusKeys(Reader& r, vtkProperty* p) {
  p->GetInformation()->Set(vtkWhittedMaterialKeys::RADIUS_ARRAY(), ("a" + std::to_string(r.u8() % 10)).c_str());
  if (r.bit()) {
    p->GetInformation()->Set(vtkWhittedMaterialKeys::RADIUS_FUNCTION(), RandomFunction(r));
  }
}

/// A Point Gaussian mapper: scale and opacity arrays by name, transfer functions, scale factor.
vtkSmartPointer<vtkMapper> RandomGaussianMapper(Reader& r, vtkPolyData* poly) {
  auto gaussian = vtkSmartPointer<vtkPointGaussianMapper>::New();
  gaussian->SetInputData(poly);
  auto function = [&r]() { return RandomFunction(r); };
  if (r.bit()) {
    gaussian->SetScaleArray(("a" + std::to_string(r.u8() % 10)).c_str());
  }
  gaussian->SetScaleArrayComponent(static_cast<int>(r.u8() % 5) - 1);
  gaussian->SetScaleFunction(r.bit() ? function() : nullptr);
  gaussian->SetScaleFactor(r.value());
  if (r.bit()) {
    gaussian->SetOpacityArray(("a" + std::to_string(r.u8() % 10)).c_str());
  }
  gaussian->SetOpacityArrayComponent(static_cast<int>(r.u8() % 5) - 1);
  gaussian->SetScalarOpacityFunction(r.bit() ? function() : nullptr);
  return gaussian;
}

/// The mapper: plain, composite over a multiblock (empty leaves, block attributes), dataset mapper,
/// and rarely (kind bytes 250-255, so earlier corpus inputs keep their meaning) a glyph or Point
/// Gaussian mapper, or a plain one whose actor gets per-point radius keys (radiusKeys); then its
/// colouring settings.
vtkSmartPointer<vtkMapper> RandomMapper(Reader& r, vtkPolyData* poly, bool& radiusKeys) {
  vtkSmartPointer<vtkMapper> mapper;
  const uint8_t kindByte = r.u8();
  const int kind = kindByte >= 250 ? 3 + kindByte % 3 : kindByte % 3;
  radiusKeys = kind == 5;
  if (kind == 3) {
    mapper = RandomGlyphMapper(r, poly);
  } else if (kind == 4) {
    mapper = RandomGaussianMapper(r, poly);
  } else if (kind == 1) {
    vtkNew<vtkMultiBlockDataSet> mb;
    mb->SetNumberOfBlocks(4);
    mb->SetBlock(0, poly);
    mb->SetBlock(1, r.bit() ? vtkSmartPointer<vtkPolyData>::New() : nullptr);
    mb->SetBlock(2, r.bit() ? RandomPolyData(r) : nullptr);
    mb->SetBlock(3, poly);  // the same block twice
    auto cpdm = vtkSmartPointer<vtkCompositePolyDataMapper2>::New();
    cpdm->SetInputDataObject(mb);
    vtkNew<vtkCompositeDataDisplayAttributes> attrs;
    cpdm->SetCompositeDataDisplayAttributes(attrs);
    for (unsigned int block = 0; block < 6; ++block) {
      switch (r.u8() % 4) {
        case 1:
          cpdm->SetBlockVisibility(block, r.bit());
          break;
        case 2: {
          double c[3] = {r.value(), r.value(), r.value()};
          cpdm->SetBlockColor(block, c);
          break;
        }
        case 3:
          cpdm->SetBlockOpacity(block, r.value());
          break;
        default:
          break;
      }
    }
    mapper = cpdm;
  } else if (kind == 2) {
    auto dsm = vtkSmartPointer<vtkDataSetMapper>::New();
    dsm->SetInputData(poly);
    mapper = dsm;
  } else {
    auto pdm = vtkSmartPointer<vtkPolyDataMapper>::New();
    pdm->SetInputData(poly);
    mapper = pdm;
  }
  RandomMapperSettings(r, mapper);
  return mapper;
}

/// A change between two conversions, as successive frames make.
void RandomChange(Reader& r, vtkPolyData* poly, vtkActor* actor) {
  switch (r.u8() % 4) {
    case 1:
      poly->Modified();
      break;
    case 2:
      RandomProperty(r, actor->GetProperty());
      break;
    case 3:
      actor->SetVisibility(false);
      break;
    default:
      break;
  }
}

/// A camera looking at the scene's bounds, or one with any values. True for a fitted camera in the valid domain
/// of fuzz_checks.h: bounds finite, diagonal d in (1e-30, 1e30] and at least 1e-6 of the centre's largest
/// coordinate (the camera then sees the whole box between 1.58 d and 2.58 d, inside its clipping range
/// [0.1 d, 5 d], so only a hit point off its surface by about d could leave [0, 1] in depth).
bool RandomCamera(Reader& r, const whitted::Bounds3& b, vtkCamera* cam) {
  if (r.bit() && b.valid() && std::isfinite(b.diagonal()) && b.diagonal() > 0.0) {
    const whitted::Vec3 c = b.center();
    const double d = b.diagonal();
    cam->SetFocalPoint(c.x, c.y, c.z);
    cam->SetPosition(c.x + 0.3 * d, c.y + 0.5 * d, c.z + 2.0 * d);
    cam->SetClippingRange(0.1 * d, 5.0 * d);
    const double extent = std::max({ std::abs(c.x), std::abs(c.y), std::abs(c.z) });
    return whitted::isFinite(c) && d > 1e-30 && d <= 1e30 && d >= 1e-6 * extent;
  } else {
    cam->SetPosition(r.value(), r.value(), r.value());
    cam->SetFocalPoint(r.value(), r.value(), r.value());
    cam->SetViewUp(r.value(), r.value(), r.value());
    cam->SetViewAngle(r.value());
    cam->SetClippingRange(r.value(), r.value());
    cam->SetParallelProjection(r.bit());
    cam->SetParallelScale(r.value());
  }
  return false;
}

/// Renders 8x8 (settings from the input) and checks the frame (fuzz_checks.h; validCamera: see RandomCamera).
void RenderAndCheck(Reader& r, const whitted::Scene& scene, vtkCamera* cam, bool validCamera,
                    const vtkWhittedSceneConverter::Result& result) {
  const whitted::Mat4 worldToClip = vtkWhittedToMat4(cam->GetCompositeProjectionTransformMatrix(1.0, -1, 1));
  whitted::RenderSettings rs;
  rs.threads = 1;
  rs.samplesPerPixel = 1 + r.u8() % 2;
  rs.integrator.maxDepth = r.u8() % 6;
  rs.integrator.fresnel = r.bit();
  rs.integrator.headlightShading = result.HeadlightShading;
  rs.integrator.viewFromEye = cam->GetParallelProjection() != 0;
  double eye[3];
  cam->GetPosition(eye);
  rs.integrator.eye = whitted::Vec3(eye[0], eye[1], eye[2]);
  whitted::FrameBuffer fb;
  const whitted::Camera camera = whitted::Camera::fromViewProjection(worldToClip);
  const whitted::FrameStats fs = whitted::render(scene, camera, rs, 8, 8, fb);
  whitted_fuzz::checkFrame(scene, camera, rs.samplesPerPixel, validCamera, fs, fb);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  Reader r{data, size};
  vtkNew<vtkRenderer> ren;
  vtkSmartPointer<vtkPolyData> poly = RandomPolyData(r);
  bool radiusKeys = false;
  vtkSmartPointer<vtkMapper> mapper = RandomMapper(r, poly, radiusKeys);

  // Actors (a second one on the same mapper: instancing), lights, background
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  RandomProperty(r, actor->GetProperty());
  if (radiusKeys) {
    RandomRadiusKeys(r, actor->GetProperty());
  }
  RandomTransform(r, actor);
  if (r.u8() % 4 == 0) {
    actor->SetTexture(RandomTexture(r));
  }
  ren->AddActor(actor);
  vtkNew<vtkActor> twin;
  if (r.bit()) {
    twin->SetMapper(mapper);
    RandomProperty(r, twin->GetProperty());
    RandomTransform(r, twin);
    ren->AddActor(twin);
  }
  RandomLights(r, ren);
  ren->SetBackground(r.value(), r.value(), r.value());
  ren->SetBackground2(r.value(), r.value(), r.value());
  ren->SetGradientBackground(r.bit());

  // Convert (twice, with a change in between, as successive frames do), commit, render 8x8
  vtkWhittedSceneConverter converter;
  vtkNew<vtkObject> owner;
  vtkWhittedSceneConverter::Result result;
  converter.Update(ren, nullptr, 0, owner, result);
  RandomChange(r, poly, actor);
  converter.Update(ren, nullptr, 0, owner, result);
  whitted::Scene& scene = converter.GetScene();
  scene.commit();
  vtkNew<vtkCamera> cam;
  const bool validCamera = RandomCamera(r, scene.bounds(), cam);
  RenderAndCheck(r, scene, cam, validCamera, result);
  whitted_fuzz::endOfInput();
  return 0;
}
