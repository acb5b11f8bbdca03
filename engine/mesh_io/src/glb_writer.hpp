// A glTF 2.0 binary (.glb) of one triangle mesh, written by hand (Khronos, "glTF 2.0
// Specification", sections 4.4 "Binary glTF Layout" and 3.7 "Concepts: Geometry").
//
// One scene, one node, one mesh, one primitive of triangles: POSITION (with the min and max
// the specification requires), NORMAL, COLOR_0 (RGBA float) and TEXCOORD_0 where the mesh
// has them, and uint32 indices, each in its own buffer view of the one binary chunk. Vertex
// data stay in Polder's frame (z up); the node carries the rotation -90 degrees about x that
// puts z up onto glTF's y up, so viewers stand the model upright and the numbers read back
// as written. glTF's texture coordinates start at the image's top: v is stored as 1 - v.
#pragma once

#include <string>

#include <polder/mesh/triangle_mesh.hpp>
#include <polder/result.hpp>

namespace polder::mesh_io::detail {

// The file's bytes; Unsupported when they would pass the format's 4 GiB limit. The mesh must
// be valid (validateMesh) with finite attributes.
Result<std::string> glbBytes(const mesh::TriangleMesh& mesh);

}  // namespace polder::mesh_io::detail
