// readMesh on the real meshes of the shared data folder (skipped when it is absent).
#include <gtest/gtest.h>

#include <algorithm>

#include <polder/mesh_io/mesh_file.hpp>

#include "mesh_test_files.hpp"
#include "test_support.hpp"

namespace polder::mesh_io {
namespace {

using test::readMeshOk;

TEST(SharedMeshes, StanfordBunny) {
  POLDER_REQUIRE_SHARED_FILE(file, "meshes/stanford_bunny_bun_zipper.ply");
  const mesh::TriangleMesh mesh = readMeshOk(file);
  EXPECT_EQ(mesh.vertexCount(), 35947u);
  EXPECT_EQ(mesh.triangleCount(), 69451u);
  EXPECT_FALSE(mesh.hasColours());
  EXPECT_FALSE(mesh.hasUvs());
  EXPECT_EQ(mesh.normals.size(), mesh.vertexCount());                           // computed
  EXPECT_NEAR(mesh::boundingBoxDiagonal(mesh.positions), 0.25, 0.005);          // about 0.155 x 0.153 x 0.12
  EXPECT_EQ(mesh.positions[0], glm::vec3(-0.0378297f, 0.12794f, 0.00447467f));  // the file's first vertex
}

TEST(SharedMeshes, CowAndFandisk) {
  POLDER_REQUIRE_SHARED_FILE(cow, "meshes/cow.obj");
  POLDER_REQUIRE_SHARED_FILE(fandisk, "meshes/fandisk.obj");
  const mesh::TriangleMesh cowMesh = readMeshOk(cow);
  EXPECT_EQ(cowMesh.vertexCount(), 2903u);
  EXPECT_EQ(cowMesh.triangleCount(), 5804u);
  const mesh::TriangleMesh fandiskMesh = readMeshOk(fandisk);
  EXPECT_EQ(fandiskMesh.vertexCount(), 6475u);
  EXPECT_EQ(fandiskMesh.triangleCount(), 12946u);
}

TEST(SharedMeshes, SpotWithBakedTexture) {
  POLDER_REQUIRE_SHARED_FILE(file, "meshes/spot_triangulated.obj");
  POLDER_REQUIRE_SHARED_FILE(texture, "meshes/spot_texture.png");
  MeshReadOptions options;
  options.bakeTexture = texture;
  const mesh::TriangleMesh mesh = readMeshOk(file, options);
  EXPECT_EQ(mesh.triangleCount(), 5856u);
  EXPECT_EQ(mesh.vertexCount(), 2930u);
  ASSERT_TRUE(mesh.hasColours());
  ASSERT_TRUE(mesh.hasUvs());
  EXPECT_TRUE(std::any_of(mesh.colours.begin(), mesh.colours.end(),
                          [&](const glm::vec4& colour) { return colour != mesh.colours.front(); }));
  for (const glm::vec4& colour : mesh.colours) {
    EXPECT_TRUE(glm::all(glm::greaterThanEqual(colour, glm::vec4(0.0f))) &&
                glm::all(glm::lessThanEqual(colour, glm::vec4(1.0f))));
    EXPECT_EQ(colour.a, 1.0f);  // an RGB texture
  }

  // Keeping the UV seams splits the 277 positions where texture coordinates meet: 259
  // vertices come twice and 18 (where seams cross) three times, each with its own side's
  // coordinate, and the triangles stay.
  options.keepUvSeams = true;
  const mesh::TriangleMesh seamed = readMeshOk(file, options);
  EXPECT_EQ(seamed.vertexCount(), 2930u + 277u + 18u);
  EXPECT_EQ(seamed.triangleCount(), 5856u);

  // Without welding the UV seams stay split too.
  options.weldPositions = false;
  const mesh::TriangleMesh unwelded = readMeshOk(file, options);
  EXPECT_GE(unwelded.vertexCount(), seamed.vertexCount());
  EXPECT_EQ(unwelded.triangleCount(), 5856u);
}

}  // namespace
}  // namespace polder::mesh_io
