#include <polder/platform/glfw_window.hpp>

#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <utility>

#define GLFW_INCLUDE_NONE  // GL comes through the renderer's loader, never GLFW's headers
#include <GLFW/glfw3.h>

namespace polder::platform {

namespace {

// GLFW's state is process-global, so its init/terminate count is too: the one piece of global
// state here, mirroring GLFW's own. GLFW is main-thread-only; the mutex only guards misuse.
struct GlfwLibrary {
  std::mutex mutex;
  int users = 0;
};

GlfwLibrary& glfwLibrary() {
  static GlfwLibrary library;
  return library;
}

// GLFW's last error on this thread, cleared. glfwGetError is used instead of an error
// callback: a callback is process-wide and would replace a host program's own.
std::string takeGlfwError() {
  const char* description = nullptr;
  const int code = glfwGetError(&description);
  if (code == GLFW_NO_ERROR) return "no details from GLFW";
  char codeText[16];
  std::snprintf(codeText, sizeof codeText, "0x%05X", unsigned(code));
  return std::string(description ? description : "unknown error") + " (GLFW error " + codeText + ")";
}

Status acquireGlfw() {
  GlfwLibrary& library = glfwLibrary();
  std::lock_guard lock(library.mutex);
  if (library.users == 0) {
    glfwGetError(nullptr);  // drop stale errors so the message below is about this init
    if (glfwInit() != GLFW_TRUE) {
      std::string message = "GLFW could not initialise: " + takeGlfwError();
      const char* display = std::getenv("DISPLAY");
      if (display == nullptr || *display == '\0') message += "; DISPLAY is not set (run under xvfb-run -a)";
      return makeError(ErrorKind::Environment, std::move(message));
    }
  }
  ++library.users;
  return {};
}

void releaseGlfw() {
  GlfwLibrary& library = glfwLibrary();
  std::lock_guard lock(library.mutex);
  if (--library.users == 0) glfwTerminate();
}

constexpr std::array<int, std::size_t(Key::Count)> kGlfwKeys = {
    GLFW_KEY_W,          GLFW_KEY_A,           GLFW_KEY_S,     GLFW_KEY_D,     GLFW_KEY_Q,
    GLFW_KEY_E,          GLFW_KEY_UP,          GLFW_KEY_DOWN,  GLFW_KEY_LEFT,  GLFW_KEY_RIGHT,
    GLFW_KEY_LEFT_SHIFT, GLFW_KEY_RIGHT_SHIFT, GLFW_KEY_SPACE, GLFW_KEY_ESCAPE};

}  // namespace

struct GlfwWindow::Impl {
  GLFWwindow* window = nullptr;
  bool haveCursor = false;  // false until the first poll (and after capture changes): no jump
  glm::dvec2 lastCursor{0.0};
  double scroll = 0.0;  // accumulated by the callback between polls

  ~Impl() {
    if (!window) return;
    glfwDestroyWindow(window);
    releaseGlfw();
  }
};

GlfwWindow::GlfwWindow(std::unique_ptr<Impl> impl) : m_impl(std::move(impl)) {}

GlfwWindow::~GlfwWindow() = default;

Result<std::unique_ptr<GlfwWindow>> GlfwWindow::create(const GlfwWindowOptions& options) {
  if (options.width <= 0 || options.height <= 0) {
    return makeError(ErrorKind::InvalidArgument, "GlfwWindow::create: size " + std::to_string(options.width) + "x" +
                                                     std::to_string(options.height) + " is empty");
  }
  if (Status status = acquireGlfw(); !status) return status.error();

  glfwDefaultWindowHints();
  glfwWindowHint(GLFW_CLIENT_API, GLFW_OPENGL_API);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_DEPTH_BITS, 24);
  glfwWindowHint(GLFW_VISIBLE, options.visible ? GLFW_TRUE : GLFW_FALSE);
  glfwWindowHint(GLFW_RESIZABLE, options.resizable ? GLFW_TRUE : GLFW_FALSE);
  GLFWwindow* window = glfwCreateWindow(options.width, options.height, options.title.c_str(), nullptr, nullptr);
  if (!window) {
    std::string message = "GlfwWindow::create: no OpenGL 3.3 core window: " + takeGlfwError();
    releaseGlfw();
    return makeError(ErrorKind::Environment, std::move(message));
  }

  auto impl = std::make_unique<Impl>();
  impl->window = window;  // from here on, Impl's destructor closes the window and releases GLFW
  glfwSetWindowUserPointer(window, impl.get());
  glfwSetScrollCallback(
      window, [](GLFWwindow* w, double, double dy) { static_cast<Impl*>(glfwGetWindowUserPointer(w))->scroll += dy; });
  glfwMakeContextCurrent(window);
  glfwSwapInterval(options.vsync ? 1 : 0);
  return std::unique_ptr<GlfwWindow>(new GlfwWindow(std::move(impl)));
}

void GlfwWindow::makeCurrent() { glfwMakeContextCurrent(m_impl->window); }

void GlfwWindow::swapBuffers() { glfwSwapBuffers(m_impl->window); }

void GlfwWindow::pollEvents() {
  Impl& w = *m_impl;
  glfwPollEvents();
  for (std::size_t i = 0; i < kGlfwKeys.size(); ++i) {
    m_input.keys[i] = glfwGetKey(w.window, kGlfwKeys[i]) == GLFW_PRESS;
  }
  m_input.leftButton = glfwGetMouseButton(w.window, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
  m_input.rightButton = glfwGetMouseButton(w.window, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
  glm::dvec2 cursor;
  glfwGetCursorPos(w.window, &cursor.x, &cursor.y);
  m_input.mouseDelta = w.haveCursor ? cursor - w.lastCursor : glm::dvec2(0.0);
  w.lastCursor = cursor;
  w.haveCursor = true;
  m_input.scrollDelta = std::exchange(w.scroll, 0.0);
}

bool GlfwWindow::shouldClose() const { return glfwWindowShouldClose(m_impl->window) == GLFW_TRUE; }

void GlfwWindow::setShouldClose(bool close) {
  glfwSetWindowShouldClose(m_impl->window, close ? GLFW_TRUE : GLFW_FALSE);
}

void GlfwWindow::setTitle(const std::string& title) { glfwSetWindowTitle(m_impl->window, title.c_str()); }

void GlfwWindow::setMouseCaptured(bool captured) {
  GLFWwindow* window = m_impl->window;
  glfwSetInputMode(window, GLFW_CURSOR, captured ? GLFW_CURSOR_DISABLED : GLFW_CURSOR_NORMAL);
  if (glfwRawMouseMotionSupported()) glfwSetInputMode(window, GLFW_RAW_MOUSE_MOTION, captured ? GLFW_TRUE : GLFW_FALSE);
  m_impl->haveCursor = false;  // the cursor jumps when its mode changes
}

glm::ivec2 GlfwWindow::framebufferSize() const {
  glm::ivec2 size(0);
  glfwGetFramebufferSize(m_impl->window, &size.x, &size.y);
  return size;
}

GlProc GlfwWindow::getProcAddress(const char* name) { return glfwGetProcAddress(name); }

}  // namespace polder::platform
