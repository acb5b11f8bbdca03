// Internal to polder::render: RAII owners for GL objects, shader compilation and GL error
// reporting over a glad --mx GladGLContext. Never included by public headers (glad and GL
// types stay out of the API); tests include it to exercise the compile-error path.
#pragma once

#include <string>
#include <string_view>

#include <glad/gl.h>

#include <polder/result.hpp>

namespace polder::render::detail {

enum class GlObjectKind { Buffer, VertexArray, Shader, Program };

// Owns one GL object name and deletes it through the context that made it. The context
// must be current when the owner dies (Renderer's contract).
class GlObject {
 public:
  GlObject() = default;
  GlObject(const GladGLContext* gl, GlObjectKind kind, GLuint id) : m_gl(gl), m_kind(kind), m_id(id) {}
  ~GlObject() { reset(); }
  GlObject(GlObject&& other) noexcept { *this = std::move(other); }
  GlObject& operator=(GlObject&& other) noexcept;
  GlObject(const GlObject&) = delete;
  GlObject& operator=(const GlObject&) = delete;

  GLuint id() const { return m_id; }
  explicit operator bool() const { return m_id != 0; }
  void reset();

 private:
  const GladGLContext* m_gl = nullptr;
  GlObjectKind m_kind = GlObjectKind::Buffer;
  GLuint m_id = 0;
};

GlObject makeBuffer(const GladGLContext& gl);
GlObject makeVertexArray(const GladGLContext& gl);

// Compiles and links a vertex + fragment program; the Error carries the driver's info log.
Result<GlObject> compileProgram(const GladGLContext& gl, std::string_view vertexSource, std::string_view fragmentSource,
                                std::string_view name);

// Names the first GL entry point Polder needs that the loader did not provide, or "" when
// all are there. glad leaves missing functions null, and calling one would crash.
std::string firstMissingFunction(const GladGLContext& gl);

// Drains glGetError; an Error naming every flag raised (e.g. "GL_INVALID_ENUM") after `what`,
// or success when none was.
Status takeGlErrors(const GladGLContext& gl, std::string_view what);

}  // namespace polder::render::detail
