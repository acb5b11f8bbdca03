// Ear clipping of the dikes' junction polygons (dike_ear_clipping.cpp), for the dike builder
// (dikes.cpp). The dikes follow J.-H. Chuang, "Level-of-Detail Modeling Technique for Virtual
// Reality (I)", 2001, part B (dikes.hpp).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <polder/terrain/dikes.hpp>

namespace polder::terrain::detail {

// Triangulates a simple polygon of at least three vertices, counter-clockwise seen from +z:
// `polygon` lists its vertices, indices into `points` (full-resolution samples, so every test
// is exact). Clips the ear with the shortest valid diagonal first (of two equally long, the
// one running north-west to south-east, as heightfield.hpp cuts its cells) and never one of
// zero area or with a vertex in its closed triangle, so vertices on straight sides stay
// vertices (no T-junctions). Writes polygon.size() - 2 triangles, three indices into `points`
// each, counter-clockwise, to `triangles`; `ears` is working memory. Returns nullptr, or what
// broke (the polygon is not simple, or degenerate).
const char* clipEars(std::span<const std::uint32_t> polygon, const DikeVertex* points,
                     std::vector<DikeScratch::Ear>& ears, std::uint32_t* triangles);

}  // namespace polder::terrain::detail
