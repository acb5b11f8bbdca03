// polder::platform_osmesa — an offscreen OpenGL core context rendered by Mesa (llvmpipe) into
// memory: no display, no GPU. Headless rendering (`polder render`, `flyover --headless`,
// image tests) uses it.
//
//   auto context = polder::platform::OsmesaContext::create(1280, 720);
//   auto renderer = polder::render::Renderer::create(&OsmesaContext::getProcAddress);
//
// Threads: OSMesa's current context is per thread. Create, makeCurrent and draw on one thread;
// create() leaves the new context current on the calling thread.
//
// Go through a loader (getProcAddress) for every GL call: calling libOSMesa's own gl* symbols
// breaks once libGL is in the same link.
#pragma once

#include <memory>

#include <polder/result.hpp>

namespace polder::platform {

// An OpenGL entry point; the same type as polder::render::GlProc.
using GlProc = void (*)();

struct OsmesaContextOptions {
  int depthBits = 24;
  int stencilBits = 8;
};

class OsmesaContext {
 public:
  // An OpenGL core context (3.3 asked first, 4.5 if Mesa refuses) drawing into an RGBA8 buffer
  // of width x height, made current on the calling thread. Errors: InvalidArgument for a
  // non-positive size, Environment when Mesa gives no context.
  static Result<std::unique_ptr<OsmesaContext>> create(int width, int height, const OsmesaContextOptions& options = {});
  ~OsmesaContext();
  OsmesaContext(const OsmesaContext&) = delete;
  OsmesaContext& operator=(const OsmesaContext&) = delete;

  // Binds this context and its buffer to the calling thread.
  Status makeCurrent();
  // Reallocates the colour buffer (contents are lost) and makes the context current.
  Status resize(int width, int height);

  int width() const;
  int height() const;
  // The core version asked for that Mesa accepted: 33, or 45 as the fallback (major * 10 +
  // minor). Mesa may grant a newer compatible version (22.3 reports 4.5 when asked for 3.3).
  int glVersion() const;

  // Leaves no OSMesa context current on the calling thread.
  static void clearCurrent();

  // Loader for polder::render::Renderer::create (wraps OSMesaGetProcAddress); works for any
  // OSMesa context current on the calling thread.
  static GlProc getProcAddress(const char* name);

 private:
  struct Impl;
  explicit OsmesaContext(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> m_impl;
};

}  // namespace polder::platform
