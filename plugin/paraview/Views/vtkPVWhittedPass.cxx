#include "vtkPVWhittedPass.h"

#include "vtkObjectFactory.h"
#include "vtkRenderState.h"
#include "vtkRenderer.h"

vtkStandardNewMacro(vtkPVWhittedPass);

//------------------------------------------------------------------------------
vtkPVWhittedPass::vtkPVWhittedPass() = default;
vtkPVWhittedPass::~vtkPVWhittedPass() = default;

//------------------------------------------------------------------------------
void vtkPVWhittedPass::SetEnvironment(const double bottom[3], const double top[3], bool gradient)
{
  bool changed = !this->HasEnvironment || this->EnvironmentGradient != gradient;
  this->HasEnvironment = true;
  for (int i = 0; i < 3; ++i)
  {
    changed =
      changed || this->EnvironmentBottom[i] != bottom[i] || this->EnvironmentTop[i] != top[i];
    this->EnvironmentBottom[i] = bottom[i];
    this->EnvironmentTop[i] = top[i];
  }
  this->EnvironmentGradient = gradient;
  if (changed)
  {
    this->Modified(); // a progressive frame being refined starts over
  }
}

//------------------------------------------------------------------------------
void vtkPVWhittedPass::RenderInternal(const vtkRenderState* s)
{
  vtkRenderer* ren = s->GetRenderer();
  if (!this->HasEnvironment || !ren)
  {
    this->Superclass::RenderInternal(s);
    return;
  }
  // The framebuffer has been cleared (to black when compositing): from here on the background is
  // only read as the tracer's environment, so show it the view's.
  double bottom[3], top[3];
  ren->GetBackground(bottom);
  ren->GetBackground2(top);
  const bool gradient = ren->GetGradientBackground();
  ren->SetBackground(this->EnvironmentBottom);
  ren->SetBackground2(this->EnvironmentTop);
  ren->SetGradientBackground(this->EnvironmentGradient);

  this->Superclass::RenderInternal(s);

  ren->SetBackground(bottom);
  ren->SetBackground2(top);
  ren->SetGradientBackground(gradient);
}

//------------------------------------------------------------------------------
void vtkPVWhittedPass::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "HasEnvironment: " << this->HasEnvironment << "\n";
  os << indent << "EnvironmentBottom: " << this->EnvironmentBottom[0] << " "
     << this->EnvironmentBottom[1] << " " << this->EnvironmentBottom[2] << "\n";
  os << indent << "EnvironmentTop: " << this->EnvironmentTop[0] << " " << this->EnvironmentTop[1]
     << " " << this->EnvironmentTop[2] << "\n";
  os << indent << "EnvironmentGradient: " << this->EnvironmentGradient << "\n";
}
