#include "vtkWhittedGeometryFingerprint.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkMapper.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkScalarsToColors.h"
#include "vtkStringArray.h"

#include <algorithm>
#include <cstring>
#include <vector>

namespace
{
//------------------------------------------------------------------------------
// A 64-bit fingerprint of byte ranges and values: four independent multiply-rotate lanes over
// 8-byte words, so hashing runs at memory speed (a 1M-triangle surface's arrays in a few ms).
class Fingerprint
{
public:
  void Add(const void* data, std::size_t bytes)
  {
    const unsigned char* p = static_cast<const unsigned char*>(data);
    std::size_t i = 0;
    for (; i + 32 <= bytes; i += 32)
    {
      for (int l = 0; l < 4; ++l)
      {
        uint64_t w;
        std::memcpy(&w, p + i + 8 * l, 8);
        this->Lanes[l] = Round(this->Lanes[l], w);
      }
    }
    for (; i < bytes; i += 8)
    {
      uint64_t w = 0;
      std::memcpy(&w, p + i, std::min<std::size_t>(8, bytes - i));
      this->Lanes[0] = Round(this->Lanes[0], w);
    }
    this->Length += bytes;
  }
  template <typename T>
  void AddValue(T v)
  {
    this->Add(&v, sizeof v);
  }
  void AddString(const char* s) { this->Add(s ? s : "", s ? std::strlen(s) + 1 : 1); }
  uint64_t Value() const
  {
    uint64_t h = Mix(this->Length);
    for (uint64_t lane : this->Lanes)
    {
      h = Mix(h ^ lane);
    }
    return h;
  }

private:
  static uint64_t Round(uint64_t lane, uint64_t w)
  {
    lane ^= w * 0x9E3779B97F4A7C15ull;
    lane = (lane << 31) | (lane >> 33);
    return lane * 0xC2B2AE3D27D4EB4Full;
  }
  static uint64_t Mix(uint64_t x) // splitmix64's finaliser
  {
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
  }
  uint64_t Lanes[4] = { 1, 2, 3, 4 };
  uint64_t Length = 0;
};

// Type, shape, name and every value of an array.
void AddArray(Fingerprint& f, vtkAbstractArray* a)
{
  if (!a)
  {
    f.AddValue(uint64_t(0));
    return;
  }
  f.AddValue(a->GetDataType());
  f.AddValue(a->GetNumberOfComponents());
  f.AddValue(a->GetNumberOfValues());
  f.AddString(a->GetName());
  auto* data = vtkDataArray::SafeDownCast(a);
  if (data && data->HasStandardMemoryLayout())
  {
    const std::size_t n = static_cast<std::size_t>(data->GetNumberOfValues());
    const std::size_t bytes =
      data->GetDataType() == VTK_BIT ? (n + 7) / 8 : n * data->GetDataTypeSize();
    f.Add(data->GetVoidPointer(0), bytes);
  }
  else if (data)
  {
    std::vector<double> tuple(static_cast<std::size_t>(data->GetNumberOfComponents()));
    for (vtkIdType i = 0; i < data->GetNumberOfTuples(); ++i)
    {
      data->GetTuple(i, tuple.data());
      f.Add(tuple.data(), tuple.size() * sizeof(double));
    }
  }
  else if (auto* strings = vtkStringArray::SafeDownCast(a))
  {
    for (vtkIdType i = 0; i < strings->GetNumberOfValues(); ++i)
    {
      f.AddString(strings->GetValue(i).c_str());
    }
  }
  else
  {
    f.AddValue(a->GetMTime()); // other arrays: any modification counts as a change
  }
}
} // namespace

//------------------------------------------------------------------------------
uint64_t vtkWhittedGeometryFingerprint::Content(vtkPolyData* poly)
{
  Fingerprint f;
  AddArray(f, poly->GetPoints() ? poly->GetPoints()->GetData() : nullptr);
  for (vtkCellArray* cells :
    { poly->GetVerts(), poly->GetLines(), poly->GetPolys(), poly->GetStrips() })
  {
    AddArray(f, cells ? cells->GetOffsetsArray() : nullptr);
    AddArray(f, cells ? cells->GetConnectivityArray() : nullptr);
  }
  for (vtkFieldData* fd : { static_cast<vtkFieldData*>(poly->GetPointData()),
         static_cast<vtkFieldData*>(poly->GetCellData()), poly->GetFieldData() })
  {
    const int n = fd ? fd->GetNumberOfArrays() : 0;
    f.AddValue(n);
    for (int i = 0; i < n; ++i)
    {
      AddArray(f, fd->GetAbstractArray(i));
    }
    if (auto* dsa = vtkDataSetAttributes::SafeDownCast(fd))
    {
      int indices[vtkDataSetAttributes::NUM_ATTRIBUTES];
      dsa->GetAttributeIndices(indices);
      f.Add(indices, sizeof indices);
    }
  }
  return f.Value();
}

//------------------------------------------------------------------------------
uint64_t vtkWhittedGeometryFingerprint::State(vtkMapper* mapper,
  const vtkWhittedPolyDataConverter::Options& options, const std::function<double()>& radiusScale)
{
  Fingerprint f;
  f.AddString(mapper->GetClassName());
  f.AddValue(mapper->GetScalarVisibility());
  f.AddValue(mapper->GetScalarMode());
  f.AddValue(mapper->GetColorMode());
  f.AddValue(mapper->GetArrayAccessMode());
  f.AddValue(mapper->GetArrayId());
  f.AddString(mapper->GetArrayName());
  f.AddValue(mapper->GetArrayComponent());
  f.AddValue(mapper->GetInterpolateScalarsBeforeMapping());
  f.AddValue(mapper->GetUseLookupTableScalarRange());
  f.AddValue(mapper->GetFieldDataTupleId());
  f.Add(mapper->GetScalarRange(), 2 * sizeof(double));
  if (mapper->GetScalarVisibility())
  {
    vtkScalarsToColors* lut = mapper->GetLookupTable();
    f.AddValue(reinterpret_cast<std::uintptr_t>(lut));
    f.AddValue(lut ? lut->GetMTime() : 0);
  }
  if (options.Spheres || options.Tubes)
  {
    f.AddValue(radiusScale());
  }
  return f.Value();
}
