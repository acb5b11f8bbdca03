// readMesh on generated OBJ and PLY files: every encoding and attribute, welding, baking.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include <polder/image.hpp>
#include <polder/mesh_io/mesh_file.hpp>
#include <polder/terrain/image_writer.hpp>

#include "mesh_test_files.hpp"
#include "test_support.hpp"

namespace polder::mesh_io {
namespace {

using test::PlyContent;
using test::PlyEncoding;
using test::ScratchDir;

const PlyEncoding kAllEncodings[] = {PlyEncoding::Ascii, PlyEncoding::BinaryLittleEndian, PlyEncoding::BinaryBigEndian};

std::string encodingName(PlyEncoding encoding) { return test::plyFormatName(encoding); }

using test::readMeshOk;

// A unit square (a quad) and a triangle over its first three corners, reversed, plus an
// unreferenced fifth vertex: uchar colours and texture coordinates named u/v or s/t.
PlyContent squareWithUcharColours(const std::string& uName, const std::string& vName) {
  PlyContent content;
  content.vertexProperties = {{"float", "x"},     {"float", "y"},    {"float", "z"},   {"uchar", "red"},
                              {"uchar", "green"}, {"uchar", "blue"}, {"float", uName}, {"float", vName}};
  content.vertices = {{0.0, 0.0, 0.5, 255, 0, 0, 0.0, 0.0},
                      {1.5, 0.0, 0.5, 0, 255, 0, 1.0, 0.0},
                      {1.5, 2.25, 0.5, 0, 0, 255, 1.0, 1.0},
                      {0.0, 2.25, 0.5, 10, 20, 30, 0.0, 1.0},
                      {-4.0, 8.0, 16.0, 1, 2, 3, 0.25, 0.75}};
  content.faces = {{0, 1, 2, 3}, {2, 1, 0}};
  return content;
}

void expectSquare(const mesh::TriangleMesh& mesh) {
  ASSERT_EQ(mesh.vertexCount(), 5u);
  const std::vector<glm::vec3> positions = {
      {0.0f, 0.0f, 0.5f}, {1.5f, 0.0f, 0.5f}, {1.5f, 2.25f, 0.5f}, {0.0f, 2.25f, 0.5f}, {-4.0f, 8.0f, 16.0f}};
  EXPECT_EQ(mesh.positions, positions);
  // The quad is split along 0-2; the reversed triangle is kept (it shares no vertex pair
  // with a weld, so it is not degenerate).
  EXPECT_EQ(mesh.indices, (std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3, 2, 1, 0}));
  ASSERT_TRUE(mesh.hasColours());
  EXPECT_EQ(mesh.colours[0], glm::vec4(1.0f, 0.0f, 0.0f, 1.0f));
  EXPECT_EQ(mesh.colours[1], glm::vec4(0.0f, 1.0f, 0.0f, 1.0f));
  EXPECT_EQ(mesh.colours[2], glm::vec4(0.0f, 0.0f, 1.0f, 1.0f));
  EXPECT_FLOAT_EQ(mesh.colours[3].r, 10.0f / 255.0f);
  EXPECT_FLOAT_EQ(mesh.colours[3].g, 20.0f / 255.0f);
  EXPECT_FLOAT_EQ(mesh.colours[3].b, 30.0f / 255.0f);
  EXPECT_EQ(mesh.colours[3].a, 1.0f);
  const std::vector<glm::vec2> uvs = {{0.0f, 0.0f}, {1.0f, 0.0f}, {1.0f, 1.0f}, {0.0f, 1.0f}, {0.25f, 0.75f}};
  EXPECT_EQ(mesh.uvs, uvs);
  // No normals in the file: computed. Vertex 3 only touches the +Z quad half.
  ASSERT_TRUE(mesh.hasNormals());
  EXPECT_EQ(mesh.normals[3], glm::vec3(0.0f, 0.0f, 1.0f));
  EXPECT_EQ(mesh.normals[4], glm::vec3(0.0f, 0.0f, 1.0f));  // unreferenced: +Z by definition
}

TEST(ReadPly, UcharColoursAndUvInEveryEncoding) {
  ScratchDir dir;
  for (PlyEncoding encoding : kAllEncodings) {
    SCOPED_TRACE(encodingName(encoding));
    const auto file = dir.file("square_" + encodingName(encoding) + ".ply");
    test::writeFile(file, test::plyFile(squareWithUcharColours("u", "v"), encoding));
    expectSquare(readMeshOk(file));
  }
}

TEST(ReadPly, TextureCoordinateNames) {
  ScratchDir dir;
  for (const auto& [u, v] : {std::pair{"s", "t"}, std::pair{"texture_u", "texture_v"}, std::pair{"u", "v"}}) {
    for (PlyEncoding encoding : kAllEncodings) {
      SCOPED_TRACE(encodingName(encoding) + " " + u);
      const auto file = dir.file(std::string("names_") + u + "_" + encodingName(encoding) + ".ply");
      test::writeFile(file, test::plyFile(squareWithUcharColours(u, v), encoding));
      expectSquare(readMeshOk(file));
    }
  }
}

TEST(ReadPly, FloatColoursWithAlphaAndNormals) {
  PlyContent content;
  content.vertexProperties = {{"float", "x"},    {"float", "y"},     {"float", "z"},   {"float", "nx"},
                              {"float", "ny"},   {"float", "nz"},    {"float", "red"}, {"float", "green"},
                              {"float", "blue"}, {"float", "alpha"}, {"float", "s"},   {"float", "t"}};
  content.vertices = {{0, 0, 0, 0, 0, 1, 0.25, 0.5, 0.75, 0.125, 0.5, 0.5},
                      {1, 0, 0, 0, 0, 1, 0.1, 0.2, 0.3, 0.4, 0.75, 0.5},
                      {1, 1, 0, 0, 0, 1, 1, 1, 1, 1, 0.75, 0.625},
                      {0, 1, 0, 0.6, 0, 0.8, 0, 0, 0, 0, 0.5, 0.625}};
  content.faces = {{0, 1, 2}, {0, 2, 3}};
  ScratchDir dir;
  for (PlyEncoding encoding : kAllEncodings) {
    SCOPED_TRACE(encodingName(encoding));
    const auto file = dir.file("float_colours_" + encodingName(encoding) + ".ply");
    test::writeFile(file, test::plyFile(content, encoding));
    const mesh::TriangleMesh mesh = readMeshOk(file);
    ASSERT_EQ(mesh.vertexCount(), 4u);
    EXPECT_EQ(mesh.indices, (std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3}));
    EXPECT_EQ(mesh.colours[0], glm::vec4(0.25f, 0.5f, 0.75f, 0.125f));
    EXPECT_EQ(mesh.colours[1], glm::vec4(0.1f, 0.2f, 0.3f, 0.4f));
    EXPECT_EQ(mesh.colours[3], glm::vec4(0.0f));
    EXPECT_EQ(mesh.uvs[2], glm::vec2(0.75f, 0.625f));
    EXPECT_EQ(mesh.normals[0], glm::vec3(0.0f, 0.0f, 1.0f));  // from the file, not computed
    EXPECT_EQ(mesh.normals[3], glm::vec3(0.6f, 0.0f, 0.8f));
  }
}

TEST(ReadPly, OtherTypesAndQuads) {
  // double positions, ushort colours, uint8/int32 lists as the Stanford files spell them.
  PlyContent content;
  content.vertexProperties = {{"double", "x"},   {"double", "y"},     {"double", "z"},
                              {"ushort", "red"}, {"ushort", "green"}, {"ushort", "blue"}};
  content.vertices = {{0, 0, 0, 65535, 0, 0},         {2, 0, 0, 0, 65535, 0}, {2, 2, 0, 0, 0, 65535},
                      {0, 2, 0, 65535, 65535, 65535}, {4, 0, 0, 0, 0, 0},     {4, 2, 0, 0, 0, 0}};
  content.faces = {{0, 1, 2, 3}, {1, 4, 5, 2}};
  content.countType = "uint8";
  content.indexType = "int32";
  ScratchDir dir;
  for (PlyEncoding encoding : kAllEncodings) {
    SCOPED_TRACE(encodingName(encoding));
    const auto file = dir.file("types_" + encodingName(encoding) + ".ply");
    test::writeFile(file, test::plyFile(content, encoding));
    const mesh::TriangleMesh mesh = readMeshOk(file);
    ASSERT_EQ(mesh.vertexCount(), 6u);
    EXPECT_EQ(mesh.triangleCount(), 4u);
    EXPECT_EQ(mesh.positions[5], glm::vec3(4.0f, 2.0f, 0.0f));
    EXPECT_EQ(mesh.colours[0], glm::vec4(1.0f, 0.0f, 0.0f, 1.0f));
    EXPECT_EQ(mesh.colours[3], glm::vec4(1.0f));
    for (const glm::vec3& normal : mesh.normals) EXPECT_EQ(normal, glm::vec3(0.0f, 0.0f, 1.0f));
  }
}

TEST(ReadObj, PositionsTextureCoordinatesAndNormals) {
  ScratchDir dir;
  const auto file = dir.file("quad.obj");
  test::writeFile(file,
                  "# a quad and a triangle\n"
                  "v 0 0 0\nv 2 0 0\nv 2 1.5 0\nv 0 1.5 0\nv 4 0 0.25\n"
                  "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0.5 0.25\n"
                  "vn 0 0 1\nvn 0 0 2\n"
                  "f 1/1/1 2/2/1 3/3/1 4/4/1\n"
                  "f 2/2/2 5/5/2 3/3/2\n");
  const mesh::TriangleMesh mesh = readMeshOk(file);
  // Vertices come in order of first use; vertices 2 and 3 have two normals but weld into one
  // (the first wins).
  const std::vector<glm::vec3> positions = {{0, 0, 0}, {2, 0, 0}, {2, 1.5f, 0}, {0, 1.5f, 0}, {4, 0, 0.25f}};
  EXPECT_EQ(mesh.positions, positions);
  EXPECT_EQ(mesh.indices, (std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3, 1, 4, 2}));
  const std::vector<glm::vec2> uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0.5f, 0.5f}};
  EXPECT_EQ(mesh.uvs, uvs);
  for (const glm::vec3& normal : mesh.normals) EXPECT_EQ(normal, glm::vec3(0, 0, 1));  // 0 0 2 normalised
  EXPECT_FALSE(mesh.hasColours());

  MeshReadOptions noWeld;
  noWeld.weldPositions = false;
  const mesh::TriangleMesh unwelded = readMeshOk(file, noWeld);
  EXPECT_EQ(unwelded.vertexCount(), 7u);  // vertices 2 and 3 twice: different normals
  EXPECT_EQ(unwelded.triangleCount(), 3u);
}

TEST(ReadObj, VertexColours) {
  ScratchDir dir;
  const auto file = dir.file("coloured.obj");
  test::writeFile(file, "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 1 1 0 0 0 1\nv 0 1 0 0.25 0.5 0.75\nf 1 2 3\nf 1 3 4\n");
  const mesh::TriangleMesh mesh = readMeshOk(file);
  ASSERT_EQ(mesh.vertexCount(), 4u);
  EXPECT_EQ(mesh.indices, (std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3}));
  const std::vector<glm::vec4> colours = {{1, 0, 0, 1}, {0, 1, 0, 1}, {0, 0, 1, 1}, {0.25f, 0.5f, 0.75f, 1}};
  EXPECT_EQ(mesh.colours, colours);
  EXPECT_FALSE(mesh.hasUvs());
}

TEST(ReadObj, WeldMergesDuplicatePositionsAndAveragesColours) {
  ScratchDir dir;
  const auto file = dir.file("seam.obj");
  // Vertices 1 and 5 share a position with different colours (a colour seam); vertex 6
  // duplicates vertex 3, making the last triangle degenerate once welded.
  test::writeFile(file,
                  "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\nv 1 1 0 1 1 1\nv 0 0 0 0 0 1\nv 0 1 0 0 0 1\n"
                  "f 1 2 3\nf 2 4 3\nf 5 2 4\nf 3 2 6\n");
  MeshReadOptions noWeld;
  noWeld.weldPositions = false;
  const mesh::TriangleMesh unwelded = readMeshOk(file, noWeld);
  EXPECT_EQ(unwelded.vertexCount(), 5u);  // 6 is an exact duplicate of 3 (same colour too)
  EXPECT_EQ(unwelded.triangleCount(), 4u);
  EXPECT_EQ(unwelded.indices[9], unwelded.indices[11]);  // kept as read, though degenerate

  const mesh::TriangleMesh welded = readMeshOk(file);
  ASSERT_EQ(welded.vertexCount(), 4u);
  EXPECT_EQ(welded.indices, (std::vector<std::uint32_t>{0, 1, 2, 1, 3, 2, 0, 1, 3}));
  EXPECT_EQ(welded.colours[0], glm::vec4(0.5f, 0.0f, 0.5f, 1.0f));  // red and blue averaged
  EXPECT_EQ(welded.colours[2], glm::vec4(0.0f, 0.0f, 1.0f, 1.0f));
}

TEST(ReadObj, KeepsNearbyAndSignedZeroPositionsApart) {
  // Assimp's JoinIdenticalVertices would merge these (it compares with an epsilon).
  ScratchDir dir;
  const auto file = dir.file("near.obj");
  test::writeFile(file, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0.0000001 0 0\nv 1 1e-7 0\nv -0 1 0\nf 1 2 3\nf 4 5 6\n");
  const mesh::TriangleMesh mesh = readMeshOk(file);
  EXPECT_EQ(mesh.vertexCount(), 6u);
  EXPECT_EQ(mesh.triangleCount(), 2u);
}

TEST(ReadObj, DropsPointsAndLinesAndMergesObjects) {
  ScratchDir dir;
  const auto file = dir.file("mixed.obj");
  test::writeFile(file,
                  "mtllib missing.mtl\no first\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nusemtl nothing\nf 1 2 3\n"
                  "l 1 3\np 4\nf 1 2\no second\nv 5 5 5\nf 1 2 5\ng group\nf -2 -1 -4\n");
  const mesh::TriangleMesh mesh = readMeshOk(file);
  EXPECT_EQ(mesh.triangleCount(), 3u);
  EXPECT_EQ(mesh.vertexCount(), 5u);
  EXPECT_EQ(mesh.positions[mesh.indices[5]], glm::vec3(5.0f));
  EXPECT_EQ(mesh.positions[mesh.indices[8]], glm::vec3(1.0f, 0.0f, 0.0f));  // -4 of 5 = vertex 2
}

TEST(ReadObj, WordsThatOnlyStartLikeStatementsAreIgnored) {
  // Assimp picks a statement by its first letters: it would read "vp" as a vertex, "glb2"
  // as a group and "fx" as a face, and fail on some of them after allocating their mesh.
  ScratchDir dir;
  const std::string plain = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n";
  const std::string noisy =
      "vp 0.5 0.5\nv 0 0 0\nv 1 0 0\ncstype bspline\nglb2 3 4\nv 1 1 0\nvx 7 7 7\nv 0 1 0\nfx 1 2 9\n"
      "f 1 2 3\ncurv 0 1 1 2\nsx 1\nousemtl a\nusemtlx b\nf 1 3 4\nend\n";
  test::writeFile(dir.file("plain.obj"), plain);
  test::writeFile(dir.file("noisy.obj"), noisy);
  const mesh::TriangleMesh expected = readMeshOk(dir.file("plain.obj"));
  const mesh::TriangleMesh mesh = readMeshOk(dir.file("noisy.obj"));
  EXPECT_EQ(mesh.positions, expected.positions);
  EXPECT_EQ(mesh.indices, expected.indices);
}

TEST(ReadObj, VertexWeightsAreDroppedAndTheNumberingKept) {
  // Numbers apart by any blank, a weight after x y z: Assimp 5.2 alone loses vertices on
  // such lines and then fails (and leaks) on a face that refers to the last of them (found
  // by fuzzing).
  ScratchDir dir;
  const auto file = dir.file("weights.obj");
  test::writeFile(file, "v 0 0 0\nv 1 0 0 5\nv 0\v0\f1\nv 0 \v\v10 0 1\nf 1 3 4\nf\v1 2 3\n");
  const mesh::TriangleMesh mesh = readMeshOk(file);
  ASSERT_EQ(mesh.triangleCount(), 2u);
  EXPECT_EQ(mesh.positions[mesh.indices[2]], glm::vec3(0.0f, 10.0f, 0.0f));
  EXPECT_EQ(mesh.positions[mesh.indices[4]], glm::vec3(1.0f, 0.0f, 0.0f));
}

TEST(ReadObj, IndentedLinesCommentsAndContinuations) {
  // Assimp alone would skip the indented face and fail on the comment.
  ScratchDir dir;
  const auto file = dir.file("layout.obj");
  test::writeFile(file,
                  "v 0 0 0\r\n  v 1 0 0\r\n\tv 1 1 \\\r\n 0\r\nv 0 1 0 # corner\r\nf 1 2 3 # first\r\n   f 1 3 4\r\n");
  const mesh::TriangleMesh mesh = readMeshOk(file);
  EXPECT_EQ(mesh.vertexCount(), 4u);
  EXPECT_EQ(mesh.triangleCount(), 2u);
  EXPECT_EQ(mesh.positions[2], glm::vec3(1.0f, 1.0f, 0.0f));
}

TEST(ReadObj, UnitNormalsKeptBitForBitAndZeroNormalsComputed) {
  ScratchDir dir;
  const auto file = dir.file("normals.obj");
  const float third = 1.0f / std::sqrt(3.0f);
  char text[256];
  std::snprintf(text, sizeof text, "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn %.9g %.9g %.9g\nvn 0 0 0\nf 1//1 2//1 3//2\n", third,
                third, third);
  test::writeFile(file, text);
  const mesh::TriangleMesh mesh = readMeshOk(file);
  EXPECT_EQ(mesh.normals[0], glm::vec3(third));
  EXPECT_EQ(mesh.normals[2], glm::vec3(0.0f, 0.0f, 1.0f));  // zero in the file: computed
}

TEST(ReadMesh, BakesTextureBeforeWelding) {
  ScratchDir dir;
  // 2 x 2 texels, top row red green, bottom row blue white.
  test::writeFile(dir.file("texture.ppm"), test::ppmFile(2, 2, {255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255}));
  const auto file = dir.file("textured.obj");
  // Texel centres, v = 0 at the bottom; vertex 1 appears twice with different texture
  // coordinates (a seam) and welds into one with the colours averaged.
  test::writeFile(file,
                  "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 0\n"
                  "vt 0.25 0.25\nvt 0.75 0.25\nvt 0.75 0.75\nvt 0.25 0.75\nvt 0.5 0.5\n"
                  "f 1/1 2/2 3/3\nf 1/3 3/3 4/4\nf 1/1 2/2 5/5\n");
  MeshReadOptions options;
  options.bakeTexture = dir.file("texture.ppm");
  options.weldPositions = false;
  const mesh::TriangleMesh unwelded = readMeshOk(file, options);
  ASSERT_EQ(unwelded.vertexCount(), 6u);
  EXPECT_EQ(unwelded.colours[0], glm::vec4(0, 0, 1, 1));           // (0.25, 0.25): bottom left, blue
  EXPECT_EQ(unwelded.colours[1], glm::vec4(1, 1, 1, 1));           // bottom right, white
  EXPECT_EQ(unwelded.colours[2], glm::vec4(0, 1, 0, 1));           // top right, green
  EXPECT_EQ(unwelded.colours[3], glm::vec4(0, 1, 0, 1));           // vertex 1 again, with the top-right coordinate
  EXPECT_EQ(unwelded.colours[4], glm::vec4(1, 0, 0, 1));           // top left, red
  EXPECT_EQ(unwelded.colours[5], glm::vec4(0.5f, 0.5f, 0.5f, 1));  // centre: all four averaged

  options.weldPositions = true;
  const mesh::TriangleMesh welded = readMeshOk(file, options);
  ASSERT_EQ(welded.vertexCount(), 5u);
  EXPECT_EQ(welded.colours[0], glm::vec4(0.0f, 0.5f, 0.5f, 1.0f));  // blue and green averaged
  EXPECT_EQ(welded.uvs[0], glm::vec2(0.25f, 0.25f));                // first occurrence wins
}

TEST(ReadMesh, BakesTranslucentTexelsWithTheirOwnColour) {
  ScratchDir dir;
  RgbaImage texel(1, 1);
  const std::uint8_t halfRed[4] = {255, 0, 0, 128};
  std::copy(halfRed, halfRed + 4, texel.at(0, 0));
  ASSERT_TRUE(terrain::writeRgbaPng(dir.file("texel.png"), texel).ok());
  const auto file = dir.file("one.obj");
  test::writeFile(file, "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.5 0.5\nf 1/1 2/1 3/1\n");
  MeshReadOptions options;
  options.bakeTexture = dir.file("texel.png");
  const mesh::TriangleMesh baked = readMeshOk(file, options);
  // Straight alpha: the colour is the painted red, not red times alpha.
  EXPECT_NEAR(baked.colours[0].r, 1.0f, 1e-6f);
  EXPECT_NEAR(baked.colours[0].a, 128.0f / 255.0f, 1e-6f);
}

TEST(ReadMesh, BakeErrorsNameBothFiles) {
  ScratchDir dir;
  const auto textured = dir.file("textured.obj");
  test::writeFile(textured, "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\n");
  const auto plain = dir.file("plain.obj");
  test::writeFile(plain, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  test::writeFile(dir.file("texture.ppm"), test::ppmFile(1, 1, {10, 20, 30}));
  test::writeFile(dir.file("broken.png"), "not a png at all");

  MeshReadOptions options;
  options.bakeTexture = dir.file("texture.ppm");
  Result<mesh::TriangleMesh> noUvs = readMesh(plain, options);
  ASSERT_FALSE(noUvs.ok());
  EXPECT_EQ(noUvs.error().kind, ErrorKind::InvalidArgument);
  EXPECT_NE(noUvs.error().message.find("plain.obj"), std::string::npos) << noUvs.error().message;
  EXPECT_NE(noUvs.error().message.find("texture coordinates"), std::string::npos) << noUvs.error().message;

  options.bakeTexture = dir.file("missing.png");
  Result<mesh::TriangleMesh> missing = readMesh(textured, options);
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().kind, ErrorKind::Io);
  EXPECT_NE(missing.error().message.find("textured.obj"), std::string::npos) << missing.error().message;
  EXPECT_NE(missing.error().message.find("missing.png"), std::string::npos) << missing.error().message;

  options.bakeTexture = dir.file("broken.png");
  Result<mesh::TriangleMesh> broken = readMesh(textured, options);
  ASSERT_FALSE(broken.ok());
  EXPECT_EQ(broken.error().kind, ErrorKind::InvalidData);
  EXPECT_NE(broken.error().message.find("broken.png"), std::string::npos) << broken.error().message;

  options.bakeTexture = dir.file("texture.ppm");
  const mesh::TriangleMesh baked = readMeshOk(textured, options);
  ASSERT_TRUE(baked.hasColours());
  EXPECT_FLOAT_EQ(baked.colours[0].r, 10 / 255.0f);
  EXPECT_FLOAT_EQ(baked.colours[0].g, 20 / 255.0f);
  EXPECT_FLOAT_EQ(baked.colours[0].b, 30 / 255.0f);
  EXPECT_EQ(baked.colours[0].a, 1.0f);
}

}  // namespace
}  // namespace polder::mesh_io
