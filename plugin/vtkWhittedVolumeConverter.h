/**
 * @class   vtkWhittedVolumeConverter
 * @brief   internal: vtkVolume -> whitted::Volume (core/geometry/volume.h), cached across frames
 *
 * Private to the Whitted module. A vtkVolume is traced when its mapper is a vtkSmartVolumeMapper,
 * vtkGPUVolumeRayCastMapper or vtkFixedPointVolumeRayCastMapper with vtkImageData input (or an
 * unstructured-grid volume mapper, whose input is resampled to image data: vtkWhittedVolumeResampled), one
 * component of point scalars, blend mode composite (Shade and gradient opacity are traced), no cropping
 * and no clipping planes; otherwise it is left to VTK's OpenGL volume pass with a warning that
 * names the setting (Verdict OpenGL). Bad input (empty image, a single point along an axis, zero or
 * non-finite spacing, a singular matrix) is not drawn at all, with a warning (Verdict Skipped);
 * NaN scalars are traced as transparent, with a warning.
 *
 * The grid goes to world coordinates: origin, spacing and direction matrix of the image, then the
 * vtkVolume's matrix. The scalars are converted to float once per content (the image's and the
 * array's MTime): a transfer-function edit only replaces the scene volume's transfer function
 * (Scene::setVolumeTransfer), a new matrix, step or interpolation copies the converted grid.
 * The transfer functions are tabulated with VTK's own GetTable over the union of their range and
 * the data's scalar range, so colour spaces and midpoint/sharpness are as VTK evaluates them.
 * The step is the sample distance the mapper would use (SampleStep).
 */

#ifndef vtkWhittedVolumeConverter_h
#define vtkWhittedVolumeConverter_h

#include "vtkType.h"                   // for vtkMTimeType
#include "vtkWhittedVolumeResampled.h" // for vtkWhittedVolumeResampled

#include <array>   // for std::array
#include <cstdint> // for uint32_t
#include <map>     // for std::map

class vtkDataArray;
class vtkImageData;
class vtkVolume;
class vtkWhittedWarnings;

namespace whitted
{
class Scene;
struct TransferFunction;
}

class vtkWhittedVolumeConverter
{
public:
  explicit vtkWhittedVolumeConverter(whitted::Scene& scene)
    : Scene(scene)
  {
  }

  enum Verdict
  {
    Traced,  ///< In the scene (or nothing to draw).
    OpenGL,  ///< Left to VTK's OpenGL volume pass (warned).
    Skipped  ///< Bad input: drawn by nobody (warned).
  };

  void BeginFrame();
  /// Converts (or updates) one visible vtkVolume; warnings through warnings. Counts grids
  /// converted and transfer-only updates.
  Verdict Convert(
    vtkVolume* volume, vtkWhittedWarnings& warnings, int& converted, int& transferUpdates);
  /// Removes the scene volumes of vtkVolumes not converted since BeginFrame.
  void FreeUnused();
  void Clear() { this->Entries.clear(); }

  /**
   * The step along rays the mapper would sample with, world units: vtkGPUVolumeRayCastMapper with
   * AutoAdjustSampleDistances (or LockSampleDistanceToInputSpacing) the smallest voxel spacing in
   * world units (spacing times the length of the volume matrix's column), else its
   * SampleDistance; vtkSmartVolumeMapper likewise (a still frame turns automatic adjustment off
   * when InteractiveAdjustSampleDistances is on; SampleDistance <= 0: the voxel spacing);
   * vtkFixedPointVolumeRayCastMapper its SampleDistance.
   */
  static double SampleStep(vtkVolume* volume, vtkImageData* image);

private:
  struct Entry
  {
    uint32_t Id = 0;
    bool InScene = false;
    bool Used = false;
    vtkImageData* Image = nullptr;
    vtkDataArray* Array = nullptr;
    vtkMTimeType DataTime = 0;     ///< Max of the image's and the array's MTime at conversion.
    /// The transfer functions' MTimes, the unit distance, the shading coefficients and gradient opacity
    /// at the last transfer update (a first conversion updates it whatever it holds).
    std::array<double, 11> TransferKey = {};
    double Range[2] = { 0.0, 0.0 };
    double Geometry[16 + 2] = {}; ///< Volume matrix, step, interpolation of the scene volume.
    vtkWhittedVolumeResampled Resampled; ///< An unstructured-grid mapper's input as image data.
  };
  void Remove(Entry& e);

  whitted::Scene& Scene;
  std::map<vtkVolume*, Entry> Entries;
};

#endif
// VTK-HeaderTest-Exclude: vtkWhittedVolumeConverter.h
