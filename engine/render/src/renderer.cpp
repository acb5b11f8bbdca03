#include <polder/render/renderer.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <vector>

#include <glm/gtc/type_ptr.hpp>

#include "embedded_shaders.hpp"
#include "gl_util.hpp"

namespace polder::render {

namespace {

using detail::GlObject;

// Interleaved so one attribute setup serves every draw of the transient stream (draws
// differ only by base vertex and index offset).
struct Vertex {
  glm::vec3 position;
  glm::vec3 normal;
};
static_assert(sizeof(Vertex) == 24);

struct Uniforms {
  GLint modelView = -1;   // world-origin meshes
  GLint gridOffset = -1;  // grid meshes
  GLint gridToEye = -1;
  GLint projection = -1;
  GLint originHeight = -1;
  GLint linear = -1;
  GLint normalMatrix = -1;
  GLint ramp = -1;
  GLint minHeight = -1;
  GLint maxHeight = -1;
  GLint sunDirection = -1;
  GLint ambient = -1;
  GLint fogColour = -1;
  GLint fogDensity = -1;
  GLint tint = -1;
  GLint shade = -1;
};

struct GpuMesh {
  GlObject vertexArray;
  GlObject vertexBuffer;
  GlObject indexBuffer;
  glm::dvec3 origin{0.0};  // positions on the GPU stay relative to it
  bool grid = false;       // a grid mesh (polder/grid_mesh.hpp): anchor and spacing instead
  GridAnchor anchor;
  GridSpacing spacing;
  GLsizei indexCount = 0;
  std::size_t bytes = 0;
  std::uint32_t generation = 1;
  bool live = false;
};

// The checks upload() and drawTransient() share: untrusted spans never reach GL unchecked,
// since an index past the vertex buffer makes the driver read out of bounds.
Status validate(const DrawItem& item, const char* what) {
  if (item.indices.size() % 3 != 0) {
    return makeError(ErrorKind::InvalidArgument, std::string(what) + ": " + std::to_string(item.indices.size()) +
                                                     " indices is not a whole number of triangles");
  }
  if (!item.normals.empty() && item.normals.size() != item.positions.size()) {
    return makeError(ErrorKind::InvalidArgument, std::string(what) + ": " + std::to_string(item.normals.size()) +
                                                     " normals for " + std::to_string(item.positions.size()) +
                                                     " positions");
  }
  std::uint32_t maxIndex = 0;
  for (const std::uint32_t index : item.indices) maxIndex = std::max(maxIndex, index);
  if (!item.indices.empty() && std::size_t(maxIndex) >= item.positions.size()) {
    return makeError(ErrorKind::InvalidArgument, std::string(what) + ": index " + std::to_string(maxIndex) +
                                                     " is out of range for " + std::to_string(item.positions.size()) +
                                                     " positions");
  }
  if (item.positions.size() > std::size_t(INT32_MAX) || item.indices.size() > std::size_t(INT32_MAX)) {
    return makeError(ErrorKind::InvalidArgument, std::string(what) + ": mesh too large for one draw");
  }
  return {};
}

// Area-weighted vertex normals (the cross product's length is twice the triangle's area).
// `out` is caller storage reused between calls.
void computeNormals(const DrawItem& item, std::vector<glm::vec3>& out) {
  out.assign(item.positions.size(), glm::vec3(0.0f));
  for (std::size_t i = 0; i + 2 < item.indices.size(); i += 3) {
    const std::uint32_t a = item.indices[i], b = item.indices[i + 1], c = item.indices[i + 2];
    const glm::vec3 n = glm::cross(item.positions[b] - item.positions[a], item.positions[c] - item.positions[a]);
    out[a] += n;
    out[b] += n;
    out[c] += n;
  }
  for (glm::vec3& n : out) {
    const float length = glm::length(n);
    n = length > 0.0f ? n / length : glm::vec3(0.0f, 0.0f, 1.0f);  // unused vertex: any unit vector
  }
}

void writeVertices(Vertex* out, std::span<const glm::vec3> positions, std::span<const glm::vec3> normals) {
  for (std::size_t i = 0; i < positions.size(); ++i) out[i] = Vertex{positions[i], normals[i]};
}

// Attribute layout of a VAO whose ARRAY_BUFFER is bound.
void setVertexLayout(const GladGLContext& gl) {
  gl.EnableVertexAttribArray(0);
  gl.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(Vertex),
                         reinterpret_cast<const void*>(offsetof(Vertex, position)));
  gl.EnableVertexAttribArray(1);
  gl.VertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(Vertex),
                         reinterpret_cast<const void*>(offsetof(Vertex, normal)));
}

// Attribute layout of a grid mesh's VAO (GridMeshVertex as it is in memory).
void setGridVertexLayout(const GladGLContext& gl) {
  gl.EnableVertexAttribArray(0);
  gl.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(GridMeshVertex),
                         reinterpret_cast<const void*>(offsetof(GridMeshVertex, x)));
  gl.EnableVertexAttribArray(1);
  gl.VertexAttribPointer(1, 3, GL_BYTE, GL_TRUE, sizeof(GridMeshVertex),
                         reinterpret_cast<const void*>(offsetof(GridMeshVertex, nx)));
}

Uniforms uniformsOf(const GladGLContext& gl, GLuint id) {
  Uniforms u;
  u.modelView = gl.GetUniformLocation(id, "u_modelView");
  u.gridOffset = gl.GetUniformLocation(id, "u_gridOffset");
  u.gridToEye = gl.GetUniformLocation(id, "u_gridToEye");
  u.projection = gl.GetUniformLocation(id, "u_projection");
  u.originHeight = gl.GetUniformLocation(id, "u_originHeight");
  u.linear = gl.GetUniformLocation(id, "u_linear");
  u.normalMatrix = gl.GetUniformLocation(id, "u_normalMatrix");
  u.ramp = gl.GetUniformLocation(id, "u_ramp");
  u.minHeight = gl.GetUniformLocation(id, "u_minHeight");
  u.maxHeight = gl.GetUniformLocation(id, "u_maxHeight");
  u.sunDirection = gl.GetUniformLocation(id, "u_sunDirection");
  u.ambient = gl.GetUniformLocation(id, "u_ambient");
  u.fogColour = gl.GetUniformLocation(id, "u_fogColour");
  u.fogDensity = gl.GetUniformLocation(id, "u_fogDensity");
  u.tint = gl.GetUniformLocation(id, "u_tint");
  u.shade = gl.GetUniformLocation(id, "u_shade");
  return u;
}

// The frame's camera, projection and style, for one program.
void setFrameUniforms(const GladGLContext& gl, GLuint program, const Uniforms& u, const glm::mat4& projection,
                      const TerrainStyle& style) {
  gl.UseProgram(program);
  gl.UniformMatrix4fv(u.projection, 1, GL_FALSE, glm::value_ptr(projection));
  gl.Uniform3fv(u.ramp, GLsizei(style.ramp.size()), glm::value_ptr(style.ramp[0]));
  gl.Uniform1f(u.minHeight, style.minHeightM);
  gl.Uniform1f(u.maxHeight, style.maxHeightM);
  gl.Uniform3fv(u.sunDirection, 1, glm::value_ptr(style.sunDirection));
  gl.Uniform1f(u.ambient, style.ambient);
  gl.Uniform3fv(u.fogColour, 1, glm::value_ptr(style.fogColour));
  gl.Uniform1f(u.fogDensity, style.fogDensity);
  gl.Uniform1f(u.shade, 1.0f);
}

// Validation of a grid mesh, as validate() for world-origin ones.
Status validateGrid(const GridMeshView& mesh) {
  if (mesh.indices.size() % 3 != 0) {
    return makeError(ErrorKind::InvalidArgument, "Renderer::upload: " + std::to_string(mesh.indices.size()) +
                                                     " indices is not a whole number of triangles");
  }
  for (const std::uint32_t index : mesh.indices) {
    if (std::size_t(index) >= mesh.vertices.size()) {
      return makeError(ErrorKind::InvalidArgument, "Renderer::upload: index " + std::to_string(index) +
                                                       " is out of range for " + std::to_string(mesh.vertices.size()) +
                                                       " grid vertices");
    }
  }
  if (mesh.vertices.size() > std::size_t(INT32_MAX) || mesh.indices.size() > std::size_t(INT32_MAX)) {
    return makeError(ErrorKind::InvalidArgument, "Renderer::upload: mesh too large for one draw");
  }
  if (!(mesh.spacing.x > 0.0) || !(mesh.spacing.y > 0.0)) {
    return makeError(ErrorKind::InvalidArgument, "Renderer::upload: a grid mesh needs a positive spacing");
  }
  return {};
}

GLADapiproc loadThrough(void* loader, const char* name) { return (*static_cast<const GlProcLoader*>(loader))(name); }

std::string glString(const GladGLContext& gl, GLenum name) {
  const auto* text = reinterpret_cast<const char*>(gl.GetString(name));
  return text ? std::string(text) : std::string("(unknown)");
}

}  // namespace

struct Renderer::Impl {
  // First member, so it outlives every GlObject that deletes through it.
  GladGLContext gl{};
  RendererOptions options;
  std::string description;
  GlObject program;
  Uniforms uniforms;
  GlObject gridProgram;
  Uniforms gridUniforms;
  GLuint currentProgram = 0;

  std::vector<GpuMesh> meshes;  // slot i holds MeshHandle::slot i + 1
  std::vector<std::uint32_t> freeSlots;
  std::size_t meshCount = 0;
  std::size_t meshBytes = 0;

  // The transient stream: one VAO over one vertex and one index buffer, filled front to back
  // during a frame and invalidated at the first write of the next.
  GlObject streamArray;
  GlObject streamVertices;
  GlObject streamIndices;
  std::size_t streamVertexCapacity = 0;
  std::size_t streamIndexCapacity = 0;
  std::size_t streamVertexCursor = 0;
  std::size_t streamIndexCursor = 0;
  std::size_t streamGrowths = 0;
  std::vector<glm::vec3> scratchNormals;  // reused, so steady-state frames do not allocate

  bool inFrame = false;
  Camera camera;
  GridSpacing gridSpacing{0.0, 0.0};  // what u_gridToEye was computed for this frame
  GridCamera gridCamera;
  std::uint64_t uploadedBytes = 0;
  glm::dmat4 viewRotation{1.0};
  glm::dvec3 cameraPosition{0.0};
  int frameWidth = 0;
  int frameHeight = 0;
  bool wireframe = false;
  std::size_t drawCalls = 0;
  std::size_t triangles = 0;

  // Takes an uploaded mesh into a slot and counts it.
  MeshHandle adopt(GpuMesh mesh) {
    std::uint32_t slot = 0;
    if (!freeSlots.empty()) {
      slot = freeSlots.back();
      freeSlots.pop_back();
      mesh.generation = meshes[slot].generation + 1;
    } else {
      slot = std::uint32_t(meshes.size());
      meshes.emplace_back();
    }
    mesh.live = true;
    meshCount += 1;
    meshBytes += mesh.bytes;
    uploadedBytes += mesh.bytes;
    meshes[slot] = std::move(mesh);
    return MeshHandle{slot + 1, meshes[slot].generation};
  }

  std::span<const glm::vec3> normalsOf(const DrawItem& item) {
    if (!item.normals.empty()) return item.normals;
    computeNormals(item, scratchNormals);
    return scratchNormals;
  }

  // Makes room for `count` elements in a stream buffer bound to `target`, growing it (doubling)
  // when this frame's draws no longer fit, and maps the range to write. Returns null when GL
  // cannot map it.
  void* mapStream(GLenum target, std::size_t elementBytes, std::size_t count, std::size_t& capacity,
                  std::size_t& cursor) {
    GLbitfield access = GL_MAP_WRITE_BIT;
    if (cursor + count > capacity) {
      capacity = std::max({capacity * 2, cursor + count, std::size_t(1024)});
      gl.BufferData(target, GLsizeiptr(capacity * elementBytes), nullptr, GL_STREAM_DRAW);
      ++streamGrowths;
      cursor = 0;
    }
    if (cursor == 0) {
      // First write of a frame (or fresh storage): earlier frames' data is dead.
      access |= GL_MAP_INVALIDATE_BUFFER_BIT;
    } else {
      // Later in the frame: this range was never written since the invalidation, so no wait.
      access |= GL_MAP_INVALIDATE_RANGE_BIT | GL_MAP_UNSYNCHRONIZED_BIT;
    }
    return gl.MapBufferRange(target, GLintptr(cursor * elementBytes), GLsizeiptr(count * elementBytes), access);
  }

  void drawIndexed(GLuint vertexArray, GLsizei indexCount, std::size_t firstIndex, GLint baseVertex,
                   const glm::dvec3& origin, const glm::vec3& tint, const glm::mat3& linear = glm::mat3(1.0f)) {
    // The only place world coordinates meet the camera: subtract in double, then go float.
    const glm::dvec3 offset = origin - cameraPosition;
    glm::dmat4 modelView = viewRotation;
    modelView[3] = viewRotation * glm::dvec4(offset, 1.0);
    const glm::mat4 modelViewF(modelView);
    // A flattening scale has no inverse: its normals keep the linear part's directions.
    const glm::dmat3 linearD(linear);
    const double determinant = glm::determinant(linearD);
    const glm::mat3 normalMatrix(std::abs(determinant) > 1e-30 ? glm::transpose(glm::inverse(linearD)) : linearD);

    use(program.id());
    gl.BindVertexArray(vertexArray);
    gl.UniformMatrix4fv(uniforms.modelView, 1, GL_FALSE, glm::value_ptr(modelViewF));
    gl.UniformMatrix3fv(uniforms.linear, 1, GL_FALSE, glm::value_ptr(linear));
    gl.UniformMatrix3fv(uniforms.normalMatrix, 1, GL_FALSE, glm::value_ptr(normalMatrix));
    gl.Uniform1f(uniforms.originHeight, float(origin.z));
    gl.Uniform3fv(uniforms.tint, 1, glm::value_ptr(tint));
    submit(uniforms, indexCount, firstIndex, baseVertex);
  }

  // A grid mesh: its offset from the camera's anchor is the only per-draw position data.
  void drawGrid(const GpuMesh& mesh, const glm::vec3& tint) {
    use(gridProgram.id());
    if (mesh.spacing != gridSpacing) {
      gridSpacing = mesh.spacing;
      gridCamera = gridCameraOf(camera.position, gridSpacing);
      const glm::mat4 toEye(gridToEye(camera, gridCamera, gridSpacing));
      gl.UniformMatrix4fv(gridUniforms.gridToEye, 1, GL_FALSE, glm::value_ptr(toEye));
    }
    const glm::vec2 offset = gridOffset(mesh.anchor, gridCamera);
    gl.BindVertexArray(mesh.vertexArray.id());
    gl.Uniform2fv(gridUniforms.gridOffset, 1, glm::value_ptr(offset));
    gl.Uniform3fv(gridUniforms.tint, 1, glm::value_ptr(tint));
    submit(gridUniforms, mesh.indexCount, 0, 0);
  }

  void use(GLuint id) {
    if (currentProgram == id) return;
    gl.UseProgram(id);
    currentProgram = id;
  }

  void submit(const Uniforms& u, GLsizei indexCount, std::size_t firstIndex, GLint baseVertex) {
    const void* indexOffset = reinterpret_cast<const void*>(firstIndex * sizeof(std::uint32_t));
    gl.DrawElementsBaseVertex(GL_TRIANGLES, indexCount, GL_UNSIGNED_INT, indexOffset, baseVertex);
    ++drawCalls;
    triangles += std::size_t(indexCount) / 3;

    if (wireframe) {
      // Edges as a second pass over the same triangles, pulled towards the eye so they win
      // the depth test against their own surface.
      gl.PolygonMode(GL_FRONT_AND_BACK, GL_LINE);
      gl.Enable(GL_POLYGON_OFFSET_LINE);
      gl.Uniform1f(u.shade, options.wireframeBrightness);
      gl.DrawElementsBaseVertex(GL_TRIANGLES, indexCount, GL_UNSIGNED_INT, indexOffset, baseVertex);
      gl.Uniform1f(u.shade, 1.0f);
      gl.Disable(GL_POLYGON_OFFSET_LINE);
      gl.PolygonMode(GL_FRONT_AND_BACK, GL_FILL);
      ++drawCalls;
    }
  }
};

Renderer::Renderer(std::unique_ptr<Impl> impl) : m_impl(std::move(impl)) {}

Renderer::~Renderer() = default;

Result<std::unique_ptr<Renderer>> Renderer::create(const GlProcLoader& loader, const RendererOptions& options) {
  if (!loader) return makeError(ErrorKind::InvalidArgument, "Renderer::create: the GL loader is empty");

  auto impl = std::make_unique<Impl>();
  impl->options = options;
  GladGLContext& gl = impl->gl;
  const int version = gladLoadGLContextUserPtr(&gl, loadThrough, const_cast<GlProcLoader*>(&loader));
  if (version == 0) {
    return makeError(ErrorKind::Environment,
                     "Renderer::create: no OpenGL context is current, or the loader does not provide glGetString");
  }
  if (version < GLAD_MAKE_VERSION(3, 3)) {
    return makeError(ErrorKind::Environment,
                     "Renderer::create: OpenGL 3.3 core or newer is needed; the current "
                     "context is \"" +
                         glString(gl, GL_VERSION) + "\"");
  }
  if (const std::string missing = detail::firstMissingFunction(gl); !missing.empty()) {
    return makeError(ErrorKind::Environment, "Renderer::create: the GL loader does not provide " + missing);
  }
  // Errors the host left pending are not ours to report.
  for (int i = 0; i < 16 && gl.GetError() != GL_NO_ERROR; ++i) {
  }
  impl->description = "OpenGL " + glString(gl, GL_VERSION) + " on " + glString(gl, GL_RENDERER);

  auto program = detail::compileProgram(gl, shaders::terrain_vert, shaders::terrain_frag, "terrain");
  if (!program) return program.error();
  impl->program = std::move(*program);
  impl->uniforms = uniformsOf(gl, impl->program.id());
  auto gridProgram = detail::compileProgram(gl, shaders::terrain_grid_vert, shaders::terrain_frag, "terrain grid");
  if (!gridProgram) return gridProgram.error();
  impl->gridProgram = std::move(*gridProgram);
  impl->gridUniforms = uniformsOf(gl, impl->gridProgram.id());

  impl->streamArray = detail::makeVertexArray(gl);
  impl->streamVertices = detail::makeBuffer(gl);
  impl->streamIndices = detail::makeBuffer(gl);
  impl->streamVertexCapacity = std::max<std::size_t>(options.transientVertexCapacity, 1024);
  impl->streamIndexCapacity = std::max<std::size_t>(options.transientIndexCapacity, 1024);
  gl.BindVertexArray(impl->streamArray.id());
  gl.BindBuffer(GL_ARRAY_BUFFER, impl->streamVertices.id());
  gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(impl->streamVertexCapacity * sizeof(Vertex)), nullptr, GL_STREAM_DRAW);
  setVertexLayout(gl);
  gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, impl->streamIndices.id());
  gl.BufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(impl->streamIndexCapacity * sizeof(std::uint32_t)), nullptr,
                GL_STREAM_DRAW);
  gl.BindVertexArray(0);
  if (Status status = detail::takeGlErrors(gl, "Renderer::create"); !status) return status.error();

  return std::unique_ptr<Renderer>(new Renderer(std::move(impl)));
}

Result<MeshHandle> Renderer::upload(const MeshData& mesh) { return upload(drawItemOf(mesh)); }

Result<MeshHandle> Renderer::upload(const DrawItem& item) {
  if (Status status = validate(item, "Renderer::upload"); !status) return status.error();
  Impl& r = *m_impl;
  const GladGLContext& gl = r.gl;
  const std::span<const glm::vec3> normals = r.normalsOf(item);

  GpuMesh mesh;
  mesh.vertexArray = detail::makeVertexArray(gl);
  mesh.vertexBuffer = detail::makeBuffer(gl);
  mesh.indexBuffer = detail::makeBuffer(gl);
  mesh.origin = item.origin;
  mesh.indexCount = GLsizei(item.indices.size());
  const std::size_t vertexBytes = item.positions.size() * sizeof(Vertex);
  const std::size_t indexBytes = item.indices.size() * sizeof(std::uint32_t);
  mesh.bytes = vertexBytes + indexBytes;

  gl.BindVertexArray(mesh.vertexArray.id());
  gl.BindBuffer(GL_ARRAY_BUFFER, mesh.vertexBuffer.id());
  gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(vertexBytes), nullptr, GL_STATIC_DRAW);
  bool written = true;
  if (vertexBytes > 0) {
    void* mapped =
        gl.MapBufferRange(GL_ARRAY_BUFFER, 0, GLsizeiptr(vertexBytes), GL_MAP_WRITE_BIT | GL_MAP_INVALIDATE_BUFFER_BIT);
    if (mapped) {
      writeVertices(static_cast<Vertex*>(mapped), item.positions, normals);
      written = gl.UnmapBuffer(GL_ARRAY_BUFFER) == GL_TRUE;
    } else {
      written = false;
    }
  }
  setVertexLayout(gl);
  gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, mesh.indexBuffer.id());
  gl.BufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(indexBytes), item.indices.data(), GL_STATIC_DRAW);
  gl.BindVertexArray(0);
  if (Status status = detail::takeGlErrors(gl, "Renderer::upload"); !status) return status.error();
  if (!written) {
    return makeError(ErrorKind::OutOfMemory, "Renderer::upload: could not write " + std::to_string(vertexBytes) +
                                                 " bytes of vertices to the GPU");
  }

  return r.adopt(std::move(mesh));
}

Result<MeshHandle> Renderer::upload(const GridMeshView& grid) {
  if (Status status = validateGrid(grid); !status) return status.error();
  Impl& r = *m_impl;
  const GladGLContext& gl = r.gl;
  GpuMesh mesh;
  mesh.vertexArray = detail::makeVertexArray(gl);
  mesh.vertexBuffer = detail::makeBuffer(gl);
  mesh.indexBuffer = detail::makeBuffer(gl);
  mesh.grid = true;
  mesh.anchor = grid.anchor;
  mesh.spacing = grid.spacing;
  mesh.indexCount = GLsizei(grid.indices.size());
  const std::size_t vertexBytes = grid.vertices.size_bytes();
  const std::size_t indexBytes = grid.indices.size_bytes();
  mesh.bytes = vertexBytes + indexBytes;

  gl.BindVertexArray(mesh.vertexArray.id());
  gl.BindBuffer(GL_ARRAY_BUFFER, mesh.vertexBuffer.id());
  gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(vertexBytes), grid.vertices.data(), GL_STATIC_DRAW);
  setGridVertexLayout(gl);
  gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, mesh.indexBuffer.id());
  gl.BufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(indexBytes), grid.indices.data(), GL_STATIC_DRAW);
  gl.BindVertexArray(0);
  if (Status status = detail::takeGlErrors(gl, "Renderer::upload"); !status) return status.error();
  return r.adopt(std::move(mesh));
}

void Renderer::release(MeshHandle handle) {
  if (!handle.valid()) return;
  Impl& r = *m_impl;
  assert(handle.slot <= r.meshes.size() && "Renderer::release: handle from another renderer");
  GpuMesh& mesh = r.meshes[handle.slot - 1];
  assert(mesh.live && mesh.generation == handle.generation && "Renderer::release: mesh already released");
  if (!mesh.live || mesh.generation != handle.generation) return;
  r.meshBytes -= mesh.bytes;
  --r.meshCount;
  mesh.vertexArray.reset();
  mesh.vertexBuffer.reset();
  mesh.indexBuffer.reset();
  mesh.live = false;
  r.freeSlots.push_back(handle.slot - 1);
}

void Renderer::beginFrame(const Camera& camera, const TerrainStyle& style) {
  Impl& r = *m_impl;
  const GladGLContext& gl = r.gl;
  assert(!r.inFrame && "Renderer::beginFrame: the previous frame was not ended");
  assert(camera.widthPx > 0 && camera.heightPx > 0 && "Renderer::beginFrame: empty viewport");
  r.inFrame = true;
  r.camera = camera;
  r.gridSpacing = GridSpacing{0.0, 0.0};
  r.viewRotation = camera.viewRotation();
  r.cameraPosition = camera.position;
  r.frameWidth = camera.widthPx;
  r.frameHeight = camera.heightPx;
  r.wireframe = style.wireframe;
  r.drawCalls = 0;
  r.triangles = 0;
  r.streamVertexCursor = 0;
  r.streamIndexCursor = 0;

  gl.Viewport(0, 0, camera.widthPx, camera.heightPx);
  gl.Disable(GL_SCISSOR_TEST);
  gl.Disable(GL_BLEND);
  gl.Disable(GL_STENCIL_TEST);
  gl.Disable(GL_FRAMEBUFFER_SRGB);
  gl.Disable(GL_POLYGON_OFFSET_LINE);
  gl.Disable(GL_POLYGON_OFFSET_FILL);
  gl.PolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  gl.PolygonOffset(-1.0f, -1.0f);  // used only by the wireframe pass
  gl.Enable(GL_DEPTH_TEST);
  gl.DepthFunc(GL_LESS);
  gl.DepthMask(GL_TRUE);
  gl.ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  gl.FrontFace(GL_CCW);
  if (r.options.cullBackFaces) {
    gl.Enable(GL_CULL_FACE);
    gl.CullFace(GL_BACK);
  } else {
    gl.Disable(GL_CULL_FACE);
  }
  // Alpha 0 marks sky (terrain writes 1).
  gl.ClearColor(style.skyColour.r, style.skyColour.g, style.skyColour.b, 0.0f);
  gl.ClearDepth(1.0);
  gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);

  const glm::mat4 projection(camera.projection());
  setFrameUniforms(gl, r.gridProgram.id(), r.gridUniforms, projection, style);
  setFrameUniforms(gl, r.program.id(), r.uniforms, projection, style);
  r.currentProgram = r.program.id();
}

void Renderer::draw(MeshHandle handle, const glm::vec3& tint) {
  Impl& r = *m_impl;
  assert(r.inFrame && "Renderer::draw: call between beginFrame and endFrame");
  assert(handle.valid() && handle.slot <= r.meshes.size() && "Renderer::draw: invalid mesh handle");
  const GpuMesh& mesh = r.meshes[handle.slot - 1];
  assert(mesh.live && mesh.generation == handle.generation && "Renderer::draw: mesh was released");
  if (!mesh.live || mesh.generation != handle.generation || mesh.indexCount == 0) return;
  if (mesh.grid) return r.drawGrid(mesh, tint);
  r.drawIndexed(mesh.vertexArray.id(), mesh.indexCount, 0, 0, mesh.origin, tint);
}

Status Renderer::drawTransient(const DrawItem& item) {
  Impl& r = *m_impl;
  assert(r.inFrame && "Renderer::drawTransient: call between beginFrame and endFrame");
  if (Status status = validate(item, "Renderer::drawTransient"); !status) return status;
  if (item.indices.empty()) return {};
  const GladGLContext& gl = r.gl;
  const std::span<const glm::vec3> normals = r.normalsOf(item);

  gl.BindVertexArray(r.streamArray.id());
  gl.BindBuffer(GL_ARRAY_BUFFER, r.streamVertices.id());
  void* vertices =
      r.mapStream(GL_ARRAY_BUFFER, sizeof(Vertex), item.positions.size(), r.streamVertexCapacity, r.streamVertexCursor);
  if (!vertices) return detail::takeGlErrors(gl, "Renderer::drawTransient (mapping vertices)");
  writeVertices(static_cast<Vertex*>(vertices), item.positions, normals);
  const bool verticesOk = gl.UnmapBuffer(GL_ARRAY_BUFFER) == GL_TRUE;

  // The element buffer is part of the stream VAO, bound above.
  void* indices = r.mapStream(GL_ELEMENT_ARRAY_BUFFER, sizeof(std::uint32_t), item.indices.size(),
                              r.streamIndexCapacity, r.streamIndexCursor);
  if (!indices) return detail::takeGlErrors(gl, "Renderer::drawTransient (mapping indices)");
  std::memcpy(indices, item.indices.data(), item.indices.size_bytes());
  const bool indicesOk = gl.UnmapBuffer(GL_ELEMENT_ARRAY_BUFFER) == GL_TRUE;
  if (!verticesOk || !indicesOk) {
    return makeError(ErrorKind::Environment, "Renderer::drawTransient: the stream buffer was lost while mapped");
  }

  r.drawIndexed(r.streamArray.id(), GLsizei(item.indices.size()), r.streamIndexCursor, GLint(r.streamVertexCursor),
                item.origin, item.tint, item.linear);
  r.streamVertexCursor += item.positions.size();
  r.streamIndexCursor += item.indices.size();
  r.uploadedBytes += item.positions.size() * sizeof(Vertex) + item.indices.size_bytes();
  return {};
}

Status Renderer::endFrame() {
  Impl& r = *m_impl;
  assert(r.inFrame && "Renderer::endFrame: no frame begun");
  r.inFrame = false;
  r.gl.BindVertexArray(0);
  r.use(r.program.id());
  return detail::takeGlErrors(r.gl, "the frame");
}

Status Renderer::readPixels(RgbaImage& image) {
  Impl& r = *m_impl;
  const GladGLContext& gl = r.gl;
  if (r.frameWidth <= 0 || r.frameHeight <= 0) {
    return makeError(ErrorKind::InvalidArgument, "Renderer::readPixels: no frame has been drawn yet");
  }
  if (image.width != r.frameWidth || image.height != r.frameHeight) image = RgbaImage(r.frameWidth, r.frameHeight);
  // A host's pack state must not redirect or reshape the read.
  gl.BindBuffer(GL_PIXEL_PACK_BUFFER, 0);
  gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
  gl.PixelStorei(GL_PACK_ROW_LENGTH, 0);
  gl.PixelStorei(GL_PACK_SKIP_ROWS, 0);
  gl.PixelStorei(GL_PACK_SKIP_PIXELS, 0);
  gl.ReadPixels(0, 0, image.width, image.height, GL_RGBA, GL_UNSIGNED_BYTE, image.pixels.data());
  // GL's row 0 is the bottom; RgbaImage's is the top.
  const std::size_t rowBytes = std::size_t(image.width) * 4;
  for (int y = 0; y < image.height / 2; ++y) {
    std::uint8_t* top = image.pixels.data() + std::size_t(y) * rowBytes;
    std::uint8_t* bottom = image.pixels.data() + std::size_t(image.height - 1 - y) * rowBytes;
    std::swap_ranges(top, top + rowBytes, bottom);
  }
  return detail::takeGlErrors(gl, "Renderer::readPixels");
}

void Renderer::finish() { m_impl->gl.Finish(); }

RendererStats Renderer::stats() const {
  const Impl& r = *m_impl;
  RendererStats stats;
  stats.meshCount = r.meshCount;
  stats.meshBytes = r.meshBytes;
  stats.transientBytes = r.streamVertexCapacity * sizeof(Vertex) + r.streamIndexCapacity * sizeof(std::uint32_t);
  stats.transientGrowths = r.streamGrowths;
  stats.drawCalls = r.drawCalls;
  stats.triangles = r.triangles;
  stats.uploadedBytes = r.uploadedBytes;
  return stats;
}

const std::string& Renderer::contextDescription() const { return m_impl->description; }

}  // namespace polder::render
