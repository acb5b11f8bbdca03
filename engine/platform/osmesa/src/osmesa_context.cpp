#include <polder/platform/osmesa_context.hpp>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <GL/osmesa.h>

namespace polder::platform {

namespace {

// Mesa 22 grants core 4.5 but refuses 4.6; 3.3 is what Polder needs, so ask that first.
constexpr std::array<std::array<int, 2>, 2> kVersions = {{{3, 3}, {4, 5}}};

OSMesaContext createCoreContext(const OsmesaContextOptions& options, int major, int minor) {
  const int attributes[] = {OSMESA_FORMAT,
                            OSMESA_RGBA,
                            OSMESA_DEPTH_BITS,
                            options.depthBits,
                            OSMESA_STENCIL_BITS,
                            options.stencilBits,
                            OSMESA_ACCUM_BITS,
                            0,
                            OSMESA_PROFILE,
                            OSMESA_CORE_PROFILE,
                            OSMESA_CONTEXT_MAJOR_VERSION,
                            major,
                            OSMESA_CONTEXT_MINOR_VERSION,
                            minor,
                            0};
  return OSMesaCreateContextAttribs(attributes, nullptr);
}

}  // namespace

struct OsmesaContext::Impl {
  OSMesaContext context = nullptr;
  std::vector<std::uint8_t> buffer;  // RGBA8, bottom row first (OSMesa's default)
  int width = 0;
  int height = 0;
  int version = 0;

  ~Impl() {
    if (!context) return;
    // Unbind first, so the thread does not keep a dangling current context.
    if (OSMesaGetCurrentContext() == context) OSMesaMakeCurrent(nullptr, nullptr, 0, 0, 0);
    OSMesaDestroyContext(context);
  }
};

OsmesaContext::OsmesaContext(std::unique_ptr<Impl> impl) : m_impl(std::move(impl)) {}

OsmesaContext::~OsmesaContext() = default;

Result<std::unique_ptr<OsmesaContext>> OsmesaContext::create(int width, int height,
                                                             const OsmesaContextOptions& options) {
  if (width <= 0 || height <= 0) {
    return makeError(ErrorKind::InvalidArgument, "OsmesaContext::create: size " + std::to_string(width) + "x" +
                                                     std::to_string(height) + " is empty");
  }
  auto impl = std::make_unique<Impl>();
  for (const auto& [major, minor] : kVersions) {
    impl->context = createCoreContext(options, major, minor);
    if (impl->context) {
      impl->version = major * 10 + minor;
      break;
    }
  }
  if (!impl->context) {
    return makeError(ErrorKind::Environment,
                     "OsmesaContext::create: Mesa could not create an OpenGL 3.3 or 4.5 core context");
  }
  std::unique_ptr<OsmesaContext> context(new OsmesaContext(std::move(impl)));
  if (Status status = context->resize(width, height); !status) return status.error();
  return context;
}

Status OsmesaContext::makeCurrent() {
  Impl& c = *m_impl;
  if (!OSMesaMakeCurrent(c.context, c.buffer.data(), GL_UNSIGNED_BYTE, c.width, c.height)) {
    return makeError(ErrorKind::Environment, "OsmesaContext: OSMesaMakeCurrent failed for a " +
                                                 std::to_string(c.width) + "x" + std::to_string(c.height) + " buffer");
  }
  return {};
}

Status OsmesaContext::resize(int width, int height) {
  if (width <= 0 || height <= 0) {
    return makeError(ErrorKind::InvalidArgument, "OsmesaContext::resize: size " + std::to_string(width) + "x" +
                                                     std::to_string(height) + " is empty");
  }
  int maxSize[2] = {0, 0};
  Impl& c = *m_impl;
  c.buffer.assign(std::size_t(width) * std::size_t(height) * 4, 0);
  c.width = width;
  c.height = height;
  if (Status status = makeCurrent(); !status) return status;
  OSMesaGetIntegerv(OSMESA_MAX_WIDTH, &maxSize[0]);
  OSMesaGetIntegerv(OSMESA_MAX_HEIGHT, &maxSize[1]);
  if ((maxSize[0] > 0 && width > maxSize[0]) || (maxSize[1] > 0 && height > maxSize[1])) {
    return makeError(ErrorKind::InvalidArgument, "OsmesaContext: " + std::to_string(width) + "x" +
                                                     std::to_string(height) + " exceeds Mesa's limit of " +
                                                     std::to_string(maxSize[0]) + "x" + std::to_string(maxSize[1]));
  }
  return {};
}

int OsmesaContext::width() const { return m_impl->width; }
int OsmesaContext::height() const { return m_impl->height; }
int OsmesaContext::glVersion() const { return m_impl->version; }

void OsmesaContext::clearCurrent() { OSMesaMakeCurrent(nullptr, nullptr, 0, 0, 0); }

GlProc OsmesaContext::getProcAddress(const char* name) { return OSMesaGetProcAddress(name); }

}  // namespace polder::platform
