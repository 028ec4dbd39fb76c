// Cameras: perspective and parallel, built from VTK-style parameters or directly from an inverse view-projection
// matrix (VTK's composite projection, incl. tiled and IceT viewports). Pixel coordinates have their origin at the
// bottom-left corner (OpenGL / VTK order); pixel (i, j) covers [i, i+1) x [j, j+1).
#pragma once

#include "util/math.h"

namespace whitted {

class Camera {
 public:
  Camera() = default;

  /// Builds from a world -> clip matrix M (OpenGL convention, column vectors: clip = M * (x, y, z, 1)).
  /// Rays start on the near plane (z_ndc = -1), like OpenGL's clipping.
  static Camera fromViewProjection(const Mat4& worldToClip);

  /// Perspective camera as vtkCamera: eye, focal point, view-up, vertical view angle in degrees, aspect
  /// (width/height), near and far clipping distances (> 0).
  static Camera perspective(const Vec3& eye, const Vec3& focal, const Vec3& up, double viewAngleDeg, double aspect,
                            double nearDist, double farDist);

  /// Parallel camera as vtkCamera with ParallelProjection on: parallelScale is half the view height.
  static Camera parallel(const Vec3& eye, const Vec3& focal, const Vec3& up, double parallelScale, double aspect,
                         double nearDist, double farDist);

  /// Ray through normalised device coordinates (x, y in [-1, 1]). Unit direction; tMin = 0 at the near plane,
  /// tMax at the far plane.
  Ray rayNdc(double x, double y) const;

  /// The frustum of every ray rayPixel / rayPixelRow gives for points of the pixel rectangle [x0, x1] x [y0, y1]
  /// (pixel units, image width x height): its four side planes through the corner rays (see Frustum).
  Frustum pixelBlockFrustum(double x0, double y0, double x1, double y1, int width, int height) const;
  /// Ray through a point of a width x height image, in continuous pixel coordinates.
  Ray rayPixel(double px, double py, int width, int height) const {
    return rayNdc(2.0 * px / width - 1.0, 2.0 * py / height - 1.0);
  }
  /// The part of rayNdc that depends on y alone, shared by a row of rays: rayNdcRow(x, rowTerm(y)) is
  /// rayNdc(x, y) bit for bit (the very same operations).
  Vec4 rowTerm(double y) const { return clipToWorld_[1] * y; }
  Ray rayNdcRow(double x, const Vec4& row) const;
  /// rayPixel by rows: pixelRowTerm(py, height) once per row, then rayPixelRow(px, width, row) per point.
  Vec4 pixelRowTerm(double py, int height) const { return rowTerm(2.0 * py / height - 1.0); }
  Ray rayPixelRow(double px, int width, const Vec4& row) const { return rayNdcRow(2.0 * px / width - 1.0, row); }

  /// OpenGL window depth (0.5 * z_ndc + 0.5) of a world point; outside [0,1] when clipped.
  double glDepth(const Vec3& world) const;

  const Mat4& worldToClip() const { return worldToClip_; }
  /// World-space unit vector pointing "up" on screen (for gradient environments).
  Vec3 up() const { return up_; }
  /// World-space unit view direction (through the screen centre).
  Vec3 viewDirection() const { return viewDir_; }

 private:
  Mat4 worldToClip_{1.0};
  Mat4 clipToWorld_{1.0};
  /// Performance note: the z and w columns of clipToWorld_ applied to the near (z = -1) and far (z = 1) planes,
  /// summed once per camera. glm forms M * (x, y, z, 1) as (c0 x + c1 y) + (c2 z + c3), so adding these to
  /// c0 x + c1 y gives the very same bits with a quarter of the multiplications.
  Vec4 nearZW_{0.0, 0.0, -1.0, 1.0}, farZW_{0.0, 0.0, 1.0, 1.0};
  Vec3 up_{0.0, 1.0, 0.0};
  Vec3 viewDir_{0.0, 0.0, -1.0};
};

}  // namespace whitted
