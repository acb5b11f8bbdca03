// polder::render — draws terrain meshes into whatever OpenGL 3.3+ core context is current.
//
// The renderer never creates a context or a window: a platform target (OsmesaContext,
// GlfwWindow) or the host program makes one current and hands over its GL loader, so Polder
// can draw inside someone else's window. GL entry points live in a per-renderer function
// table (glad --mx); nothing GL-related is process-global.
//
// One frame:
//   renderer->beginFrame(camera, style);          // viewport, clear to sky, state
//   renderer->draw(handle);                       // static meshes uploaded once
//   renderer->drawTransient(drawItemOf(mesh));    // per-frame meshes, streamed
//   renderer->endFrame();                         // reports GL errors of the frame
//   renderer->readPixels(image);                  // optional: read the frame back
//
// Threads and lifetime: every call, the destructor included, must happen on a thread where
// the context the renderer was created in (or one sharing its objects) is current. Destroy
// the renderer before its context.
//
// Coordinates: meshes carry float positions relative to a double origin. Per draw the
// renderer computes (origin - camera.position) in double and sends a float model-view
// matrix, so terrain 1e7 m from the world origin draws as steadily as terrain near it.
// Grid meshes (terrain pieces) carry integer sample offsets from an integer anchor instead,
// and all of a frame's grid meshes go through one matrix (polder/grid_mesh.hpp).
//
// Shading mirrors polder::shadeTerrain (elevation ramp, Lambert + ambient, exp-squared fog by
// eye distance) per fragment, then multiplies by the draw's tint. Terrain fragments write
// alpha 1 and the clear writes alpha 0, so alpha read back is a terrain/sky mask.
//
// GL state: beginFrame sets everything the renderer depends on (viewport, depth test, culling,
// polygon mode, blending off, scissor off, sRGB writes off) and the renderer does not restore
// the host's state afterwards. It draws into, and reads from, the framebuffers bound when
// called (the default framebuffer unless the host bound its own).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include <glm/glm.hpp>

#include <polder/camera.hpp>
#include <polder/grid_mesh.hpp>
#include <polder/image.hpp>
#include <polder/mesh_data.hpp>
#include <polder/result.hpp>
#include <polder/terrain_style.hpp>

namespace polder::render {

// An OpenGL entry point as GL loaders return it. A function pointer rather than void*, so
// glfwGetProcAddress and OSMesaGetProcAddress fit without casts.
using GlProc = void (*)();

// Looks up a GL entry point by its name ("glClear") for the current context; returns null when
// it is absent. A plain function converts (e.g. glfwGetProcAddress,
// polder::platform::OsmesaContext::getProcAddress); a host may pass a capturing lambda. The
// loader is used only inside Renderer::create.
using GlProcLoader = std::function<GlProc(const char* name)>;

// A mesh resident on the GPU. Default-constructed is "no mesh". Handles of released meshes
// are detected (generation count) and rejected by assertions.
struct MeshHandle {
  std::uint32_t slot = 0;  // 1-based; 0 means no mesh
  std::uint32_t generation = 0;

  bool valid() const { return slot != 0; }
  friend bool operator==(const MeshHandle&, const MeshHandle&) = default;
};

struct RendererOptions {
  // Terrain triangles are counter-clockwise seen from above; culling skips the far slopes of
  // hills. Turn off for meshes with mixed winding.
  bool cullBackFaces = true;
  // Wireframe overlay colour = shaded colour * this (edges stay readable through fog).
  float wireframeBrightness = 0.35f;
  // First size of the transient stream. It doubles when a frame needs more, so after the
  // largest frame it stops changing (no GL allocation in steady state).
  std::size_t transientVertexCapacity = std::size_t(1) << 16;
  std::size_t transientIndexCapacity = std::size_t(3) << 17;
};

struct RendererStats {
  std::size_t meshCount = 0;         // uploaded, not yet released
  std::size_t meshBytes = 0;         // GPU bytes of those meshes
  std::size_t transientBytes = 0;    // capacity of the transient stream
  std::size_t transientGrowths = 0;  // times the stream grew since create()
  std::size_t drawCalls = 0;         // in the current (or last) frame, wireframe passes included
  std::size_t triangles = 0;         // in the current (or last) frame, wireframe passes excluded
  std::uint64_t uploadedBytes = 0;   // vertex and index bytes sent since create(): uploads and streams
};

class Renderer {
 public:
  // Loads GL through `loader` for the context current now, checks it is OpenGL 3.3+ with every
  // entry point Polder uses, and compiles the shaders. Errors (kind Environment): no context
  // current, a loader that finds nothing, too old a version, a missing function, a shader
  // that fails to compile or link (with the driver's log). An empty loader is InvalidArgument.
  static Result<std::unique_ptr<Renderer>> create(const GlProcLoader& loader, const RendererOptions& options = {});
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Copies a mesh to the GPU for repeated drawing (static full-resolution terrain, cached LOD
  // meshes). Missing normals are computed (area-weighted vertex normals). Errors:
  // InvalidArgument for an index out of range, an index count not a multiple of 3, or a normal
  // count that is neither 0 nor the position count; OutOfMemory when GL cannot hold it.
  Result<MeshHandle> upload(const MeshData& mesh);
  Result<MeshHandle> upload(const DrawItem& item);  // item.tint is ignored: tint is per draw
  // Copies a grid mesh (polder/grid_mesh.hpp: terrain pieces) to the GPU as it is. Grid meshes
  // of one frame that share vertices reach the rasteriser bit-identical there, so their joins
  // have no pixel cracks. Errors as above, and InvalidArgument for a spacing that is not positive.
  Result<MeshHandle> upload(const GridMeshView& mesh);
  // Frees the mesh's GPU memory. An invalid handle is ignored.
  void release(MeshHandle mesh);

  // Starts a frame: viewport = camera size, clear to the style's sky colour (alpha 0) and
  // depth, set the GL state and the style's uniforms. The camera and style hold until endFrame.
  void beginFrame(const Camera& camera, const TerrainStyle& style);
  // Draws an uploaded mesh; `tint` multiplies the shaded colour.
  void draw(MeshHandle mesh, const glm::vec3& tint = glm::vec3(1.0f));
  // Streams a mesh for this frame only through a reused buffer, then draws it with item.tint.
  // The spans need only live until the call returns. Errors as for upload().
  Status drawTransient(const DrawItem& item);
  // Ends the frame and reports any GL error raised since beginFrame.
  Status endFrame();

  // Reads the current read framebuffer at the last frame's size into `image` (resized when
  // its size differs), flipped so row 0 is the top. Waits for drawing to finish.
  Status readPixels(RgbaImage& image);
  // Blocks until every GL command issued so far has finished (timing, external readback).
  void finish();

  RendererStats stats() const;
  // "OpenGL <GL_VERSION> on <GL_RENDERER>", for logs and benchmark reports.
  const std::string& contextDescription() const;

 private:
  struct Impl;
  explicit Renderer(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> m_impl;
};

}  // namespace polder::render
