/**
 * @struct  vtkWhittedVolumeResampled
 * @brief   internal: an unstructured grid's volume as image data for the tracer
 *
 * Private to the Whitted module (vtkWhittedVolumeConverter). The plan for unstructured grids: resample to image
 * data first (this), march the tetrahedra themselves later.
 */
#ifndef vtkWhittedVolumeResampled_h
#define vtkWhittedVolumeResampled_h

#include "vtkImageData.h"    // for vtkSmartPointer<vtkImageData>
#include "vtkSmartPointer.h" // for vtkSmartPointer
#include "vtkType.h"         // for vtkMTimeType

#include <cstddef> // for std::size_t
#include <string>  // for std::string

class vtkDataArray;
class vtkDataObject;
class vtkUnstructuredGridVolumeMapper;

/// An unstructured-grid volume mapper's input resampled to image data (vtkResampleToImage at kSamples^3 over the
/// input's bounds, like ParaView's 'Resample To Image' volume mode), the mapper's scalars as float with NaN
/// (transparent) at the points outside every cell; made again when the input, its contents or the selected array
/// change.
struct vtkWhittedVolumeResampled
{
  static constexpr int kSamples = 128; ///< Points per axis (ParaView's default SamplingDimensions).
  vtkSmartPointer<vtkImageData> Image;
  vtkDataObject* From = nullptr; ///< The input it was made from (compared, never read).
  vtkDataArray* Source = nullptr; ///< The mapper's scalars then (compared, never read): another array is resampled.
  vtkMTimeType Time = 0;         ///< Max of the input's and its scalars' MTime then.
  std::size_t Outside = 0;       ///< Points outside every cell.
  /// Resamples mapper's input unless it and its scalars are unchanged since the last time. Returns why it cannot
  /// (empty: Image holds it).
  std::string Update(vtkUnstructuredGridVolumeMapper* mapper);
};

#endif
// VTK-HeaderTest-Exclude: vtkWhittedVolumeResampled.h
