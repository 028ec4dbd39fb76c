/**
 * @class   vtkWhittedGlyphPlacement
 * @brief   internal: the glyphs of a vtkGlyph3DMapper as VTK places them (source, matrix, colour)
 *
 * Private to the Whitted module. Stateless; vtkWhittedGlyphConverter makes each glyph an instance
 * of its source's converted objects (so a million glyphs cost instance records, not copies of the
 * geometry) and decides when to call it (the mapper, its lookup table or the points changed). The
 * rules are those of VTK 9.1's vtkOpenGLGlyph3DMapper::RebuildStructures, so the traced glyphs
 * stand where OpenGL draws them:
 *
 * - Masking (a one-component vtkBitArray: glyphs with mask 0 are left out) and SourceIndexing
 *   (the norm of the index array's tuple, truncated and clamped to the sources).
 * - Orientation (Orient with the orientation array): DIRECTION (the source's x axis turned onto the
 *   vector), ROTATION (angles in degrees about x, y, z, applied as vtkProp3D does) or QUATERNION
 *   (w, x, y, z). An array with the wrong number of components draws nothing, as in VTK.
 * - Scaling (only when Scaling is on): ScaleFactor times the scale array's magnitude
 *   (SCALE_BY_MAGNITUDE) or its three components (SCALE_BY_COMPONENTS), clamped to Range and
 *   mapped to [0, 1] when Clamping is on; a zero scale becomes 1e-10, as in VTK.
 * - Colours: the mapper's scalars mapped through its lookup table per point (its scalar
 *   visibility, mode, array and range) with alpha = the table's alpha; VTK's OpenGL glyph mapper
 *   multiplies the actor opacity in a second time, the tracer does not (see plugin/README.md).
 *
 * @sa vtkWhittedGlyphConverter vtkGlyph3DMapper
 */

#ifndef vtkWhittedGlyphPlacement_h
#define vtkWhittedGlyphPlacement_h

#include "vtkType.h" // for vtkIdType

#include "util/math.h" // for whitted::Mat4

#include <functional> // for std::function

class vtkDataSet;
class vtkGlyph3DMapper;
class vtkMapper;
class vtkUnsignedCharArray;

class vtkWhittedGlyphPlacement
{
public:
  /// What made the glyphs of a dataset undrawable (then none is placed).
  enum Problem
  {
    None = 0,
    OrientationComponents, ///< Orientation array without 3 (DIRECTION, ROTATION) or 4 components.
    MaskComponents,        ///< Mask array with more than one component.
    ScaleComponents,       ///< SCALE_BY_COMPONENTS with a scale array of other than 3 components.
    ShortArray             ///< An orientation, mask, source index or scale array with fewer tuples than points.
  };

  /**
   * Calls place(source, pointId, matrix) for every glyph mapper draws on points, in point order:
   * source is the index of the glyph's source in [0, numberOfSources), matrix its glyph -> data
   * coordinates transform (before the actor's matrix). Returns the problem that stopped it, if any
   * (ScaleComponents does not stop: those glyphs are unscaled, as in VTK).
   */
  static Problem ForEachGlyph(vtkGlyph3DMapper* mapper, vtkDataSet* points, int numberOfSources,
    const std::function<void(int, vtkIdType, const whitted::Mat4&)>& place);

  /**
   * The per-point glyph colours mapper maps from points (RGBA, one tuple per point), or null when
   * it colours by no scalars. colorMapper is a helper of the caller's that takes mapper's colour
   * settings (so mapping leaves mapper itself untouched).
   */
  static vtkUnsignedCharArray* MapColors(
    vtkGlyph3DMapper* mapper, vtkMapper* colorMapper, vtkDataSet* points);
};

#endif
// VTK-HeaderTest-Exclude: vtkWhittedGlyphPlacement.h
