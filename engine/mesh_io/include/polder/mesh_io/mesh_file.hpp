// Reading and writing triangle meshes as OBJ or PLY (PLY: ascii, binary little- and big-endian).
//
// readMesh imports through Assimp and merges every mesh of the file into one TriangleMesh,
// vertices as stored (node transforms are not applied; OBJ and PLY have none anyway).
//   - Polygons are triangulated; points and lines are dropped.
//   - Attributes: colour set 0 as RGBA (integer PLY colours scaled to [0, 1], values clamped to
//     [0, 1], a missing alpha is 1), texture coordinate set 0 (u, v as stored: v = 0 is the
//     bottom of the image), normals. Where only some of the file's meshes carry an attribute,
//     the others get white, (0, 0) or a computed normal.
//   - Vertices whose position, normal, colour and texture coordinate are all bit-identical
//     are one vertex (an OBJ face corner becomes a vertex first). Assimp's own
//     aiProcess_JoinIdenticalVertices is not used: it merges positions up to an epsilon
//     and treats NaN as equal to anything. PLY keeps the file's vertex order (unreferenced
//     vertices included); OBJ yields its referenced vertices in order of first use.
//   - options.bakeTexture: the image is sampled (bilinear, v = 0 the bottom row; coordinates
//     outside [0, 1] repeat, samples never blend across the image border) at each vertex's
//     texture coordinate and replaces the colours, before welding.
//   - options.weldPositions: vertices with bit-identical positions become one; the first
//     one's normal and texture coordinate win, colours are averaged. Triangles with a
//     repeated vertex are then dropped. Without welding every triangle is kept as read.
//     With options.keepUvSeams, vertices whose texture coordinates differ stay apart: the
//     texture keeps its seams, and the builders move the two sides of a seam together.
//   - Normals: the file's (normalised) where present and non-zero, otherwise
//     mesh::computeVertexNormals of the final triangles (after welding).
//   - Before Assimp runs, PLY files get a structural walk and OBJ files a checking pass
//     (ply_check.hpp, obj_check.hpp in src/): Assimp 5.2 alone hangs, crashes or silently
//     misreads some truncated or malformed files.
// Errors never throw; the message is one line naming the file (and the texture) and the
// problem. ErrorKind: Io (mesh or texture missing or unreadable), Unsupported (extension
// other than .obj/.ply), InvalidData (empty, garbage, truncated, index out of range,
// non-finite position, no triangles left, undecodable texture), InvalidArgument
// (bakeTexture for a mesh without texture coordinates), OutOfMemory.
// Thread-safe: calls on different files may run concurrently.
//
// writeMesh picks the format from the extension (.obj, .ply or .glb). OBJ stores v (with r g b
// when the mesh has colours; alpha is not stored), vt, vn and f v/vt/vn; PLY stores float
// x y z, nx ny nz, red green blue alpha, s t and int vertex_indices, ascii or binary little
// endian; glTF 2.0 binary stores one primitive of POSITION, NORMAL, COLOR_0, TEXCOORD_0 and
// uint32 indices, z up turned to glTF's y up by its node's rotation (src/glb_writer.hpp).
// OBJ and PLY numbers are written so that readMesh reads back the same floats (an OBJ comes back
// with its vertices in order of first use). The file is written under a temporary name
// beside it and renamed, so a failed write leaves no partial file. Errors name the file:
// Unsupported (extension), InvalidArgument (mesh fails validateMesh or has non-finite
// attributes), Io (cannot create, write or rename).
#pragma once

#include <filesystem>
#include <string_view>

#include <polder/mesh/triangle_mesh.hpp>
#include <polder/result.hpp>

namespace polder::mesh_io {

struct MeshReadOptions {
  bool weldPositions = true;
  bool keepUvSeams = false;           // with weldPositions: weld only vertices with equal texture coordinates
  std::filesystem::path bakeTexture;  // empty: none
};

Result<mesh::TriangleMesh> readMesh(const std::filesystem::path& file, const MeshReadOptions& options = {});

struct MeshWriteOptions {
  bool binary = true;  // PLY only
};

Status writeMesh(const std::filesystem::path& file, const mesh::TriangleMesh& mesh,
                 const MeshWriteOptions& options = {});

}  // namespace polder::mesh_io
