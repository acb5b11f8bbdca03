// Image tests of polder::render under OSMesa: shading against shadeTerrain, the sky/terrain
// mask, camera-relative precision far from the origin, wireframe, the transient stream, and
// errors as values.
#include <polder/platform/osmesa_context.hpp>
#include <polder/render/renderer.hpp>

#include <cmath>
#include <cstring>
#include <memory>
#include <string>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "gl_util.hpp"  // private to polder::render: compile errors and raw GL errors
#include "test_scenes.hpp"

// Sanitizer builds (POLDER_SANITIZE): OSMesa keeps a record per buffer made current for the
// whole process (OSMesaMakeCurrent), which LeakSanitizer would blame on us.
extern "C" const char* __lsan_default_suppressions() { return "leak:libOSMesa.so\n"; }

namespace polder {
namespace {

using platform::OsmesaContext;
using render::Renderer;
using test::isTerrain;
using test::makeGrid;
using test::maxChannelDifference;
using test::smallCamera;
using test::toByte;

render::GlProc osmesaLoader(const char* name) { return OsmesaContext::getProcAddress(name); }

class RendererTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto context = OsmesaContext::create(128, 96);
    ASSERT_TRUE(context.ok()) << context.error().message;
    m_context = std::move(*context);
    auto renderer = Renderer::create(&OsmesaContext::getProcAddress);
    ASSERT_TRUE(renderer.ok()) << renderer.error().message;
    m_renderer = std::move(*renderer);
  }

  // One frame of uploaded meshes, read back.
  RgbaImage renderMesh(const MeshData& mesh, const Camera& camera, const TerrainStyle& style,
                       const glm::vec3& tint = glm::vec3(1.0f)) {
    auto handle = m_renderer->upload(mesh);
    EXPECT_TRUE(handle.ok()) << handle.error().message;
    m_renderer->beginFrame(camera, style);
    m_renderer->draw(*handle, tint);
    EXPECT_TRUE(m_renderer->endFrame().ok());
    RgbaImage image;
    const Status read = m_renderer->readPixels(image);
    EXPECT_TRUE(read.ok()) << read.error().message;
    m_renderer->release(*handle);
    return image;
  }

  // Declared first so it is destroyed last: the renderer needs its context current to die.
  std::unique_ptr<OsmesaContext> m_context;
  std::unique_ptr<Renderer> m_renderer;
};

// Every pixel of a view that sees only a plane must equal shadeTerrain at the ray's hit.
void expectMatchesShadeTerrain(const RgbaImage& image, const Camera& camera, const TerrainStyle& style,
                               const glm::dvec3& planePoint, const glm::dvec3& planeNormal,
                               const std::function<float(const glm::dvec3&)>& heightAt) {
  ASSERT_EQ(image.width, camera.widthPx);
  ASSERT_EQ(image.height, camera.heightPx);
  int worst = 0, mismatches = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const glm::dvec3 ray = camera.pixelRay(x + 0.5, y + 0.5);
      const double t = glm::dot(planePoint - camera.position, planeNormal) / glm::dot(ray, planeNormal);
      ASSERT_GT(t, 0.0) << "the view must see only the plane";
      const glm::dvec3 hit = camera.position + t * ray;
      const glm::vec3 expected = shadeTerrain(style, glm::vec3(planeNormal), heightAt(hit), float(t));
      const std::uint8_t* got = image.at(x, y);
      EXPECT_EQ(got[3], 255) << "pixel " << x << "," << y << " is not terrain";
      for (int c = 0; c < 3; ++c) {
        const int difference = std::abs(int(got[c]) - int(test::toByte(expected[c])));
        worst = std::max(worst, difference);
        mismatches += difference > 2 ? 1 : 0;
      }
    }
  }
  EXPECT_LE(worst, 2) << "largest channel difference to shadeTerrain, in 1/255";
  EXPECT_EQ(mismatches, 0);
}

TEST_F(RendererTest, FlatPlaneSeenFromAboveMatchesShadeTerrain) {
  constexpr float kHeight = 330.0f;
  const MeshData plane = makeGrid({10.0, 20.0, 0.0}, 2000.0f, 8, [](float, float) { return kHeight; });
  Camera camera = smallCamera();
  camera.position = {10.0, 20.0, 1330.0};
  camera.pitchDeg = -90.0;
  TerrainStyle style;
  style.fogDensity = fogDensityForDistance(1500.0f);

  const RgbaImage image = renderMesh(plane, camera, style);
  expectMatchesShadeTerrain(image, camera, style, {0.0, 0.0, kHeight}, {0.0, 0.0, 1.0},
                            [](const glm::dvec3&) { return kHeight; });
}

TEST_F(RendererTest, TiltedPlaneMatchesRampLightingAndFog) {
  // z = 300 + 0.4 x: heights across the view cross several ramp stops, the normal is tilted
  // away from the sun's azimuth, and the distances vary enough for the fog to vary.
  const auto height = [](float x, float) { return 300.0f + 0.4f * x; };
  const MeshData plane = makeGrid({0.0, 0.0, 0.0}, 3000.0f, 12, height);
  Camera camera = smallCamera();
  camera.position = {0.0, -200.0, 900.0};
  camera.yawDeg = 30.0;
  camera.pitchDeg = -60.0;
  TerrainStyle style;
  style.minHeightM = 0.0f;
  style.maxHeightM = 600.0f;
  style.fogDensity = fogDensityForDistance(1200.0f);

  const RgbaImage image = renderMesh(plane, camera, style);
  const glm::dvec3 normal = glm::normalize(glm::dvec3(-0.4, 0.0, 1.0));
  expectMatchesShadeTerrain(image, camera, style, {0.0, 0.0, 300.0}, normal,
                            [](const glm::dvec3& p) { return float(p.z); });
}

TEST_F(RendererTest, HorizonSplitsSkyAboveFromTerrainBelow) {
  const MeshData plane = makeGrid({0.0, 0.0, 0.0}, 1.0e5f, 16, [](float, float) { return 0.0f; });
  Camera camera = smallCamera();
  camera.position = {0.0, 0.0, 10.0};
  camera.yawDeg = 45.0;
  camera.pitchDeg = 0.0;
  TerrainStyle style;

  const RgbaImage image = renderMesh(plane, camera, style);
  for (int y = 0; y < image.height; ++y) {
    int terrain = 0;
    for (int x = 0; x < image.width; ++x) terrain += isTerrain(image, x, y) ? 1 : 0;
    const double fraction = double(terrain) / image.width;
    if (y < image.height / 2 - 1) {
      EXPECT_EQ(fraction, 0.0) << "row " << y << " should be sky";
    }
    if (y > image.height / 2) {
      EXPECT_EQ(fraction, 1.0) << "row " << y << " should be terrain";
    }
  }
  const std::uint8_t* sky = image.at(3, 3);
  EXPECT_EQ(sky[0], toByte(style.skyColour.r));
  EXPECT_EQ(sky[1], toByte(style.skyColour.g));
  EXPECT_EQ(sky[2], toByte(style.skyColour.b));
  EXPECT_EQ(sky[3], 0);
}

TEST_F(RendererTest, TerrainFarFromTheOriginDrawsLikeTerrainAtTheOrigin) {
  // At 1e7 m a float's step is 1 m: positions sent as world floats would visibly snap.
  TerrainStyle style;
  style.maxHeightM = 100.0f;
  style.fogDensity = fogDensityForDistance(800.0f);
  Camera camera = smallCamera();
  camera.yawDeg = 20.0;
  camera.pitchDeg = -25.0;
  const glm::dvec3 eye(37.3, -412.7, 140.9);

  RgbaImage images[2];
  const glm::dvec3 bases[2] = {glm::dvec3(0.0), glm::dvec3(1.0e7, 1.0e7, 0.0)};
  for (int i = 0; i < 2; ++i) {
    const MeshData hills = makeGrid(bases[i], 400.0f, 32, test::hills);
    camera.position = bases[i] + eye;
    images[i] = renderMesh(hills, camera, style);
  }
  EXPECT_LE(maxChannelDifference(images[0], images[1]), 1);

  // The view holds both terrain and sky, so the comparison covers silhouettes too.
  int terrain = 0;
  for (int y = 0; y < images[0].height; ++y)
    for (int x = 0; x < images[0].width; ++x) terrain += isTerrain(images[0], x, y) ? 1 : 0;
  const int total = images[0].width * images[0].height;
  EXPECT_GT(terrain, total / 5);
  EXPECT_LT(terrain, total);
}

// A grid surface drawn as one piece and as four pieces with their own anchors gives the same
// image bit for bit: shared vertices reach the rasteriser identical, so joins leave no
// pixel cracks (and no pixel differs along them).
TEST_F(RendererTest, GridPiecesThatShareVerticesDrawExactlyLikeOneMesh) {
  TerrainStyle style;
  style.maxHeightM = 100.0f;
  const GridSpacing spacing{12.5, 12.5};
  auto height = [](double x, double y) { return test::hills(float(x - 400.0), float(y - 400.0)); };
  Camera camera = smallCamera();
  camera.position = {412.3, -91.7, 180.4};
  camera.yawDeg = 17.0;
  camera.pitchDeg = -28.0;

  const test::GridMeshData whole = test::makeGridMesh(0, 0, 64, 64, spacing, height);
  const test::GridMeshData parts[4] = {
      test::makeGridMesh(0, 0, 29, 37, spacing, height), test::makeGridMesh(29, 0, 64, 37, spacing, height),
      test::makeGridMesh(0, 37, 29, 64, spacing, height), test::makeGridMesh(29, 37, 64, 64, spacing, height)};
  auto draw = [&](std::span<const test::GridMeshData> meshes) {
    std::vector<render::MeshHandle> handles;
    for (const test::GridMeshData& mesh : meshes) {
      auto handle = m_renderer->upload(mesh.view());
      EXPECT_TRUE(handle.ok()) << handle.error().message;
      handles.push_back(*handle);
    }
    m_renderer->beginFrame(camera, style);
    for (const render::MeshHandle handle : handles) m_renderer->draw(handle);
    EXPECT_TRUE(m_renderer->endFrame().ok());
    RgbaImage image;
    EXPECT_TRUE(m_renderer->readPixels(image).ok());
    for (const render::MeshHandle handle : handles) m_renderer->release(handle);
    return image;
  };
  const RgbaImage one = draw(std::span(&whole, 1));
  const RgbaImage four = draw(parts);
  EXPECT_EQ(maxChannelDifference(one, four), 0);
  int terrain = 0;
  for (int y = 0; y < one.height; ++y)
    for (int x = 0; x < one.width; ++x) terrain += isTerrain(one, x, y) ? 1 : 0;
  EXPECT_GT(terrain, one.width * one.height / 3);
}

// Only camera-relative differences reach float: a grid 10^7 m from the world origin draws as
// the same grid near it.
TEST_F(RendererTest, GridMeshesFarFromTheOriginDrawLikeGridsAtTheOrigin) {
  TerrainStyle style;
  style.maxHeightM = 100.0f;
  style.fogDensity = fogDensityForDistance(800.0f);
  const GridSpacing spacing{1.25, 1.25};
  const std::int64_t far = 8000000;  // samples: 10^7 m east and north
  Camera camera = smallCamera();
  camera.yawDeg = 20.0;
  camera.pitchDeg = -25.0;
  const glm::dvec3 eye(37.3, -412.7, 140.9);
  RgbaImage images[2];
  for (int i = 0; i < 2; ++i) {
    const std::int64_t base = i == 0 ? 0 : far;
    const double baseM = double(base) * spacing.x;
    auto height = [baseM](double x, double y) {
      return test::hills(float(x - baseM - 400.0), float(y - baseM - 400.0));
    };
    const test::GridMeshData hills = test::makeGridMesh(base, base, base + 640, base + 640, spacing, height);
    auto handle = m_renderer->upload(hills.view());
    ASSERT_TRUE(handle.ok());
    camera.position = glm::dvec3(baseM + 400.0, baseM + 400.0, 0.0) + eye;
    m_renderer->beginFrame(camera, style);
    m_renderer->draw(*handle);
    ASSERT_TRUE(m_renderer->endFrame().ok());
    ASSERT_TRUE(m_renderer->readPixels(images[i]).ok());
    m_renderer->release(*handle);
  }
  EXPECT_LE(maxChannelDifference(images[0], images[1]), 1);
  int terrain = 0;
  for (int y = 0; y < images[0].height; ++y)
    for (int x = 0; x < images[0].width; ++x) terrain += isTerrain(images[0], x, y) ? 1 : 0;
  EXPECT_GT(terrain, images[0].width * images[0].height / 5);
  EXPECT_LT(terrain, images[0].width * images[0].height);
}

TEST_F(RendererTest, GridUploadsRejectBadIndicesAndSpacing) {
  test::GridMeshData mesh = test::makeGridMesh(0, 0, 2, 2, GridSpacing{1.0, 1.0}, [](double, double) { return 0.0f; });
  mesh.indices.back() = 99;
  auto outOfRange = m_renderer->upload(mesh.view());
  ASSERT_FALSE(outOfRange.ok());
  EXPECT_NE(outOfRange.error().message.find("out of range"), std::string::npos);
  mesh.indices.back() = 0;
  mesh.spacing = GridSpacing{0.0, 1.0};
  EXPECT_FALSE(m_renderer->upload(mesh.view()).ok());
}

TEST_F(RendererTest, WireframeOverlayChangesTerrainPixelsOnly) {
  const MeshData hills = makeGrid({0.0, 0.0, 0.0}, 400.0f, 16, test::hills);
  Camera camera = smallCamera();
  camera.position = {0.0, -300.0, 250.0};
  camera.pitchDeg = -35.0;
  TerrainStyle style;
  style.maxHeightM = 100.0f;

  const RgbaImage plain = renderMesh(hills, camera, style);
  style.wireframe = true;
  const RgbaImage wired = renderMesh(hills, camera, style);

  int changed = 0, terrain = 0, maskChanges = 0;
  for (int y = 0; y < plain.height; ++y) {
    for (int x = 0; x < plain.width; ++x) {
      const std::uint8_t* a = plain.at(x, y);
      const std::uint8_t* b = wired.at(x, y);
      terrain += a[3] == 255 ? 1 : 0;
      maskChanges += a[3] != b[3] ? 1 : 0;
      changed += std::abs(int(a[0]) - int(b[0])) + std::abs(int(a[1]) - int(b[1])) > 16 ? 1 : 0;
    }
  }
  EXPECT_GT(terrain, 1000);
  EXPECT_GT(changed, terrain / 20) << "edges should darken a visible share of the terrain";
  EXPECT_LT(maskChanges, terrain / 50) << "edges may only touch the silhouette";
}

TEST_F(RendererTest, TransientDrawEqualsUploadedDraw) {
  const MeshData hills = makeGrid({500.0, -200.0, 5.0}, 400.0f, 24, test::hills);
  Camera camera = smallCamera();
  camera.position = {500.0, -600.0, 260.0};
  camera.pitchDeg = -30.0;
  TerrainStyle style;
  style.maxHeightM = 100.0f;

  const RgbaImage uploaded = renderMesh(hills, camera, style);
  m_renderer->beginFrame(camera, style);
  ASSERT_TRUE(m_renderer->drawTransient(drawItemOf(hills)).ok());
  ASSERT_TRUE(m_renderer->endFrame().ok());
  RgbaImage streamed;
  ASSERT_TRUE(m_renderer->readPixels(streamed).ok());
  EXPECT_EQ(maxChannelDifference(uploaded, streamed), 0);
}

// A draw's linear part (a rigid instance's rotation and scale) places and shades the
// vertices as if they had been transformed on the CPU.
TEST_F(RendererTest, TransientDrawAppliesItsLinearPart) {
  const MeshData hills = makeGrid({500.0, -200.0, 5.0}, 200.0f, 24, test::hills);
  glm::mat3 linear = glm::mat3(glm::rotate(glm::mat4(1.0f), 0.6f, glm::normalize(glm::vec3(0.2f, 0.3f, 1.0f))));
  linear = linear * glm::mat3(glm::scale(glm::mat4(1.0f), glm::vec3(1.5f, 0.8f, 1.2f)));
  MeshData moved = hills;
  const glm::mat3 normalMatrix = glm::transpose(glm::inverse(linear));
  for (std::size_t i = 0; i < moved.positions.size(); ++i) {
    moved.positions[i] = linear * hills.positions[i];
    if (!moved.normals.empty()) moved.normals[i] = glm::normalize(normalMatrix * hills.normals[i]);
  }
  Camera camera = smallCamera();
  camera.position = {500.0, -700.0, 300.0};
  camera.pitchDeg = -30.0;
  TerrainStyle style;
  style.maxHeightM = 100.0f;
  auto render = [&](const DrawItem& item) {
    m_renderer->beginFrame(camera, style);
    EXPECT_TRUE(m_renderer->drawTransient(item).ok());
    EXPECT_TRUE(m_renderer->endFrame().ok());
    RgbaImage image;
    EXPECT_TRUE(m_renderer->readPixels(image).ok());
    return image;
  };
  const RgbaImage onTheCpu = render(drawItemOf(moved));
  DrawItem placed = drawItemOf(hills);
  placed.linear = linear;
  const RgbaImage byMatrix = render(placed);
  const RgbaImage unmoved = render(drawItemOf(hills));
  int differing = 0, differingFromUnmoved = 0;
  for (std::size_t i = 0; i < byMatrix.pixels.size(); i += 4) {
    for (int c = 0; c < 3; ++c) {
      if (std::abs(int(byMatrix.pixels[i + c]) - int(onTheCpu.pixels[i + c])) > 3) {
        ++differing;
        break;
      }
    }
    differingFromUnmoved += byMatrix.pixels[i] != unmoved.pixels[i];
  }
  const int pixels = int(byMatrix.pixels.size() / 4);
  EXPECT_LT(differing, pixels / 200) << "rounding may only touch a few edge pixels";
  EXPECT_GT(differingFromUnmoved, pixels / 20) << "the linear part must move the mesh";
}

TEST_F(RendererTest, TransientStreamStopsGrowingInSteadyState) {
  // A small first stream, so the first frame has to grow it.
  render::RendererOptions options;
  options.transientVertexCapacity = 1024;
  options.transientIndexCapacity = 1024;
  auto created = Renderer::create(osmesaLoader, options);
  ASSERT_TRUE(created.ok()) << created.error().message;
  Renderer& renderer = **created;

  const MeshData near = makeGrid({0.0, 0.0, 0.0}, 200.0f, 32, test::hills);          // 1089 vertices
  const MeshData far = makeGrid({400.0, 0.0, 0.0}, 200.0f, 32, test::hills, false);  // normals computed
  Camera camera = smallCamera();
  camera.position = {200.0, -500.0, 300.0};
  camera.pitchDeg = -30.0;
  const TerrainStyle style;

  RgbaImage first, later;
  std::size_t growthsAfterFirst = 0;
  for (int frame = 0; frame < 4; ++frame) {
    renderer.beginFrame(camera, style);
    ASSERT_TRUE(renderer.drawTransient(drawItemOf(near)).ok());
    ASSERT_TRUE(renderer.drawTransient(drawItemOf(far)).ok());
    ASSERT_TRUE(renderer.endFrame().ok());
    const render::RendererStats stats = renderer.stats();
    EXPECT_EQ(stats.drawCalls, 2u);
    EXPECT_EQ(stats.triangles, near.triangleCount() + far.triangleCount());
    if (frame == 0) {
      EXPECT_GT(stats.transientGrowths, 0u);
      growthsAfterFirst = stats.transientGrowths;
      ASSERT_TRUE(renderer.readPixels(first).ok());
    } else {
      EXPECT_EQ(stats.transientGrowths, growthsAfterFirst) << "frame " << frame << " grew the stream";
    }
  }
  ASSERT_TRUE(renderer.readPixels(later).ok());
  EXPECT_EQ(maxChannelDifference(first, later), 0);
}

TEST_F(RendererTest, TintMultipliesTheShadedColour) {
  const MeshData hills = makeGrid({0.0, 0.0, 0.0}, 400.0f, 16, test::hills);
  Camera camera = smallCamera();
  camera.position = {0.0, 0.0, 500.0};
  camera.pitchDeg = -90.0;
  const TerrainStyle style;
  const RgbaImage plain = renderMesh(hills, camera, style);
  const RgbaImage red = renderMesh(hills, camera, style, {1.0f, 0.0f, 0.0f});
  for (int y = 0; y < plain.height; ++y) {
    for (int x = 0; x < plain.width; ++x) {
      ASSERT_EQ(red.at(x, y)[0], plain.at(x, y)[0]);
      ASSERT_EQ(red.at(x, y)[1], 0);
      ASSERT_EQ(red.at(x, y)[2], 0);
    }
  }
}

TEST_F(RendererTest, ReleasedMeshesFreeTheirBytesAndSlotsAreReused) {
  const MeshData a = makeGrid({0.0, 0.0, 0.0}, 100.0f, 4, test::hills);
  auto first = m_renderer->upload(a);
  ASSERT_TRUE(first.ok());
  EXPECT_EQ(m_renderer->stats().meshCount, 1u);
  EXPECT_EQ(m_renderer->stats().meshBytes, a.positions.size() * 24 + a.indices.size() * 4);
  m_renderer->release(*first);
  EXPECT_EQ(m_renderer->stats().meshCount, 0u);
  EXPECT_EQ(m_renderer->stats().meshBytes, 0u);
  auto second = m_renderer->upload(a);
  ASSERT_TRUE(second.ok());
  EXPECT_EQ(second->slot, first->slot);
  EXPECT_NE(second->generation, first->generation) << "a stale handle must not alias the new mesh";
  m_renderer->release(render::MeshHandle{});  // no mesh: ignored
}

TEST_F(RendererTest, MalformedMeshesAreErrorsNotCrashes) {
  MeshData mesh = makeGrid({0.0, 0.0, 0.0}, 100.0f, 2, test::hills);
  MeshData outOfRange = mesh;
  outOfRange.indices[4] = 9999;
  MeshData partialTriangle = mesh;
  partialTriangle.indices.pop_back();
  MeshData fewNormals = mesh;
  fewNormals.normals.pop_back();
  for (const MeshData* bad : {&outOfRange, &partialTriangle, &fewNormals}) {
    auto handle = m_renderer->upload(*bad);
    ASSERT_FALSE(handle.ok());
    EXPECT_EQ(handle.error().kind, ErrorKind::InvalidArgument);
  }
  m_renderer->beginFrame(smallCamera(), TerrainStyle{});
  const Status status = m_renderer->drawTransient(drawItemOf(outOfRange));
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.error().message.find("9999"), std::string::npos) << status.error().message;
  EXPECT_TRUE(m_renderer->endFrame().ok());
}

TEST_F(RendererTest, GlErrorsInAFrameAreReportedByEndFrame) {
  GladGLContext gl{};
  ASSERT_NE(gladLoadGLContext(&gl, OsmesaContext::getProcAddress), 0);
  m_renderer->beginFrame(smallCamera(), TerrainStyle{});
  gl.Enable(0x7FFF);  // not a capability: GL_INVALID_ENUM
  const Status status = m_renderer->endFrame();
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.error().message.find("GL_INVALID_ENUM"), std::string::npos) << status.error().message;
  m_renderer->beginFrame(smallCamera(), TerrainStyle{});
  EXPECT_TRUE(m_renderer->endFrame().ok()) << "errors are cleared once reported";
}

TEST_F(RendererTest, ShaderCompileAndLinkErrorsCarryTheDriversLog) {
  GladGLContext gl{};
  ASSERT_NE(gladLoadGLContext(&gl, OsmesaContext::getProcAddress), 0);
  constexpr const char* kVertex = "#version 330 core\nvoid main() { gl_Position = vec4(0.0); }\n";
  constexpr const char* kBroken = "#version 330 core\nout vec4 c;\nvoid main() { c = vec4(undeclared); }\n";
  auto compiled = render::detail::compileProgram(gl, kVertex, kBroken, "broken");
  ASSERT_FALSE(compiled.ok());
  EXPECT_EQ(compiled.error().kind, ErrorKind::Environment);
  EXPECT_NE(compiled.error().message.find("fragment shader of broken failed to compile"), std::string::npos);
  EXPECT_NE(compiled.error().message.find("undeclared"), std::string::npos) << compiled.error().message;

  // Compiles, but a program without main() cannot link.
  constexpr const char* kNoMain = "#version 330 core\nvoid notMain() { gl_Position = vec4(0.0); }\n";
  constexpr const char* kFragment = "#version 330 core\nout vec4 c;\nvoid main() { c = vec4(1.0); }\n";
  auto linked = render::detail::compileProgram(gl, kNoMain, kFragment, "mainless");
  ASSERT_FALSE(linked.ok());
  EXPECT_NE(linked.error().message.find("failed to link"), std::string::npos) << linked.error().message;
}

TEST_F(RendererTest, ReadPixelsBeforeAnyFrameIsAnError) {
  RgbaImage image;
  const Status status = m_renderer->readPixels(image);
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.error().kind, ErrorKind::InvalidArgument);
}

TEST_F(RendererTest, ResizedContextReadsBackAtTheNewSize) {
  ASSERT_TRUE(m_context->resize(64, 48).ok());
  EXPECT_EQ(m_context->width(), 64);
  Camera camera = smallCamera();
  camera.widthPx = 64;
  camera.heightPx = 48;
  const MeshData plane = makeGrid({0.0, 0.0, 0.0}, 1000.0f, 2, [](float, float) { return 0.0f; });
  camera.position = {0.0, 0.0, 100.0};
  camera.pitchDeg = -90.0;
  const RgbaImage image = renderMesh(plane, camera, TerrainStyle{});
  ASSERT_EQ(image.width, 64);
  ASSERT_EQ(image.height, 48);
  EXPECT_TRUE(isTerrain(image, 0, 0) && isTerrain(image, 63, 47));
}

// --- create() failures: each an Error value, never a crash -----------------------------------

TEST(RendererCreate, EmptyLoaderIsInvalidArgument) {
  auto renderer = Renderer::create(render::GlProcLoader{});
  ASSERT_FALSE(renderer.ok());
  EXPECT_EQ(renderer.error().kind, ErrorKind::InvalidArgument);
}

TEST(RendererCreate, LoaderThatFindsNothingIsAnError) {
  auto context = OsmesaContext::create(16, 16);
  ASSERT_TRUE(context.ok());
  auto renderer = Renderer::create([](const char*) -> render::GlProc { return nullptr; });
  ASSERT_FALSE(renderer.ok());
  EXPECT_EQ(renderer.error().kind, ErrorKind::Environment);
}

TEST(RendererCreate, NoCurrentContextIsAnError) {
  OsmesaContext::clearCurrent();
  auto renderer = Renderer::create(osmesaLoader);
  ASSERT_FALSE(renderer.ok());
  EXPECT_EQ(renderer.error().kind, ErrorKind::Environment);
  EXPECT_NE(renderer.error().message.find("no OpenGL context"), std::string::npos) << renderer.error().message;
}

TEST(RendererCreate, MissingEntryPointIsNamed) {
  auto context = OsmesaContext::create(16, 16);
  ASSERT_TRUE(context.ok());
  auto renderer = Renderer::create([](const char* name) -> render::GlProc {
    return std::strcmp(name, "glDrawElementsBaseVertex") == 0 ? nullptr : OsmesaContext::getProcAddress(name);
  });
  ASSERT_FALSE(renderer.ok());
  EXPECT_NE(renderer.error().message.find("glDrawElementsBaseVertex"), std::string::npos) << renderer.error().message;
}

const GLubyte* oldGetString(GLenum name) {
  return reinterpret_cast<const GLubyte*>(name == GL_VERSION ? "2.1 Pretend" : "");
}

TEST(RendererCreate, ContextOlderThan33IsAnError) {
  auto context = OsmesaContext::create(16, 16);
  ASSERT_TRUE(context.ok());
  auto renderer = Renderer::create([](const char* name) -> render::GlProc {
    if (std::strcmp(name, "glGetString") == 0) return reinterpret_cast<render::GlProc>(&oldGetString);
    return OsmesaContext::getProcAddress(name);
  });
  ASSERT_FALSE(renderer.ok());
  EXPECT_NE(renderer.error().message.find("2.1 Pretend"), std::string::npos) << renderer.error().message;
}

TEST(OsmesaContextTest, EmptySizeIsInvalidArgument) {
  auto context = OsmesaContext::create(0, 10);
  ASSERT_FALSE(context.ok());
  EXPECT_EQ(context.error().kind, ErrorKind::InvalidArgument);
}

TEST(OsmesaContextTest, GrantsACoreContextOfAtLeast33) {
  auto context = OsmesaContext::create(8, 8);
  ASSERT_TRUE(context.ok()) << context.error().message;
  EXPECT_GE((*context)->glVersion(), 33);
  auto renderer = Renderer::create(&OsmesaContext::getProcAddress);
  ASSERT_TRUE(renderer.ok()) << renderer.error().message;
  EXPECT_NE((*renderer)->contextDescription().find("OpenGL"), std::string::npos);
}

}  // namespace
}  // namespace polder
