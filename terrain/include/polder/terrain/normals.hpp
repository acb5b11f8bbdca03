// Surface normals of a heightfield at its samples, shared by the renderer's meshes and the
// ray-cast reference renderer so both shade the same.
#pragma once

#include <glm/glm.hpp>

#include <polder/terrain/heightfield.hpp>

namespace polder::terrain {

// Unit normal at sample (x, y) from central differences (one-sided at the edges).
glm::vec3 sampleNormal(const Heightfield& field, int x, int y);

}  // namespace polder::terrain
