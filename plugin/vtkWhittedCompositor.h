/**
 * @class   vtkWhittedCompositor
 * @brief   internal: writes a traced colour + depth image into the current OpenGL framebuffer
 *
 * Private to the Whitted module. Uploads the tracer's linear RGBA (float) and OpenGL window depth
 * (float) as textures (kept between frames of the same size: later frames update them in place) and draws a full-screen quad over the renderer's viewport that writes both
 * gl_FragData and gl_FragDepth. Pixels the tracer missed (alpha 0) are discarded, so whatever VTK
 * cleared there (background, gradient, lower layers, a transparent background for compositing)
 * stays; partly covered pixels are blended as premultiplied colour. The depth test is LEQUAL
 * against the cleared (or preserved) depth buffer, so OpenGL geometry drawn before or after
 * depth-composes with the traced geometry. When VTK resolves coincident topology by polygon offset
 * (vtkMapper::SetResolveCoincidentTopologyToPolygonOffset; ParaView does), the traced depth is pushed
 * back as glPolygonOffset pushes VTK's own polygons (factor x depth slope + units), so lines and
 * points drawn over a traced surface stay in front of it.
 */

#ifndef vtkWhittedCompositor_h
#define vtkWhittedCompositor_h

#include "vtkNew.h" // for vtkNew

class vtkOpenGLQuadHelper;
class vtkOpenGLRenderWindow;
class vtkTextureObject;
class vtkWindow;

namespace whitted
{
struct FrameBuffer;
}

class vtkWhittedCompositor
{
public:
  vtkWhittedCompositor();
  ~vtkWhittedCompositor();
  vtkWhittedCompositor(const vtkWhittedCompositor&) = delete;
  vtkWhittedCompositor& operator=(const vtkWhittedCompositor&) = delete;

  /**
   * Draws fb (premultiplied) into the viewport (x, y, width, height) of the current framebuffer,
   * stretched (nearest neighbour) if fb is smaller. Returns false if the shader could not be built.
   */
  bool Draw(vtkOpenGLRenderWindow* win, const whitted::FrameBuffer& fb, int x, int y, int width,
    int height);

  void ReleaseGraphicsResources(vtkWindow* w);

private:
  // The quad's program without and with the coincident-topology depth offset (each compiled when
  // first needed: llvmpipe's first draw of the offset variant takes longer, and so does every draw)
  vtkOpenGLQuadHelper* Quad = nullptr;
  vtkOpenGLQuadHelper* OffsetQuad = nullptr;
  vtkNew<vtkTextureObject> ColorTexture;
  vtkNew<vtkTextureObject> DepthTexture;
};

#endif
// VTK-HeaderTest-Exclude: vtkWhittedCompositor.h
