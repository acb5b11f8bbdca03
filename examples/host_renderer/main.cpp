// A host renderer fed from Polder's terrain pieces, without Polder's GL renderer: the host
// keeps one vertex array per piece, uploads pieces when they are created or changed, frees
// them when they retire, and draws every piece with one matrix (polder/grid_mesh.hpp).
// Usage: host_renderer DEM [FRAMES]; prints what it uploaded and how much of the last frame
// shows terrain.
#define GLFW_INCLUDE_GLCOREARB
#include <GLFW/glfw3.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <vector>

#include <glm/gtc/type_ptr.hpp>
#include <polder/polder.hpp>

// The GL 3.3 core entry points the host uses, loaded through GLFW.
// clang-format off
#define HOST_GL(X) \
  X(PFNGLGENVERTEXARRAYSPROC, GenVertexArrays) \
  X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray) \
  X(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays) \
  X(PFNGLGENBUFFERSPROC, GenBuffers) \
  X(PFNGLBINDBUFFERPROC, BindBuffer) \
  X(PFNGLBUFFERDATAPROC, BufferData) \
  X(PFNGLDELETEBUFFERSPROC, DeleteBuffers) \
  X(PFNGLENABLEVERTEXATTRIBARRAYPROC, EnableVertexAttribArray) \
  X(PFNGLVERTEXATTRIBPOINTERPROC, VertexAttribPointer) \
  X(PFNGLCREATESHADERPROC, CreateShader) \
  X(PFNGLSHADERSOURCEPROC, ShaderSource) \
  X(PFNGLCOMPILESHADERPROC, CompileShader) \
  X(PFNGLCREATEPROGRAMPROC, CreateProgram) \
  X(PFNGLATTACHSHADERPROC, AttachShader) \
  X(PFNGLLINKPROGRAMPROC, LinkProgram) \
  X(PFNGLUSEPROGRAMPROC, UseProgram) \
  X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation) \
  X(PFNGLUNIFORM2FPROC, Uniform2f) \
  X(PFNGLUNIFORMMATRIX4FVPROC, UniformMatrix4fv) \
  X(PFNGLDRAWELEMENTSPROC, DrawElements) \
  X(PFNGLCLEARCOLORPROC, ClearColor) \
  X(PFNGLCLEARPROC, Clear) \
  X(PFNGLENABLEPROC, Enable) \
  X(PFNGLVIEWPORTPROC, Viewport) \
  X(PFNGLREADPIXELSPROC, ReadPixels)
// clang-format on
namespace {
#define DECLARE(type, name) type gl##name = nullptr;
HOST_GL(DECLARE)

const char* kVertex = R"(#version 330 core
layout(location = 0) in vec3 grid;    // samples from the piece's anchor, height in metres
layout(location = 1) in vec3 normal;
uniform vec2 offset;                  // piece anchor - camera anchor, whole samples: exact
uniform mat4 gridToClip;              // one matrix for every piece of the frame
out vec3 n;
void main() { n = normal; gl_Position = gridToClip * vec4(grid.xy + offset, grid.z, 1.0); })";
const char* kFragment = R"(#version 330 core
in vec3 n; out vec4 colour;
void main() { colour = vec4(vec3(0.3, 0.5, 0.2) * (0.4 + 0.6 * max(dot(normalize(n), vec3(0.5, 0.3, 0.8)), 0.0)), 1.0); })";

struct HostPiece {
  GLuint vertexArray = 0, buffers[2] = {};
  GLsizei indexCount = 0;
  polder::GridAnchor anchor;
};

HostPiece upload(const polder::GridMeshView& mesh) {
  HostPiece piece{0, {0, 0}, GLsizei(mesh.indices.size()), mesh.anchor};
  glGenVertexArrays(1, &piece.vertexArray);
  glBindVertexArray(piece.vertexArray);
  glGenBuffers(2, piece.buffers);
  glBindBuffer(GL_ARRAY_BUFFER, piece.buffers[0]);
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(mesh.vertices.size_bytes()), mesh.vertices.data(), GL_STATIC_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(polder::GridMeshVertex), nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_BYTE, GL_TRUE, sizeof(polder::GridMeshVertex), reinterpret_cast<void*>(12));
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, piece.buffers[1]);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(mesh.indices.size_bytes()), mesh.indices.data(), GL_STATIC_DRAW);
  return piece;
}

void release(HostPiece& piece) {
  glDeleteBuffers(2, piece.buffers);
  glDeleteVertexArrays(1, &piece.vertexArray);
}

GLuint program() {
  const GLuint id = glCreateProgram();
  for (const auto& [kind, source] : {std::pair{GL_VERTEX_SHADER, kVertex}, std::pair{GL_FRAGMENT_SHADER, kFragment}}) {
    const GLuint shader = glCreateShader(GLenum(kind));
    glShaderSource(shader, 1, &source, nullptr);
    glCompileShader(shader);
    glAttachShader(id, shader);
  }
  glLinkProgram(id);
  return id;
}

}  // namespace

int main(int argc, char** argv) {
  auto dem = polder::terrain::readDem(argc > 1 ? argv[1] : "terrain.png");
  if (!dem) return std::fprintf(stderr, "%s\n", dem.error().message.c_str()), 1;
  auto field = std::make_shared<const polder::terrain::Heightfield>(std::move(dem->field));
  auto engine = polder::TerrainEngine::create(field);
  if (!engine || !glfwInit()) return 1;
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  GLFWwindow* window = glfwCreateWindow(640, 360, "Host renderer", nullptr, nullptr);
  if (!window) return 1;
  glfwMakeContextCurrent(window);
#define LOAD(type, name) gl##name = reinterpret_cast<type>(glfwGetProcAddress("gl" #name));
  HOST_GL(LOAD)
  const GLuint shaders = program();
  const GLint offsetUniform = glGetUniformLocation(shaders, "offset");
  const GLint matrixUniform = glGetUniformLocation(shaders, "gridToClip");

  std::map<std::uint64_t, HostPiece> pieces;  // by TerrainPieceKey
  std::size_t uploads = 0, stillUploads = 0;
  const int frames = argc > 2 ? std::atoi(argv[2]) : 300;
  const double cruiseM = field->heightRange().second + 400.0;
  polder::Camera camera;
  camera.pitchDeg = -25.0, camera.yawDeg = 60.0, camera.farM = 4.0 * (field->extentX() + field->extentY());
  std::vector<unsigned char> pixels;
  // The first half moves; then the camera holds still until the loaders are done (at most
  // kMostFramesToSettle frames) and for half the frames more, which must upload nothing.
  constexpr int kMostFramesToSettle = 2000;
  const int moving = frames / 2;
  int settledFrames = 0;  // still frames since every block was resident and nothing changed
  bool settled = false;
  for (int frame = 0; !glfwWindowShouldClose(window); ++frame) {
    const bool still = frame >= moving;
    if (settled ? settledFrames >= frames - moving : frame >= moving + kMostFramesToSettle) break;
    camera.position = {0.3 * field->extentX() + 40.0 * (still ? moving : frame), 0.4 * field->extentY(), cruiseM};
    glfwGetFramebufferSize(window, &camera.widthPx, &camera.heightPx);
    const polder::TerrainFrame& terrain = (*engine)->update(camera);
    for (const polder::TerrainPieceKey key : terrain.retired) release(pieces.at(key.value)), pieces.erase(key.value);
    for (const auto& list : {terrain.created, terrain.changed}) {
      for (const std::uint32_t i : list) {
        const polder::TerrainPiece& piece = terrain.pieces[i];
        if (auto old = pieces.find(piece.key.value); old != pieces.end()) release(old->second);
        pieces[piece.key.value] = upload(piece.mesh);
        ++uploads;
        stillUploads += settled;
      }
    }
    // Background loads may still land in the first still frames; once a still frame changed
    // nothing, drew every block at its own level and asked the loaders for nothing, a still
    // camera must change nothing more.
    settledFrames += settled;
    settled = settled || (still && terrain.created.empty() && terrain.changed.empty() && terrain.retired.empty() &&
                          terrain.stats.blocksOnAncestor == 0 && terrain.stats.loadsRequested == 0);
    // One matrix for all pieces: projection, rotation, the camera's fraction of a sample.
    const polder::GridSpacing spacing{field->spacingX, field->spacingY};
    const polder::GridCamera grid = polder::gridCameraOf(camera.position, spacing);
    const glm::mat4 gridToClip(camera.projection() * polder::gridToEye(camera, grid, spacing));
    glViewport(0, 0, camera.widthPx, camera.heightPx);
    glEnable(GL_DEPTH_TEST);
    glClearColor(0.6f, 0.75f, 0.9f, 0.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glUseProgram(shaders);
    glUniformMatrix4fv(matrixUniform, 1, GL_FALSE, glm::value_ptr(gridToClip));
    for (const polder::TerrainPiece& piece : terrain.pieces) {
      const HostPiece& host = pieces.at(piece.key.value);
      const glm::vec2 offset = polder::gridOffset(host.anchor, grid);
      glUniform2f(offsetUniform, offset.x, offset.y);
      glBindVertexArray(host.vertexArray);
      glDrawElements(GL_TRIANGLES, host.indexCount, GL_UNSIGNED_INT, nullptr);
    }
    pixels.resize(std::size_t(camera.widthPx) * std::size_t(camera.heightPx) * 4);
    glReadPixels(0, 0, camera.widthPx, camera.heightPx, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
    glfwSwapBuffers(window);
    glfwPollEvents();
  }
  std::size_t terrainPixels = 0;
  for (std::size_t i = 3; i < pixels.size(); i += 4) terrainPixels += pixels[i] == 255;
  if (!settled) std::fprintf(stderr, "the loaders never settled in %d still frames\n", kMostFramesToSettle);
  std::printf(
      "uploaded %zu pieces, %zu in %d settled still frames; %zu pieces held; terrain %.0f%% of the last frame\n",
      uploads, stillUploads, settledFrames, pieces.size(),
      100.0 * double(terrainPixels) / double(std::max<std::size_t>(pixels.size() / 4, 1)));
  for (auto& [key, piece] : pieces) release(piece);
  glfwTerminate();
  return settled ? 0 : 1;
}
