// The GLFW window platform: needs an X display (ctest runs under xvfb-run -a). Without one the
// window tests skip, and the no-display path is checked to return an Error.
#include <polder/platform/glfw_window.hpp>
#include <polder/render/renderer.hpp>

#include <chrono>
#include <cstdlib>
#include <optional>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "test_scenes.hpp"

// Sanitizer builds (POLDER_SANITIZE): GLX loads Mesa's DRI driver with dlopen and unloads it at
// glfwTerminate, leaving allocations LeakSanitizer can neither attribute nor suppress by name.
// Leaks in Polder's own code are checked by render_tests (OSMesa), which runs the same renderer.
extern "C" const char* __asan_default_options() { return "detect_leaks=0"; }

namespace polder {
namespace {

using platform::GlfwWindow;
using platform::GlfwWindowOptions;

bool haveDisplay() {
  const char* display = std::getenv("DISPLAY");
  return display != nullptr && *display != '\0';
}

#define POLDER_REQUIRE_DISPLAY() \
  if (!haveDisplay()) GTEST_SKIP() << "DISPLAY is not set: no X server for a window (run under xvfb-run -a)"

GlfwWindowOptions smallWindow() {
  GlfwWindowOptions options;
  options.title = "polder test";
  options.width = 64;
  options.height = 48;
  options.vsync = false;
  return options;
}

// Xvfb (as xvfb-run starts it, without -noreset) resets itself when its last client disconnects,
// which each test does when its last window closes and GLFW terminates; a connection made
// during the reset is refused. Retry briefly instead of failing on the test harness's race.
Result<std::unique_ptr<GlfwWindow>> openWindow() {
  auto window = GlfwWindow::create(smallWindow());
  for (int attempt = 0;
       attempt < 40 && !window.ok() && window.error().message.find("Failed to open display") != std::string::npos;
       ++attempt) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    window = GlfwWindow::create(smallWindow());
  }
  return window;
}

// Sets or unsets an environment variable for one scope.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : m_name(name) {
    if (const char* old = std::getenv(name)) m_old = old;
    if (value) {
      ::setenv(name, value, 1);
    } else {
      ::unsetenv(name);
    }
  }
  ~ScopedEnv() {
    if (m_old) {
      ::setenv(m_name.c_str(), m_old->c_str(), 1);
    } else {
      ::unsetenv(m_name.c_str());
    }
  }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  std::string m_name;
  std::optional<std::string> m_old;
};

TEST(GlfwWindowTest, WithoutADisplayCreateIsAnErrorNotACrash) {
  // No window may be open here: GLFW reads DISPLAY when it initialises.
  const ScopedEnv noDisplay("DISPLAY", nullptr);
  const ScopedEnv noWayland("WAYLAND_DISPLAY", nullptr);
  auto window = GlfwWindow::create(smallWindow());
  ASSERT_FALSE(window.ok());
  EXPECT_EQ(window.error().kind, ErrorKind::Environment);
  EXPECT_NE(window.error().message.find("DISPLAY"), std::string::npos) << window.error().message;
}

TEST(GlfwWindowTest, OpensAWindowAndClearsItToTheSky) {
  POLDER_REQUIRE_DISPLAY();
  auto window = openWindow();
  ASSERT_TRUE(window.ok()) << window.error().message;
  auto renderer = render::Renderer::create(&GlfwWindow::getProcAddress);
  ASSERT_TRUE(renderer.ok()) << renderer.error().message;

  const glm::ivec2 size = (*window)->framebufferSize();
  ASSERT_GT(size.x, 0);
  ASSERT_GT(size.y, 0);
  Camera camera = test::smallCamera();
  camera.widthPx = size.x;
  camera.heightPx = size.y;
  camera.pitchDeg = 20.0;  // up at the empty sky
  const TerrainStyle style;
  (*renderer)->beginFrame(camera, style);
  ASSERT_TRUE((*renderer)->endFrame().ok());
  RgbaImage image;
  ASSERT_TRUE((*renderer)->readPixels(image).ok());
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      // RGB only: the window's visual may have no alpha channel.
      ASSERT_EQ(image.at(x, y)[0], test::toByte(style.skyColour.r));
      ASSERT_EQ(image.at(x, y)[1], test::toByte(style.skyColour.g));
      ASSERT_EQ(image.at(x, y)[2], test::toByte(style.skyColour.b));
    }
  }
  (*window)->swapBuffers();
  (*window)->pollEvents();
  EXPECT_FALSE((*window)->shouldClose());
  EXPECT_FALSE((*window)->input().held(platform::Key::W));
  EXPECT_EQ((*window)->input().mouseDelta, glm::dvec2(0.0));
  (*window)->setShouldClose(true);
  EXPECT_TRUE((*window)->shouldClose());
  renderer->reset();  // before its context goes
}

TEST(GlfwWindowTest, DrawsTerrainIntoTheWindow) {
  POLDER_REQUIRE_DISPLAY();
  auto window = openWindow();
  ASSERT_TRUE(window.ok()) << window.error().message;
  auto renderer = render::Renderer::create(&GlfwWindow::getProcAddress);
  ASSERT_TRUE(renderer.ok()) << renderer.error().message;
  const MeshData plane = test::makeGrid({0.0, 0.0, 0.0}, 1000.0f, 4, [](float, float) { return 0.0f; });
  Camera camera = test::smallCamera();
  const glm::ivec2 size = (*window)->framebufferSize();
  camera.widthPx = size.x;
  camera.heightPx = size.y;
  camera.position = {0.0, 0.0, 200.0};
  camera.pitchDeg = -90.0;
  const TerrainStyle style;
  (*renderer)->beginFrame(camera, style);
  ASSERT_TRUE((*renderer)->drawTransient(drawItemOf(plane)).ok());
  ASSERT_TRUE((*renderer)->endFrame().ok());
  RgbaImage image;
  ASSERT_TRUE((*renderer)->readPixels(image).ok());
  const glm::vec3 expected = shadeTerrain(style, {0.0f, 0.0f, 1.0f}, 0.0f, 200.0f);
  const std::uint8_t* centre = image.at(image.width / 2, image.height / 2);
  EXPECT_NEAR(centre[0], test::toByte(expected.r), 2);
  EXPECT_NEAR(centre[1], test::toByte(expected.g), 2);
  EXPECT_NEAR(centre[2], test::toByte(expected.b), 2);
  (*window)->swapBuffers();
  renderer->reset();
}

TEST(GlfwWindowTest, GlfwStaysInitialisedWhileAnyWindowLives) {
  POLDER_REQUIRE_DISPLAY();
  auto first = openWindow();
  ASSERT_TRUE(first.ok()) << first.error().message;
  auto second = openWindow();
  ASSERT_TRUE(second.ok()) << second.error().message;
  first->reset();  // must not terminate GLFW under the second window
  (*second)->makeCurrent();
  (*second)->pollEvents();
  auto renderer = render::Renderer::create(&GlfwWindow::getProcAddress);
  ASSERT_TRUE(renderer.ok()) << renderer.error().message;
  renderer->reset();
  second->reset();
  // And GLFW comes back for a window after the last one closed.
  auto third = openWindow();
  ASSERT_TRUE(third.ok()) << third.error().message;
}

}  // namespace
}  // namespace polder
