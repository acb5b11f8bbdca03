#include "gl_util.hpp"

#include <algorithm>
#include <array>
#include <utility>

namespace polder::render::detail {

GlObject& GlObject::operator=(GlObject&& other) noexcept {
  if (this != &other) {
    reset();
    m_gl = std::exchange(other.m_gl, nullptr);
    m_kind = other.m_kind;
    m_id = std::exchange(other.m_id, 0u);
  }
  return *this;
}

void GlObject::reset() {
  if (m_id == 0 || m_gl == nullptr) return;
  switch (m_kind) {
    case GlObjectKind::Buffer:
      m_gl->DeleteBuffers(1, &m_id);
      break;
    case GlObjectKind::VertexArray:
      m_gl->DeleteVertexArrays(1, &m_id);
      break;
    case GlObjectKind::Shader:
      m_gl->DeleteShader(m_id);
      break;
    case GlObjectKind::Program:
      m_gl->DeleteProgram(m_id);
      break;
  }
  m_id = 0;
}

GlObject makeBuffer(const GladGLContext& gl) {
  GLuint id = 0;
  gl.GenBuffers(1, &id);
  return GlObject(&gl, GlObjectKind::Buffer, id);
}

GlObject makeVertexArray(const GladGLContext& gl) {
  GLuint id = 0;
  gl.GenVertexArrays(1, &id);
  return GlObject(&gl, GlObjectKind::VertexArray, id);
}

namespace {

// The info log of a shader or program: getParameter is GetShaderiv or GetProgramiv,
// getLog GetShaderInfoLog or GetProgramInfoLog.
template <class GetParameter, class GetLog>
std::string infoLog(GLuint object, GetParameter getParameter, GetLog getLog) {
  GLint length = 0;
  getParameter(object, GL_INFO_LOG_LENGTH, &length);
  std::string log(std::size_t(std::max(length, 1)), '\0');
  GLsizei written = 0;
  getLog(object, GLsizei(log.size()), &written, log.data());
  log.resize(std::size_t(written));
  return log;
}

std::string shaderLog(const GladGLContext& gl, GLuint shader) {
  return infoLog(shader, gl.GetShaderiv, gl.GetShaderInfoLog);
}

std::string programLog(const GladGLContext& gl, GLuint program) {
  return infoLog(program, gl.GetProgramiv, gl.GetProgramInfoLog);
}

Result<GlObject> compileShader(const GladGLContext& gl, GLenum stage, std::string_view source, std::string_view name) {
  GlObject shader(&gl, GlObjectKind::Shader, gl.CreateShader(stage));
  if (!shader) {
    return makeError(ErrorKind::Environment, "glCreateShader failed for " + std::string(name));
  }
  const GLchar* text = source.data();
  const GLint length = GLint(source.size());
  gl.ShaderSource(shader.id(), 1, &text, &length);
  gl.CompileShader(shader.id());
  GLint compiled = GL_FALSE;
  gl.GetShaderiv(shader.id(), GL_COMPILE_STATUS, &compiled);
  if (compiled != GL_TRUE) {
    const char* stageName = stage == GL_VERTEX_SHADER ? "vertex" : "fragment";
    return makeError(ErrorKind::Environment, "the " + std::string(stageName) + " shader of " + std::string(name) +
                                                 " failed to compile: " + shaderLog(gl, shader.id()));
  }
  return shader;
}

}  // namespace

Result<GlObject> compileProgram(const GladGLContext& gl, std::string_view vertexSource, std::string_view fragmentSource,
                                std::string_view name) {
  auto vertex = compileShader(gl, GL_VERTEX_SHADER, vertexSource, name);
  if (!vertex) return vertex.error();
  auto fragment = compileShader(gl, GL_FRAGMENT_SHADER, fragmentSource, name);
  if (!fragment) return fragment.error();

  GlObject program(&gl, GlObjectKind::Program, gl.CreateProgram());
  if (!program) return makeError(ErrorKind::Environment, "glCreateProgram failed for " + std::string(name));
  gl.AttachShader(program.id(), vertex->id());
  gl.AttachShader(program.id(), fragment->id());
  gl.LinkProgram(program.id());
  GLint linked = GL_FALSE;
  gl.GetProgramiv(program.id(), GL_LINK_STATUS, &linked);
  if (linked != GL_TRUE) {
    return makeError(ErrorKind::Environment,
                     "the program " + std::string(name) + " failed to link: " + programLog(gl, program.id()));
  }
  // The shaders may go once linked; detaching lets their deletion take effect now.
  gl.DetachShader(program.id(), vertex->id());
  gl.DetachShader(program.id(), fragment->id());
  return program;
}

std::string firstMissingFunction(const GladGLContext& gl) {
#define POLDER_GL_ENTRY(name) \
  std::pair<const char*, bool> { "gl" #name, gl.name != nullptr }
  const std::array required = {
      POLDER_GL_ENTRY(GetString),
      POLDER_GL_ENTRY(GetError),
      POLDER_GL_ENTRY(GetIntegerv),
      POLDER_GL_ENTRY(Viewport),
      POLDER_GL_ENTRY(ClearColor),
      POLDER_GL_ENTRY(ClearDepth),
      POLDER_GL_ENTRY(Clear),
      POLDER_GL_ENTRY(Enable),
      POLDER_GL_ENTRY(Disable),
      POLDER_GL_ENTRY(DepthFunc),
      POLDER_GL_ENTRY(DepthMask),
      POLDER_GL_ENTRY(ColorMask),
      POLDER_GL_ENTRY(CullFace),
      POLDER_GL_ENTRY(FrontFace),
      POLDER_GL_ENTRY(PolygonMode),
      POLDER_GL_ENTRY(PolygonOffset),
      POLDER_GL_ENTRY(GenBuffers),
      POLDER_GL_ENTRY(DeleteBuffers),
      POLDER_GL_ENTRY(BindBuffer),
      POLDER_GL_ENTRY(BufferData),
      POLDER_GL_ENTRY(MapBufferRange),
      POLDER_GL_ENTRY(UnmapBuffer),
      POLDER_GL_ENTRY(GenVertexArrays),
      POLDER_GL_ENTRY(DeleteVertexArrays),
      POLDER_GL_ENTRY(BindVertexArray),
      POLDER_GL_ENTRY(EnableVertexAttribArray),
      POLDER_GL_ENTRY(VertexAttribPointer),
      POLDER_GL_ENTRY(CreateShader),
      POLDER_GL_ENTRY(ShaderSource),
      POLDER_GL_ENTRY(CompileShader),
      POLDER_GL_ENTRY(GetShaderiv),
      POLDER_GL_ENTRY(GetShaderInfoLog),
      POLDER_GL_ENTRY(DeleteShader),
      POLDER_GL_ENTRY(CreateProgram),
      POLDER_GL_ENTRY(AttachShader),
      POLDER_GL_ENTRY(DetachShader),
      POLDER_GL_ENTRY(LinkProgram),
      POLDER_GL_ENTRY(GetProgramiv),
      POLDER_GL_ENTRY(GetProgramInfoLog),
      POLDER_GL_ENTRY(DeleteProgram),
      POLDER_GL_ENTRY(UseProgram),
      POLDER_GL_ENTRY(GetUniformLocation),
      POLDER_GL_ENTRY(Uniform1f),
      POLDER_GL_ENTRY(Uniform3fv),
      POLDER_GL_ENTRY(UniformMatrix4fv),
      POLDER_GL_ENTRY(DrawElementsBaseVertex),
      POLDER_GL_ENTRY(ReadPixels),
      POLDER_GL_ENTRY(PixelStorei),
      POLDER_GL_ENTRY(Finish),
  };
#undef POLDER_GL_ENTRY
  for (const auto& [name, present] : required) {
    if (!present) return name;
  }
  return {};
}

namespace {
const char* glErrorName(GLenum error) {
  switch (error) {
    case GL_INVALID_ENUM:
      return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE:
      return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION:
      return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION:
      return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY:
      return "GL_OUT_OF_MEMORY";
    default:
      return "unknown GL error";
  }
}
}  // namespace

Status takeGlErrors(const GladGLContext& gl, std::string_view what) {
  std::string names;
  bool outOfMemory = false;
  // Bounded: a lost context may report an error forever.
  for (int i = 0; i < 16; ++i) {
    const GLenum error = gl.GetError();
    if (error == GL_NO_ERROR) break;
    outOfMemory = outOfMemory || error == GL_OUT_OF_MEMORY;
    if (!names.empty()) names += ", ";
    names += glErrorName(error);
  }
  if (names.empty()) return {};
  return makeError(outOfMemory ? ErrorKind::OutOfMemory : ErrorKind::Environment,
                   "OpenGL reported " + names + " during " + std::string(what));
}

}  // namespace polder::render::detail
