// An unstructured-grid volume mapper's input resampled to image data for the tracer (vtkWhittedVolumeResampled.h).
#include "vtkWhittedVolumeResampled.h"

#include "vtkAbstractMapper.h"
#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkDataSetAttributes.h"
#include "vtkFloatArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkResampleToImage.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGridVolumeMapper.h"

#include <algorithm>
#include <limits>

//------------------------------------------------------------------------------
std::string vtkWhittedVolumeResampled::Update(vtkUnstructuredGridVolumeMapper* mapper)
{
  mapper->Update();
  auto* input = vtkDataSet::SafeDownCast(mapper->GetInputDataObject(0, 0));
  if (!input || input->GetNumberOfCells() == 0)
  {
    return "unstructured input empty or not a data set";
  }
  int cellFlag = 0;
  auto* source = vtkDataArray::SafeDownCast(vtkAbstractMapper::GetAbstractScalars(input, mapper->GetScalarMode(),
    mapper->GetArrayAccessMode(), mapper->GetArrayId(), mapper->GetArrayName(), cellFlag));
  if (!source || !source->GetName())
  {
    return "unstructured input without named scalars";
  }
  if (cellFlag)
  {
    return "cell scalars (only point scalars are traced)";
  }
  if (source->GetNumberOfComponents() != 1)
  {
    return std::to_string(source->GetNumberOfComponents()) + "-component scalars (only one component is traced)";
  }
  // The same input, contents and selected array: the image made last time
  const vtkMTimeType time = std::max(input->GetMTime(), source->GetMTime());
  if (this->Image && this->From == input && this->Source == source && this->Time == time)
  {
    return std::string();
  }
  vtkNew<vtkResampleToImage> resample;
  resample->SetInputDataObject(input);
  resample->UseInputBoundsOn();
  const int n = kSamples;
  resample->SetSamplingDimensions(n, n, n);
  resample->Update();
  vtkImageData* out = resample->GetOutput();
  vtkDataArray* probed = out->GetPointData()->GetArray(source->GetName()); // (point data in, point data out)
  if (!probed || probed->GetNumberOfTuples() != out->GetNumberOfPoints())
  {
    return "resampling to image data lost the scalars";
  }
  // Points outside every cell are hidden by the resampler (vtkGhostType): transparent, as NaN
  vtkUnsignedCharArray* ghosts = out->GetPointGhostArray();
  vtkNew<vtkFloatArray> scalars;
  scalars->SetName("WhittedResampled");
  scalars->SetNumberOfTuples(out->GetNumberOfPoints());
  std::size_t outside = 0;
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
  {
    const bool hidden = ghosts && (ghosts->GetValue(i) & vtkDataSetAttributes::HIDDENPOINT);
    outside += hidden ? 1 : 0;
    scalars->SetValue(i, hidden ? std::numeric_limits<float>::quiet_NaN() : float(probed->GetComponent(i, 0)));
  }
  this->Image = vtkSmartPointer<vtkImageData>::New();
  this->Image->CopyStructure(out);
  this->Image->GetPointData()->SetScalars(scalars);
  this->From = input;
  this->Source = source;
  this->Time = time;
  this->Outside = outside;
  return std::string();
}
