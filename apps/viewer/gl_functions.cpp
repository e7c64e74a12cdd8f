#include "apps/viewer/gl_functions.h"

#include <stdexcept>
#include <string>

namespace candela {

GlFunctions::GlFunctions(GlGetProcAddress get) {
#define CANDELA_GL_LOAD(type, name)               \
  name = reinterpret_cast<type>(get("gl" #name)); \
  if (!name) throw std::runtime_error("OpenGL: the context does not provide gl" #name);
  CANDELA_GL_FUNCTIONS(CANDELA_GL_LOAD)
#undef CANDELA_GL_LOAD
}

// Throws std::runtime_error with the object's info log when its `status` (compile or link) is false,
// after deleting the object. Works for shaders and programs alike (their query functions share signatures).
static void check_status(GLuint object, GLenum status, PFNGLGETSHADERIVPROC get, PFNGLGETSHADERINFOLOGPROC get_log,
                         PFNGLDELETESHADERPROC remove, const char* what) {
  GLint ok = 0;
  get(object, status, &ok);
  if (ok) return;
  char log[1024] = {};
  get_log(object, sizeof(log), nullptr, log);
  remove(object);
  throw std::runtime_error(std::string("OpenGL: ") + what + ": " + log);
}

// Compiles one shader stage; throws with the info log on failure.
static GLuint compile_shader(const GlFunctions& gl, GLenum stage, const char* source) {
  GLuint shader = gl.CreateShader(stage);
  gl.ShaderSource(shader, 1, &source, nullptr);
  gl.CompileShader(shader);
  check_status(shader, GL_COMPILE_STATUS, gl.GetShaderiv, gl.GetShaderInfoLog, gl.DeleteShader,
               "shader does not compile");
  return shader;
}

GLuint link_program(const GlFunctions& gl, const char* vertex_source, const char* fragment_source) {
  GLuint vs = compile_shader(gl, GL_VERTEX_SHADER, vertex_source);
  GLuint fs = compile_shader(gl, GL_FRAGMENT_SHADER, fragment_source);
  GLuint program = gl.CreateProgram();
  gl.AttachShader(program, vs);
  gl.AttachShader(program, fs);
  gl.LinkProgram(program);
  gl.DeleteShader(vs);
  gl.DeleteShader(fs);
  check_status(program, GL_LINK_STATUS, gl.GetProgramiv, gl.GetProgramInfoLog, gl.DeleteProgram,
               "program does not link");
  return program;
}

}  // namespace candela
