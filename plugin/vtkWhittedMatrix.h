/**
 * @file    vtkWhittedMatrix.h
 * @brief   internal: the one conversion of a vtkMatrix4x4 to the tracer's whitted::Mat4
 *
 * Private to the Whitted module. Used for actor matrices (vtkWhittedSceneConverter), the camera's
 * projection (vtkWhittedPass) and the textured background's projection (vtkWhittedEnvironment).
 */

#ifndef vtkWhittedMatrix_h
#define vtkWhittedMatrix_h

#include "vtkMatrix4x4.h"

#include "util/math.h" // for whitted::Mat4

/**
 * vtkMatrix4x4 is row-major with column vectors (p' = M p); glm is column-major: element (row,
 * column) goes to m[column][row]. A null matrix gives the identity.
 */
inline whitted::Mat4 vtkWhittedToMat4(const vtkMatrix4x4* m)
{
  whitted::Mat4 r(1.0);
  if (m)
  {
    for (int row = 0; row < 4; ++row)
    {
      for (int col = 0; col < 4; ++col)
      {
        r[col][row] = m->GetElement(row, col);
      }
    }
  }
  return r;
}

#endif
// VTK-HeaderTest-Exclude: vtkWhittedMatrix.h
