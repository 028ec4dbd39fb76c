#include "vtkWhittedCompositor.h"

#include "vtkOpenGLQuadHelper.h"
#include "vtkOpenGLRenderUtilities.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLShaderCache.h"
#include "vtkOpenGLState.h"
#include "vtkShaderProgram.h"
#include "vtkTextureObject.h"
#include "vtk_glew.h"

#include "renderer.h"

#include <string>

//------------------------------------------------------------------------------
vtkWhittedCompositor::vtkWhittedCompositor() = default;

vtkWhittedCompositor::~vtkWhittedCompositor()
{
  delete this->Quad;
}

//------------------------------------------------------------------------------
bool vtkWhittedCompositor::Draw(vtkOpenGLRenderWindow* win, const whitted::FrameBuffer& fb, int x,
  int y, int width, int height)
{
  if (fb.width <= 0 || fb.height <= 0)
  {
    return true;
  }
  win->MakeCurrent();

  // Shader: premultiplied colour and true depth; missed pixels leave the framebuffer alone
  if (!this->Quad)
  {
    std::string fs = vtkOpenGLRenderUtilities::GetFullScreenQuadFragmentShaderTemplate();
    vtkShaderProgram::Substitute(fs, "//VTK::FSQ::Decl",
      "uniform sampler2D colorTexture;\n"
      "uniform sampler2D depthTexture;\n");
    vtkShaderProgram::Substitute(fs, "//VTK::FSQ::Impl",
      "vec4 color = texture(colorTexture, texCoord);\n"
      "if (color.a <= 0.0) { discard; }\n"
      "gl_FragData[0] = color;\n"
      "gl_FragDepth = texture(depthTexture, texCoord).r;\n");
    this->Quad = new vtkOpenGLQuadHelper(
      win, vtkOpenGLRenderUtilities::GetFullScreenQuadVertexShader().c_str(), fs.c_str(), "");
    for (vtkTextureObject* t : { this->ColorTexture.Get(), this->DepthTexture.Get() })
    {
      t->SetContext(win);
      t->SetMinificationFilter(vtkTextureObject::Nearest);
      t->SetMagnificationFilter(vtkTextureObject::Nearest);
      t->SetWrapS(vtkTextureObject::ClampToEdge);
      t->SetWrapT(vtkTextureObject::ClampToEdge);
    }
  }
  else
  {
    win->GetShaderCache()->ReadyShaderProgram(this->Quad->Program);
  }
  if (!this->Quad->Program || !this->Quad->Program->GetCompiled())
  {
    return false;
  }

  // Upload
  this->ColorTexture->Create2DFromRaw(
    fb.width, fb.height, 4, VTK_FLOAT, const_cast<float*>(&fb.color[0].x));
  this->DepthTexture->CreateDepthFromRaw(
    fb.width, fb.height, vtkTextureObject::Float32, VTK_FLOAT, const_cast<float*>(fb.depth.data()));
  this->ColorTexture->Activate();
  this->DepthTexture->Activate();
  this->Quad->Program->SetUniformi("colorTexture", this->ColorTexture->GetTextureUnit());
  this->Quad->Program->SetUniformi("depthTexture", this->DepthTexture->GetTextureUnit());

  // Draw under scoped state: blend premultiplied colour, depth-test against what is there
  vtkOpenGLState* state = win->GetState();
  vtkOpenGLState::ScopedglViewport vsaver(state);
  vtkOpenGLState::ScopedglScissor ssaver(state);
  vtkOpenGLState::ScopedglEnableDisable dsaver(state, GL_DEPTH_TEST);
  vtkOpenGLState::ScopedglEnableDisable bsaver(state, GL_BLEND);
  vtkOpenGLState::ScopedglDepthFunc dfsaver(state);
  vtkOpenGLState::ScopedglDepthMask dmsaver(state);
  vtkOpenGLState::ScopedglBlendFuncSeparate bfsaver(state);
  vtkOpenGLState::ScopedglColorMask cmsaver(state);

  state->vtkglViewport(x, y, width, height);
  state->vtkglScissor(x, y, width, height);
  state->vtkglColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  state->vtkglEnable(GL_DEPTH_TEST);
  state->vtkglDepthFunc(GL_LEQUAL);
  state->vtkglDepthMask(GL_TRUE);
  state->vtkglEnable(GL_BLEND);
  state->vtkglBlendFuncSeparate(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);

  this->Quad->Render();

  this->DepthTexture->Deactivate();
  this->ColorTexture->Deactivate();
  return true;
}

//------------------------------------------------------------------------------
void vtkWhittedCompositor::ReleaseGraphicsResources(vtkWindow* w)
{
  if (this->Quad)
  {
    this->Quad->ReleaseGraphicsResources(w);
    delete this->Quad;
    this->Quad = nullptr;
  }
  this->ColorTexture->ReleaseGraphicsResources(w);
  this->DepthTexture->ReleaseGraphicsResources(w);
}
