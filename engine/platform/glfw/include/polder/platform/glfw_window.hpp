// polder::platform_glfw — a desktop window with an OpenGL 3.3 core context, for the flyover.
//
//   auto window = polder::platform::GlfwWindow::create({.title = "Polder"});
//   auto renderer = polder::render::Renderer::create(&GlfwWindow::getProcAddress);
//   while (!window->shouldClose()) { window->pollEvents(); ...draw...; window->swapBuffers(); }
//
// Threads: GLFW is process-global and main-thread-only. Create, poll and destroy every
// GlfwWindow on the main thread. GLFW is initialised with the first live GlfwWindow and
// terminated with the last (a reference count), so windows may come and go; a host that uses
// GLFW itself must not call glfwTerminate while a GlfwWindow lives.
//
// Needs a display: on a machine without one (no $DISPLAY), create() returns an Error
// (kind Environment) carrying GLFW's message. Tests run under `xvfb-run -a`.
#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <string>

#include <glm/glm.hpp>

#include <polder/result.hpp>

namespace polder::platform {

// An OpenGL entry point; the same type as polder::render::GlProc.
using GlProc = void (*)();

struct GlfwWindowOptions {
  std::string title = "Polder";
  int width = 1280;  // window size in screen coordinates
  int height = 720;
  bool visible = true;  // false: a hidden window (tests, offscreen use of the context)
  bool vsync = true;
  bool resizable = true;
};

// The keys the flyover reads.
enum class Key : std::size_t { W, A, S, D, Q, E, Up, Down, Left, Right, LeftShift, RightShift, Space, Escape, Count };

// What the user did since the previous pollEvents().
struct InputState {
  std::array<bool, std::size_t(Key::Count)> keys{};  // held at the last poll
  glm::dvec2 mouseDelta{0.0};                        // cursor movement in screen coordinates, +y downwards
  double scrollDelta = 0.0;                          // wheel steps, + away from the user
  bool leftButton = false;                           // held at the last poll
  bool rightButton = false;

  bool held(Key key) const { return keys[std::size_t(key)]; }
};

class GlfwWindow {
 public:
  // Opens the window and makes its context current on the calling (main) thread.
  static Result<std::unique_ptr<GlfwWindow>> create(const GlfwWindowOptions& options = {});
  ~GlfwWindow();
  GlfwWindow(const GlfwWindow&) = delete;
  GlfwWindow& operator=(const GlfwWindow&) = delete;

  void makeCurrent();
  void swapBuffers();
  // Processes window events and refreshes input(); call once per frame.
  void pollEvents();
  const InputState& input() const { return m_input; }

  bool shouldClose() const;
  void setShouldClose(bool close);
  void setTitle(const std::string& title);
  // Hides and captures the cursor so mouse deltas are unbounded (flight look).
  void setMouseCaptured(bool captured);

  // Drawable size in pixels (differs from the window size on high-DPI screens): use it for
  // Camera::widthPx/heightPx.
  glm::ivec2 framebufferSize() const;

  // Loader for polder::render::Renderer::create (wraps glfwGetProcAddress); valid while a
  // GLFW context is current on the calling thread.
  static GlProc getProcAddress(const char* name);

 private:
  struct Impl;
  explicit GlfwWindow(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> m_impl;
  InputState m_input;
};

}  // namespace polder::platform
