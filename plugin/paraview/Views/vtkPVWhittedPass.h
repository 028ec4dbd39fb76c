/**
 * @class   vtkPVWhittedPass
 * @brief   vtkWhittedPass that sees the view's background while ParaView composites on black
 *
 * ParaView renders on a black, transparent background wherever images are composited (every server
 * rank, IceT; see vtkSynchronizedRenderers::FixBackground) and blends the result over the view's
 * background afterwards. That is right for what a ray misses, but reflections and refractions that
 * leave the scene must show the view's background, not black. vtkPVWhittedView hands the background
 * it set up to this pass, which shows it to the tracer during RenderInternal() only -- after VTK
 * has cleared the framebuffer to black -- so missed pixels stay black/transparent for compositing
 * while secondary rays see the real environment. Everything else is vtkWhittedPass.
 *
 * @sa vtkWhittedPass vtkPVWhittedView
 */

#ifndef vtkPVWhittedPass_h
#define vtkPVWhittedPass_h

#include "WhittedParaViewModule.h" // for export macro
#include "vtkWhittedPass.h"

class WHITTEDPARAVIEW_EXPORT vtkPVWhittedPass : public vtkWhittedPass
{
public:
  static vtkPVWhittedPass* New();
  vtkTypeMacro(vtkPVWhittedPass, vtkWhittedPass);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * Background seen by rays that leave the scene: bottom colour, top colour, and whether it is a
   * vertical gradient. Until this is called the renderer's background is used (plain vtkWhittedPass
   * behaviour).
   */
  void SetEnvironment(const double bottom[3], const double top[3], bool gradient);

  /**
   * Converts, traces and composites with the environment set above in place of the renderer's
   * background (restored afterwards).
   */
  void RenderInternal(const vtkRenderState* s) override;

protected:
  vtkPVWhittedPass();
  ~vtkPVWhittedPass() override;

  bool HasEnvironment = false;
  double EnvironmentBottom[3] = { 0, 0, 0 };
  double EnvironmentTop[3] = { 0, 0, 0 };
  bool EnvironmentGradient = false;

private:
  vtkPVWhittedPass(const vtkPVWhittedPass&) = delete;
  void operator=(const vtkPVWhittedPass&) = delete;
};

#endif
