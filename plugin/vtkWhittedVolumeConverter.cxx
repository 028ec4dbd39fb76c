// VTK-HeaderTest-Exclude: vtkWhittedVolumeConverter.h
#include "vtkWhittedVolumeConverter.h"
#include "vtkWhittedVolumeResampled.h"

#include "vtkWhittedMatrix.h"
#include "vtkWhittedWarnings.h"

#include "vtkColorTransferFunction.h"
#include "vtkDataArray.h"
#include "vtkFixedPointVolumeRayCastMapper.h"
#include "vtkDataObjectTree.h"
#include "vtkDataObjectTreeIterator.h"
#include "vtkGPUVolumeRayCastMapper.h"
#include "vtkImageData.h"
#include "vtkMatrix3x3.h"
#include "vtkMatrix4x4.h"
#include "vtkMultiBlockVolumeMapper.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkUnstructuredGridVolumeMapper.h"
#include "vtkPlaneCollection.h"
#include "vtkSmartVolumeMapper.h"
#include "vtkVolume.h"
#include "vtkSmartPointer.h"
#include "vtkVolumeProperty.h"

#include "scene/scene.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <new>
#include <string>
#include <vector>

namespace
{
using whitted::Mat3;
using whitted::Mat4;
using whitted::Vec3;

vtkMTimeType MTimeOf(vtkObject* o)
{
  return o ? o->GetMTime() : 0;
}

// Whether gradient opacity changes anything: set, enabled, and not 1 everywhere (VTK creates a
// default function of 1 everywhere when anything asks for it)
bool GradientOpacityActive(vtkVolumeProperty* p)
{
  if (!p->HasGradientOpacity(0) || p->GetDisableGradientOpacity(0))
  {
    return false;
  }
  vtkPiecewiseFunction* f = p->GetStoredGradientOpacity(0);
  if (!f)
  {
    return false;
  }
  for (int i = 0; i < f->GetSize(); ++i)
  {
    double node[4];
    f->GetNodeValue(i, node);
    if (node[1] != 1.0)
    {
      return true;
    }
  }
  return false;
}

// Why the tracer cannot trace a volume with this property (empty: it can)
std::string UnsupportedProperty(vtkVolumeProperty* p)
{
  if (p->GetTransferFunctionMode() != vtkVolumeProperty::TF_1D)
  {
    return "2D transfer function";
  }
  return std::string();
}

// Why the tracer leaves this volume to OpenGL (empty: it traces it). Sets image and array (an unstructured-grid
// mapper's input resampled into resampled).
std::string Unsupported(
  vtkVolume* volume, vtkWhittedVolumeResampled& resampled, vtkImageData*& image, vtkDataArray*& array)
{
  image = nullptr;
  array = nullptr;
  if (auto* unstructured = vtkUnstructuredGridVolumeMapper::SafeDownCast(volume->GetMapper()))
  {
    if (unstructured->GetBlendMode() != vtkUnstructuredGridVolumeMapper::COMPOSITE_BLEND)
    {
      return "blend mode " + std::to_string(unstructured->GetBlendMode()) + " (only composite is traced)";
    }
    if (unstructured->GetClippingPlanes() && unstructured->GetClippingPlanes()->GetNumberOfItems() > 0)
    {
      return "clipping planes";
    }
    std::string why = UnsupportedProperty(volume->GetProperty());
    if (why.empty())
    {
      why = resampled.Update(unstructured);
    }
    if (!why.empty())
    {
      return why;
    }
    image = resampled.Image;
    array = image->GetPointData()->GetScalars();
    return std::string();
  }
  resampled = vtkWhittedVolumeResampled();
  auto* mapper = vtkVolumeMapper::SafeDownCast(volume->GetMapper());
  auto* multiBlock = vtkMultiBlockVolumeMapper::SafeDownCast(mapper);
  if (!mapper ||
    !(vtkSmartVolumeMapper::SafeDownCast(mapper) || vtkGPUVolumeRayCastMapper::SafeDownCast(mapper) ||
      vtkFixedPointVolumeRayCastMapper::SafeDownCast(mapper) || multiBlock))
  {
    return std::string("mapper ") + (volume->GetMapper() ? volume->GetMapper()->GetClassName() : "none") +
      " (traced: vtkSmartVolumeMapper, vtkGPUVolumeRayCastMapper, vtkFixedPointVolumeRayCastMapper, "
      "vtkMultiBlockVolumeMapper of one block, unstructured-grid volume mappers by resampling)";
  }
  if (mapper->GetBlendMode() != vtkVolumeMapper::COMPOSITE_BLEND)
  {
    return "blend mode " + std::to_string(mapper->GetBlendMode()) + " (only composite is traced)";
  }
  if (mapper->GetCropping())
  {
    return "cropping";
  }
  if (mapper->GetClippingPlanes() && mapper->GetClippingPlanes()->GetNumberOfItems() > 0)
  {
    return "clipping planes";
  }
  const std::string why = UnsupportedProperty(volume->GetProperty());
  if (!why.empty())
  {
    return why;
  }
  mapper->Update();
  vtkDataObject* input = mapper->GetInputDataObject(0, 0);
  image = vtkImageData::SafeDownCast(input);
  if (auto* tree = multiBlock ? vtkDataObjectTree::SafeDownCast(input) : nullptr)
  {
    // ParaView's Volume representation: one block (per rank) of image data
    int leaves = 0;
    vtkSmartPointer<vtkDataObjectTreeIterator> it;
    it.TakeReference(tree->NewTreeIterator());
    it->SkipEmptyNodesOff();
    for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
    {
      image = leaves++ == 0 ? vtkImageData::SafeDownCast(it->GetCurrentDataObject()) : nullptr;
    }
    if (leaves > 1)
    {
      return "a composite input of " + std::to_string(leaves) + " blocks (one is traced)";
    }
  }
  if (!image)
  {
    return "input not vtkImageData";
  }
  int cellFlag = 0;
  array = vtkDataArray::SafeDownCast(vtkAbstractMapper::GetAbstractScalars(image, mapper->GetScalarMode(),
    mapper->GetArrayAccessMode(), mapper->GetArrayId(), mapper->GetArrayName(), cellFlag));
  if (array && cellFlag)
  {
    array = nullptr;
    return "cell scalars (only point scalars are traced)";
  }
  if (array && array->GetNumberOfComponents() != 1)
  {
    const int n = array->GetNumberOfComponents();
    array = nullptr;
    return std::to_string(n) + "-component scalars (only one component is traced)";
  }
  return std::string();
}

// Why this grid cannot be drawn at all (empty: it can)
std::string BadGrid(vtkImageData* image, vtkDataArray* array, const Mat4& matrix)
{
  int dims[3];
  image->GetDimensions(dims);
  if (image->GetNumberOfPoints() == 0 || !array || array->GetNumberOfTuples() == 0)
  {
    return "empty image or no point scalars";
  }
  if (array->GetNumberOfTuples() < image->GetNumberOfPoints())
  {
    return "fewer scalars than points";
  }
  static const char* const axis[3] = { "x", "y", "z" };
  const double* spacing = image->GetSpacing();
  for (int a = 0; a < 3; ++a)
  {
    if (dims[a] < 2)
    {
      return std::string("a single point along ") + axis[a] + " (no thickness to march)";
    }
    if (!(std::isfinite(spacing[a]) && spacing[a] != 0.0))
    {
      return std::string("spacing along ") + axis[a] + " is zero or not finite";
    }
  }
  const double* origin = image->GetOrigin();
  if (!(std::isfinite(origin[0]) && std::isfinite(origin[1]) && std::isfinite(origin[2])))
  {
    return "origin not finite";
  }
  const Mat3 linear(matrix);
  const double det = glm::determinant(linear);
  if (!(std::isfinite(det) && det != 0.0) || !whitted::isFinite(Vec3(matrix[3])))
  {
    return "the volume's matrix is singular or not finite";
  }
  return std::string();
}

// Sets g's dimensions and its placement in the world: the volume's matrix x (origin + D x
// diag(spacing) x index)
void Place(vtkImageData* image, const Mat4& matrix, whitted::VolumeGrid& g)
{
  image->GetDimensions(g.dims);
  const Mat3 linear(matrix);
  const double* d = image->GetDirectionMatrix()->GetData(); // row-major 3x3
  Mat3 dir;
  for (int r = 0; r < 3; ++r)
  {
    for (int c = 0; c < 3; ++c)
    {
      dir[c][r] = d[3 * r + c];
    }
  }
  // The grid's first point: index (extent minimum), not the origin (index 0)
  const int* extent = image->GetExtent();
  const double* s = image->GetSpacing();
  const Vec3 first = Vec3(image->GetOrigin()[0], image->GetOrigin()[1], image->GetOrigin()[2]) +
    dir * Vec3(s[0] * extent[0], s[1] * extent[2], s[2] * extent[4]);
  g.origin = Vec3(matrix * whitted::Vec4(first, 1.0));
  g.direction = linear * dir;
  g.spacing = Vec3(s[0], s[1], s[2]);
}

// The grid of image's scalars array, placed by matrix; the scalars are written into reuse's memory
// when it has their size (a new time step of the same grid: no allocation, no page faults)
whitted::VolumeGrid Grid(
  vtkImageData* image, vtkDataArray* array, const Mat4& matrix, whitted::VolumeScalars reuse,
  std::size_t& invalid)
{
  whitted::VolumeGrid g;
  Place(image, matrix, g);
  const std::size_t n = static_cast<std::size_t>(image->GetNumberOfPoints());
  if (reuse.size() == n)
  {
    g.scalars = std::move(reuse);
  }
  bool copied = false;
  if (array->HasStandardMemoryLayout())
  {
    switch (array->GetDataType())
    {
      vtkTemplateMacro(
        invalid = whitted::VolumeGrid::convertScalars(
          static_cast<const VTK_TT*>(array->GetVoidPointer(0)), n, g.scalars);
        copied = true);
      default:
        break;
    }
  }
  if (!copied)
  {
    g.scalars.resize(n);
    invalid = 0;
    for (std::size_t i = 0; i < n; ++i)
    {
      g.scalars[i] = static_cast<float>(array->GetComponent(static_cast<vtkIdType>(i), 0));
      invalid += std::isfinite(g.scalars[i]) ? 0 : 1;
    }
  }
  return g;
}

// The transfer functions, tabulated by VTK over the union of their range and the data's
whitted::TransferFunction Transfer(vtkVolumeProperty* p, const double range[2])
{
  constexpr int kNodes = whitted::Volume::kTableSize;
  whitted::TransferFunction tf;
  tf.unitDistance = p->GetScalarOpacityUnitDistance(0);
  auto tabulate = [&](double lo, double hi, std::vector<float>& xs)
  {
    lo = std::min(lo, range[0]);
    hi = std::max(hi, range[1]);
    if (!(hi > lo))
    {
      hi = lo + 1.0;
    }
    xs.resize(kNodes);
    for (int i = 0; i < kNodes; ++i)
    {
      xs[static_cast<std::size_t>(i)] = static_cast<float>(lo + (hi - lo) * i / (kNodes - 1));
    }
    return std::make_pair(lo, hi);
  };
  // (VTK creates a default function for whichever is asked for: ask only for the one in use)
  if (p->GetColorChannels(0) == 1)
  {
    vtkPiecewiseFunction* gray = p->GetGrayTransferFunction(0);
    if (gray->GetSize() > 0)
    {
      const double* r = gray->GetRange();
      const auto span = tabulate(r[0], r[1], tf.colorX);
      std::vector<float> v(kNodes);
      gray->GetTable(span.first, span.second, kNodes, v.data());
      tf.colorY.resize(kNodes);
      for (std::size_t i = 0; i < std::size_t(kNodes); ++i)
      {
        tf.colorY[i] = whitted::Color(v[i]);
      }
    }
  }
  else if (vtkColorTransferFunction* ctf = p->GetRGBTransferFunction(0))
  {
    if (ctf->GetSize() > 0)
    {
      const double* r = ctf->GetRange();
      const auto span = tabulate(r[0], r[1], tf.colorX);
      std::vector<float> rgb(3 * kNodes);
      ctf->GetTable(span.first, span.second, kNodes, rgb.data());
      tf.colorY.resize(kNodes);
      for (std::size_t i = 0; i < std::size_t(kNodes); ++i)
      {
        tf.colorY[i] = whitted::Color(rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]);
      }
    }
  }
  vtkPiecewiseFunction* otf = p->GetScalarOpacity(0);
  if (otf && otf->GetSize() > 0)
  {
    const double* r = otf->GetRange();
    const auto span = tabulate(r[0], r[1], tf.opacityX);
    tf.opacityY.resize(kNodes);
    otf->GetTable(span.first, span.second, kNodes, tf.opacityY.data());
  }
  // Shading with VTK's coefficients; gradient opacity as VTK's GPU mapper tabulates it (its default
  // range: gradient magnitudes 0 .. a quarter of the scalar range)
  tf.shade = p->GetShade(0) != 0;
  tf.ambient = static_cast<float>(p->GetAmbient(0));
  tf.diffuse = static_cast<float>(p->GetDiffuse(0));
  tf.specular = static_cast<float>(p->GetSpecular(0));
  tf.specularPower = static_cast<float>(p->GetSpecularPower(0));
  if (GradientOpacityActive(p))
  {
    const double span = range[1] > range[0] ? range[1] - range[0] : 1.0;
    tf.gradientOpacityMax = 0.25 * span;
    tf.gradientOpacity.resize(kNodes);
    p->GetStoredGradientOpacity(0)->GetTable(0.0, tf.gradientOpacityMax, kNodes, tf.gradientOpacity.data());
  }
  return tf;
}
} // namespace

//------------------------------------------------------------------------------
double vtkWhittedVolumeConverter::SampleStep(vtkVolume* volume, vtkImageData* image)
{
  // The smallest voxel spacing in world units, as vtkOpenGLGPUVolumeRayCastMapper computes it
  // with AutoAdjustSampleDistances
  vtkMatrix4x4* m = volume->GetMatrix();
  const double* spacing = image->GetSpacing();
  double voxel = VTK_DOUBLE_MAX;
  for (int i = 0; i < 3; ++i)
  {
    const double a = m->GetElement(0, i), b = m->GetElement(1, i), c = m->GetElement(2, i);
    voxel = std::min(voxel, std::abs(spacing[i] * std::sqrt(a * a + b * b + c * c)));
  }
  vtkAbstractVolumeMapper* mapper = volume->GetMapper();
  if (auto* smart = vtkSmartVolumeMapper::SafeDownCast(mapper))
  {
    const bool adjust = smart->GetInteractiveAdjustSampleDistances()
      ? false // a still frame: the smart mapper turns the GPU mapper's adjustment off
      : smart->GetAutoAdjustSampleDistances() != 0;
    return adjust || smart->GetSampleDistance() <= 0.0f ? voxel : smart->GetSampleDistance();
  }
  if (auto* gpu = vtkGPUVolumeRayCastMapper::SafeDownCast(mapper))
  {
    return gpu->GetAutoAdjustSampleDistances() || gpu->GetLockSampleDistanceToInputSpacing()
      ? voxel
      : gpu->GetSampleDistance();
  }
  if (auto* fixed = vtkFixedPointVolumeRayCastMapper::SafeDownCast(mapper))
  {
    return fixed->GetSampleDistance();
  }
  // vtkMultiBlockVolumeMapper: vtkSmartVolumeMappers with their defaults (SampleDistance -1)
  return voxel;
}

//------------------------------------------------------------------------------
void vtkWhittedVolumeConverter::BeginFrame()
{
  for (auto& e : this->Entries)
  {
    e.second.Used = false;
  }
}

void vtkWhittedVolumeConverter::Remove(Entry& e)
{
  if (e.InScene)
  {
    this->Scene.removeVolume(e.Id);
  }
  e = Entry();
}

void vtkWhittedVolumeConverter::FreeUnused()
{
  for (auto it = this->Entries.begin(); it != this->Entries.end();)
  {
    if (!it->second.Used)
    {
      this->Remove(it->second);
      it = this->Entries.erase(it);
    }
    else
    {
      ++it;
    }
  }
}

//------------------------------------------------------------------------------
vtkWhittedVolumeConverter::Verdict vtkWhittedVolumeConverter::Convert(
  vtkVolume* volume, vtkWhittedWarnings& warnings, int& converted, int& transferUpdates)
{
  Entry& e = this->Entries[volume];
  e.Used = true;
  if (!volume->GetProperty())
  {
    this->Remove(e);
    return Traced; // nothing to draw
  }
  // Not traced: warned, out of the scene, still counted as seen this frame
  auto notTraced = [&](vtkWhittedWarnings::Warning message, const std::string& why, Verdict verdict) {
    warnings.WarnVolume(volume, message, why);
    this->Remove(e);
    e.Used = true;
    return verdict;
  };
  vtkImageData* image = nullptr;
  vtkDataArray* array = nullptr;
  const std::string unsupported = Unsupported(volume, e.Resampled, image, array);
  if (!unsupported.empty())
  {
    return notTraced(vtkWhittedWarnings::VolumeOpenGL, unsupported, OpenGL);
  }
  const Mat4 matrix = vtkWhittedToMat4(volume->GetMatrix());
  const std::string bad = BadGrid(image, array, matrix);
  if (!bad.empty())
  {
    return notTraced(vtkWhittedWarnings::VolumeSkipped, bad, Skipped);
  }

  // Geometry of the scene volume: matrix, step, interpolation
  vtkVolumeProperty* p = volume->GetProperty();
  double geometry[18];
  for (int i = 0; i < 16; ++i)
  {
    geometry[i] = volume->GetMatrix()->GetData()[i];
  }
  geometry[16] = SampleStep(volume, image);
  geometry[17] = p->GetInterpolationType() == VTK_NEAREST_INTERPOLATION ? 0.0 : 1.0;
  const vtkMTimeType dataTime = std::max(image->GetMTime(), array->GetMTime());
  const bool newData = !e.InScene || e.Image != image || e.Array != array || e.DataTime != dataTime;
  const bool newGeometry = !std::equal(geometry, geometry + 18, e.Geometry);
  if (newData)
  {
    array->GetFiniteRange(e.Range, 0); // (as VTK's volume texture: infinite values left out)
  }
  // The transfer functions' own times, not the property's (VTK's mappers touch the property when
  // they draw it)
  const bool gray = p->GetColorChannels(0) == 1;
  const bool gradientOpacity = GradientOpacityActive(p);
  const std::array<double, 11> transferKey = { double(gray ? MTimeOf(p->GetGrayTransferFunction(0))
                                                          : MTimeOf(p->GetRGBTransferFunction(0))),
    double(gray), double(MTimeOf(p->GetScalarOpacity(0))), p->GetScalarOpacityUnitDistance(0),
    double(p->GetShade(0)), p->GetAmbient(0), p->GetDiffuse(0), p->GetSpecular(0), p->GetSpecularPower(0),
    double(gradientOpacity), gradientOpacity ? double(MTimeOf(p->GetStoredGradientOpacity(0))) : 0.0 };
  const bool newTransfer = newData || e.TransferKey != transferKey;

  if (newData || newGeometry)
  {
    whitted::Volume v;
    // The traced grid's scalars when they have this grid's size: kept when only the placement
    // changed, else written over by the new ones (the next time step; allocating and zeroing a
    // fresh 64 MB grid took 23-450 ms here, page faults and all, against 30 ms for the copy)
    const std::size_t points = static_cast<std::size_t>(image->GetNumberOfPoints());
    whitted::VolumeScalars traced;
    if (e.InScene && this->Scene.volume(e.Id).grid.scalars.size() == points)
    {
      traced = this->Scene.releaseVolumeScalars(e.Id);
    }
    if (newData || traced.size() != points)
    {
      std::size_t invalid = 0;
      try
      {
        v.grid = Grid(image, array, matrix, std::move(traced), invalid);
        ++converted; // (a conversion that failed is not counted)
      }
      catch (const std::bad_alloc&)
      {
        // The rest of the scene is traced; OpenGL draws this volume from VTK's own copy
        const double mib = double(points) * sizeof(float) / (1024.0 * 1024.0);
        return notTraced(vtkWhittedWarnings::VolumeOpenGL,
          "not enough memory for the traced copy of its scalars (" + std::to_string(int64_t(mib + 0.5)) +
            " MiB as float)",
          OpenGL);
      }
      if (e.Resampled.Image)
      {
        // The points outside the unstructured grid's cells are NaN on purpose
        invalid -= std::min(invalid, e.Resampled.Outside);
        const int n = vtkWhittedVolumeResampled::kSamples;
        warnings.WarnVolume(volume, vtkWhittedWarnings::VolumeResampled,
          std::to_string(n) + "^3 (" + std::to_string(e.Resampled.Outside) + " points outside its cells: "
            "transparent)");
      }
      if (invalid)
      {
        warnings.WarnVolume(volume, vtkWhittedWarnings::VolumeInvalidScalars,
          std::to_string(invalid) + " of " + std::to_string(v.grid.scalars.size()));
      }
    }
    else
    {
      v.grid.scalars = std::move(traced); // only the placement changed
      Place(image, matrix, v.grid);
    }
    v.transfer = Transfer(p, e.Range);
    v.interpolation =
      geometry[17] == 0.0 ? whitted::VolumeInterpolation::Nearest : whitted::VolumeInterpolation::Linear;
    v.sampleDistance = geometry[16];
    // VTK's GPU mapper marches with unit steps of the dataset's space (before the volume matrix)
    // times the sample distance, and corrects opacity by sample / unit distance there
    v.lengthMetric = glm::inverse(Mat3(matrix));
    if (e.InScene)
    {
      this->Scene.setVolume(e.Id, std::move(v));
    }
    else
    {
      e.Id = this->Scene.addVolume(std::move(v));
      e.InScene = true;
    }
  }
  else if (newTransfer)
  {
    ++transferUpdates;
    this->Scene.setVolumeTransfer(e.Id, Transfer(p, e.Range));
  }
  e.Image = image;
  e.Array = array;
  e.DataTime = dataTime;
  e.TransferKey = transferKey;
  std::copy(geometry, geometry + 18, e.Geometry);

  // What the core found at the last commit (a grid it could not trace)
  const std::string& error = this->Scene.volumeError(e.Id);
  if (!error.empty() && !newData && !newGeometry)
  {
    warnings.WarnVolume(volume, vtkWhittedWarnings::VolumeSkipped, error);
  }
  return Traced;
}
