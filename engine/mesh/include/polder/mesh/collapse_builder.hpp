// Builder `collapse`: the ASLOD cluster tree (D. Schmalstieg and A. Fuhrmann, "Coarse View-Dependent Levels of Detail
// for Hierarchical and Deformable Models", 1999, section 2) grown by half-edge collapses: each step moves one vertex
// onto one of its neighbours, so every level uses original vertices only. Collapses are taken cheapest first by the
// quadric error metric (Garland & Heckbert 1997) of the removed vertex's planes at the
// neighbour's position (divided by the cluster's area to the power 0.8), plus an
// attribute term: the area-weighted squared difference of
// the removed cluster's normals, colours and UVs from the representative's (kept as
// moments, so merged clusters cost O(1)). A collapse is refused when it would flip or
// nearly flip a triangle, break the surface's manifold structure (link condition), move a
// vertex off an open boundary or a non-manifold vertex at all, move a vertex beside a
// colour discontinuity off that border (colourWeight > 0), or join two regions.
// A mesh split along texture seams (two vertices at one position, each with its own side's
// UVs) keeps its seams closed: a seam vertex moves along the seam together with its twin,
// in one step, each onto its own side's neighbour (SimplificationSteps::onto).
#pragma once

#include <cstdint>
#include <functional>

#include "polder/mesh/region_partition.hpp"
#include "polder/mesh/simplification_steps.hpp"
#include "polder/mesh/triangle_mesh.hpp"
#include "polder/result.hpp"

namespace polder::mesh {

struct CollapseOptions {
  // Weights of the attribute term; a difference of 1 in an attribute costs as much as a
  // distance of `weight` bounding-box diagonals. 0 ignores the attribute.
  double normalWeight = 0.0;
  double colourWeight = 0.1;
  double uvWeight = 0.05;
  // Open boundaries are held by planes through their edges, this times the face weight.
  double boundaryWeight = 4.0;
  // A collapse may turn no triangle's normal by more than this angle's cosine allows.
  double minNormalCosine = 0.2;
  // Stop once this many triangles remain (0: go as far as collapses allow).
  std::uint32_t stopAtTriangles = 0;
  // Called now and then with the fraction of collapses done (for long builds).
  std::function<void(double)> progress;
  // The most threads the build runs on at once (0: one per hardware thread); the steps do
  // not depend on it.
  int threads = 0;
};

// The steps from the original mesh down to the coarsest mesh the rules allow. Errors in
// the steps are object-space distances (root of the mean squared plane distance of the
// representative's cluster).
Result<SimplificationSteps> buildCollapseSteps(const TriangleMesh& mesh, const RegionPartition& partition,
                                               const CollapseOptions& options = {});

}  // namespace polder::mesh
