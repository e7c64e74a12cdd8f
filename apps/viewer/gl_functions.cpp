#include "apps/viewer/gl_functions.h"

#include <stdexcept>
#include <string>

namespace candela {

GlFunctions::GlFunctions(GlGetProcAddress get) {
#define CANDELA_GL_LOAD(type, name)                                                       \
  name = reinterpret_cast<type>(get("gl" #name));                                         \
  if (!name) throw std::runtime_error("OpenGL: the context does not provide gl" #name);
  CANDELA_GL_FUNCTIONS(CANDELA_GL_LOAD)
#undef CANDELA_GL_LOAD
}

// Compiles one shader stage; throws with the info log on failure.
static GLuint compile_shader(const GlFunctions& gl, GLenum stage, const char* source) {
  GLuint shader = gl.CreateShader(stage);
  gl.ShaderSource(shader, 1, &source, nullptr);
  gl.CompileShader(shader);
  GLint ok = 0;
  gl.GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[1024] = {};
    gl.GetShaderInfoLog(shader, sizeof(log), nullptr, log);
    gl.DeleteShader(shader);
    throw std::runtime_error(std::string("OpenGL: shader does not compile: ") + log);
  }
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
  GLint ok = 0;
  gl.GetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[1024] = {};
    gl.GetProgramInfoLog(program, sizeof(log), nullptr, log);
    gl.DeleteProgram(program);
    throw std::runtime_error(std::string("OpenGL: program does not link: ") + log);
  }
  return program;
}

}  // namespace candela
