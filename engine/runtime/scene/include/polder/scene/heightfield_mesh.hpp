// A DEM as one mesh object: ASLOD's Silvretta model (Schmalstieg and Fuhrmann 1999,
// section 7), a terrain crop simplified and allocated like any other mesh.
#pragma once

#include <polder/mesh/triangle_mesh.hpp>
#include <polder/terrain/heightfield.hpp>

namespace polder::scene {

// Every sample a vertex at (i * spacingX, j * spacingY, height), row by row from the
// south-west; two triangles per cell, counter-clockwise seen from above; area-weighted
// vertex normals.
mesh::TriangleMesh heightfieldMesh(const terrain::Heightfield& field);

}  // namespace polder::scene
