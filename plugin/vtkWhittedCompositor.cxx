#include "vtkWhittedCompositor.h"

#include "vtkOpenGLQuadHelper.h"
#include "vtkOpenGLRenderUtilities.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLShaderCache.h"
#include "vtkOpenGLState.h"
#include "vtkShaderProgram.h"
#include "vtkMapper.h"
#include "vtkTextureObject.h"
#include "vtk_glew.h"

#include "image/renderer.h"

#include <string>

namespace
{
// Whether t holds a w x h image of the last upload in win (the format is fixed per texture)
bool Reusable(vtkTextureObject* t, vtkOpenGLRenderWindow* win, int w, int h)
{
  return t->GetHandle() != 0 && t->GetContext() == win && t->GetTarget() == GL_TEXTURE_2D &&
    t->GetWidth() == static_cast<unsigned int>(w) && t->GetHeight() == static_cast<unsigned int>(h);
}

// The quad's fragment shader: premultiplied colour and true depth, missed pixels discarded; with
// withOffset, the depth pushed back by VTK's polygon offset (uniform polygonOffset)
std::string FragmentShader(bool withOffset)
{
  std::string fs = vtkOpenGLRenderUtilities::GetFullScreenQuadFragmentShaderTemplate();
  std::string decl = "uniform sampler2D colorTexture;\n"
                     "uniform sampler2D depthTexture;\n";
  std::string impl = "vec4 color = texture(colorTexture, texCoord);\n"
                     "if (color.a <= 0.0) { discard; }\n"
                     "gl_FragData[0] = color;\n"
                     "float d = texture(depthTexture, texCoord).r;\n";
  if (withOffset)
  {
    decl += "uniform vec3 polygonOffset;\n" // factor, units x resolvable depth, texels per pixel
      // Depth slope per pixel, as glPolygonOffset's DZ: per axis the smaller one-sided difference
      // to a hit neighbour (a silhouette must not count as a slope)
      "float slope(float d, float a, float b) {\n"
      "  float da = a < 1.0 ? abs(a - d) : 1.0, db = b < 1.0 ? abs(b - d) : 1.0;\n"
      "  float s = min(da, db);\n"
      "  return s < 1.0 ? s : 0.0;\n"
      "}\n";
    impl += "float dx = slope(d, textureOffset(depthTexture, texCoord, ivec2(1, 0)).r,\n"
            "  textureOffset(depthTexture, texCoord, ivec2(-1, 0)).r);\n"
            "float dy = slope(d, textureOffset(depthTexture, texCoord, ivec2(0, 1)).r,\n"
            "  textureOffset(depthTexture, texCoord, ivec2(0, -1)).r);\n"
            "d = clamp(d + polygonOffset.x * max(dx, dy) * polygonOffset.z + polygonOffset.y, 0.0, 1.0);\n";
  }
  impl += "gl_FragDepth = d;\n";
  vtkShaderProgram::Substitute(fs, "//VTK::FSQ::Decl", decl);
  vtkShaderProgram::Substitute(fs, "//VTK::FSQ::Impl", impl);
  return fs;
}
}

//------------------------------------------------------------------------------
vtkWhittedCompositor::vtkWhittedCompositor() = default;

vtkWhittedCompositor::~vtkWhittedCompositor()
{
  delete this->Quad;
  delete this->OffsetQuad;
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

  // VTK's coincident topology resolution (ParaView turns it on): surfaces are pushed back as VTK
  // pushes its own polygons, so OpenGL lines and points drawn over a traced surface (wireframes,
  // the selection highlight) stay in front of it as they do over OpenGL surfaces
  float offset[3] = { 0.0f, 0.0f, width > 0 ? static_cast<float>(fb.width) / width : 1.0f };
  if (vtkMapper::GetResolveCoincidentTopology() == VTK_RESOLVE_POLYGON_OFFSET)
  {
    double factor = 0.0, units = 0.0;
    vtkMapper::GetResolveCoincidentTopologyPolygonOffsetParameters(factor, units);
    offset[0] = static_cast<float>(factor);
    offset[1] = static_cast<float>(units / 16777215.0); // a unit of a 24-bit depth buffer
  }
  const bool withOffset = offset[0] != 0.0f || offset[1] != 0.0f;

  // Shader: premultiplied colour and true depth; missed pixels leave the framebuffer alone
  vtkOpenGLQuadHelper*& quad = withOffset ? this->OffsetQuad : this->Quad;
  if (!quad)
  {
    quad = new vtkOpenGLQuadHelper(win,
      vtkOpenGLRenderUtilities::GetFullScreenQuadVertexShader().c_str(),
      FragmentShader(withOffset).c_str(), "");
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
    win->GetShaderCache()->ReadyShaderProgram(quad->Program);
  }
  if (!quad->Program || !quad->Program->GetCompiled())
  {
    return false;
  }

  // Upload: into the textures of the last frame when they have this size (their formats never change), as
  // glTexSubImage2D; a new texture (glTexImage2D of 20 bytes a pixel) only on the first frame, a new size or
  // context, or after ReleaseGraphicsResources
  float* color = const_cast<float*>(&fb.color[0].x);
  float* depth = const_cast<float*>(fb.depth.data());
  if (Reusable(this->ColorTexture, win, fb.width, fb.height))
  {
    this->ColorTexture->Bind();
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, fb.width, fb.height, GL_RGBA, GL_FLOAT, color);
  }
  else
  {
    this->ColorTexture->Create2DFromRaw(fb.width, fb.height, 4, VTK_FLOAT, color);
  }
  if (Reusable(this->DepthTexture, win, fb.width, fb.height))
  {
    this->DepthTexture->Bind();
    glTexSubImage2D(
      GL_TEXTURE_2D, 0, 0, 0, fb.width, fb.height, GL_DEPTH_COMPONENT, GL_FLOAT, depth);
  }
  else
  {
    this->DepthTexture->CreateDepthFromRaw(
      fb.width, fb.height, vtkTextureObject::Float32, VTK_FLOAT, depth);
  }
  this->ColorTexture->Activate();
  this->DepthTexture->Activate();
  quad->Program->SetUniformi("colorTexture", this->ColorTexture->GetTextureUnit());
  quad->Program->SetUniformi("depthTexture", this->DepthTexture->GetTextureUnit());
  if (withOffset)
  {
    quad->Program->SetUniform3f("polygonOffset", offset);
  }

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

  quad->Render();

  this->DepthTexture->Deactivate();
  this->ColorTexture->Deactivate();
  return true;
}

//------------------------------------------------------------------------------
void vtkWhittedCompositor::ReleaseGraphicsResources(vtkWindow* w)
{
  for (vtkOpenGLQuadHelper** quad : { &this->Quad, &this->OffsetQuad })
  {
    if (*quad)
    {
      (*quad)->ReleaseGraphicsResources(w);
      delete *quad;
      *quad = nullptr;
    }
  }
  this->ColorTexture->ReleaseGraphicsResources(w);
  this->DepthTexture->ReleaseGraphicsResources(w);
}
