/**
 * @class   vtkWhittedGeometryFingerprint
 * @brief   internal: 64-bit fingerprints of a polydata's contents and of a mapper's colouring state
 *
 * Private to the Whitted module. The keys of the geometry cache's time cache
 * (vtkWhittedGeometryTimeCache): an input whose two fingerprints match those of kept contents
 * converts to the same geometry, so the kept objects are used instead. Hashing reads every byte
 * (four independent multiply-rotate lanes over 8-byte words, at memory speed: a 1M-triangle
 * surface's arrays in a few ms); it is not cryptographic.
 *
 * @sa vtkWhittedGeometryCache vtkWhittedGeometryTimeCache
 */

#ifndef vtkWhittedGeometryFingerprint_h
#define vtkWhittedGeometryFingerprint_h

#include "vtkWhittedPolyDataConverter.h" // for Options

#include <cstdint>    // for uint64_t
#include <functional> // for std::function

class vtkMapper;
class vtkPolyData;

class vtkWhittedGeometryFingerprint
{
public:
  /// The contents of a polydata: points, cells, and every point, cell and field array (type,
  /// components, values, name) with the attribute designations (which array is the scalars,
  /// normals, ...). Arrays of other types than data and string arrays count by their MTime.
  static uint64_t Content(vtkPolyData* poly);

  /// The mapper state a conversion reads (class, scalar visibility, mode, array, colour mode,
  /// scalar range, lookup table and its MTime), and radiusScale() (called only then) when the
  /// options ask for spheres or tubes.
  static uint64_t State(vtkMapper* mapper, const vtkWhittedPolyDataConverter::Options& options,
    const std::function<double()>& radiusScale);
};

#endif
// VTK-HeaderTest-Exclude: vtkWhittedGeometryFingerprint.h
