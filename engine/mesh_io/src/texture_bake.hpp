// Sampling an image at texture coordinates into vertex colours (OpenImageIO).
#pragma once

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <vector>

#include <glm/glm.hpp>

#include <polder/result.hpp>

namespace polder::mesh_io::detail {

// A colour channel as a TriangleMesh holds it: clamped to [0, 1], non-finite values 0. For
// the file's colours and the sampled ones alike.
inline float unitColour(float value) { return std::isfinite(value) ? std::clamp(value, 0.0f, 1.0f) : 0.0f; }

// Bilinear samples of the image at each (u, v), v = 0 being the bottom row (OBJ convention).
// Coordinates outside [0, 1] repeat; samples do not blend across the image border. Grey
// images give grey colours, images without alpha give alpha 1; values are clamped to [0, 1].
// Errors name the image but not the mesh (the caller adds it).
Result<std::vector<glm::vec4>> sampleTexture(const std::filesystem::path& image, const std::vector<glm::vec2>& uvs);

}  // namespace polder::mesh_io::detail
