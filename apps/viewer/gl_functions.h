#pragma once
// The OpenGL 3.3 core functions the viewer calls, loaded through the current context's GetProcAddress
// (glfwGetProcAddress or OSMesaGetProcAddress). Nothing here links libGL or calls gl* by symbol: with
// OSMesa in the process such calls would silently go to a dispatch table no context uses
// (docs/design.md, "Build and dependencies").
#include <GL/glcorearb.h>

#include "apps/viewer/gl_context.h"

namespace candela {

// X(type, name): one entry per function; the member `gl.Name` holds glName. Two entries per line, by hand.
// clang-format off
#define CANDELA_GL_FUNCTIONS(X)                                                            \
  X(PFNGLVIEWPORTPROC, Viewport) X(PFNGLSCISSORPROC, Scissor)                              \
  X(PFNGLCLEARCOLORPROC, ClearColor) X(PFNGLCLEARPROC, Clear)                              \
  X(PFNGLENABLEPROC, Enable) X(PFNGLDISABLEPROC, Disable)                                  \
  X(PFNGLBLENDEQUATIONPROC, BlendEquation) X(PFNGLBLENDFUNCSEPARATEPROC, BlendFuncSeparate) \
  X(PFNGLPIXELSTOREIPROC, PixelStorei) X(PFNGLREADPIXELSPROC, ReadPixels)                  \
  X(PFNGLGENTEXTURESPROC, GenTextures) X(PFNGLDELETETEXTURESPROC, DeleteTextures)          \
  X(PFNGLBINDTEXTUREPROC, BindTexture) X(PFNGLACTIVETEXTUREPROC, ActiveTexture)            \
  X(PFNGLTEXPARAMETERIPROC, TexParameteri) X(PFNGLTEXIMAGE2DPROC, TexImage2D)              \
  X(PFNGLTEXSUBIMAGE2DPROC, TexSubImage2D)                                                 \
  X(PFNGLCREATESHADERPROC, CreateShader) X(PFNGLSHADERSOURCEPROC, ShaderSource)            \
  X(PFNGLCOMPILESHADERPROC, CompileShader) X(PFNGLGETSHADERIVPROC, GetShaderiv)            \
  X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog) X(PFNGLDELETESHADERPROC, DeleteShader)    \
  X(PFNGLCREATEPROGRAMPROC, CreateProgram) X(PFNGLATTACHSHADERPROC, AttachShader)          \
  X(PFNGLLINKPROGRAMPROC, LinkProgram) X(PFNGLGETPROGRAMIVPROC, GetProgramiv)              \
  X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog) X(PFNGLDELETEPROGRAMPROC, DeleteProgram) \
  X(PFNGLUSEPROGRAMPROC, UseProgram) X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation)    \
  X(PFNGLUNIFORM1IPROC, Uniform1i) X(PFNGLUNIFORMMATRIX4FVPROC, UniformMatrix4fv)          \
  X(PFNGLGENVERTEXARRAYSPROC, GenVertexArrays) X(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays) \
  X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray) X(PFNGLGENBUFFERSPROC, GenBuffers)          \
  X(PFNGLDELETEBUFFERSPROC, DeleteBuffers) X(PFNGLBINDBUFFERPROC, BindBuffer)              \
  X(PFNGLBUFFERDATAPROC, BufferData) X(PFNGLENABLEVERTEXATTRIBARRAYPROC, EnableVertexAttribArray) \
  X(PFNGLVERTEXATTRIBPOINTERPROC, VertexAttribPointer) X(PFNGLDRAWARRAYSPROC, DrawArrays)  \
  X(PFNGLDRAWELEMENTSBASEVERTEXPROC, DrawElementsBaseVertex)
// clang-format on

struct GlFunctions {
#define CANDELA_GL_MEMBER(type, name) type name = nullptr;
  CANDELA_GL_FUNCTIONS(CANDELA_GL_MEMBER)
#undef CANDELA_GL_MEMBER

  // Loads every function through `get` (the context must be current). Throws std::runtime_error naming
  // the first function the context does not provide. Cost: one lookup per function, once per context.
  explicit GlFunctions(GlGetProcAddress get);
};

// Compiles and links a vertex + fragment shader pair; throws std::runtime_error with the driver's log.
GLuint link_program(const GlFunctions& gl, const char* vertex_source, const char* fragment_source);

}  // namespace candela
