// Builder `cluster`: view-independent LOD modelling by floating-cell vertex clustering
// (J.-H. Chuang, "Level-of-Detail Modeling Technique for Virtual Reality (I)", 2001, part A). Each step picks the
// representative of lowest cost, centres an axis-aligned cell of size tau on it, grows a spanning tree from it over the
// current edges inside the cell, and gathers the tree onto it: several vertices per step; triangles with two or three
// gathered corners vanish, the others are re-pointed (no edge collapse's link condition: the paper simplifies topology
// too, though a step never pinches the surface into a non-manifold edge). The representative is an original vertex, so
// every level uses original vertices only (simplification_steps.hpp).
//
// Vertices are classified once (simple, boundary, seam, sharp edge, corner, complex), and a
// vertex only joins a representative that keeps its feature: sharp-edge vertices along
// their feature line, boundary vertices along the boundary, colour-border vertices along
// their side of the border; corners and non-manifold vertices never join. A mesh split
// along texture seams (two vertices at one position, each with its own side's UVs) keeps
// its seams closed: a seam vertex joins only a seam representative, along the seam, and
// its twin joins the representative's twin in the same step (SimplificationSteps::onto).
// Knots of sharp edges spanning only a few edge lengths (noise) are no features, and a
// feature the coarser mesh no longer shows (no sharp edge left around it) relaxes to a
// simple vertex.
//
// Cost of a cluster: the quadric error (Garland & Heckbert 1997) of the gathered vertices'
// planes at the representative plus their area-weighted colour deviation, each scaled by
// the vertex's class weight, averaged over the gathered vertices. A vertex costing far
// more than the others, or whose move would flip a surviving triangle or pinch the
// surface (a non-manifold edge, an isolated vertex), stays out with its subtree. Cells
// start at tau0 (the paper's uniform subdivision of the bounding box); a representative
// with nothing to gather in its cell grows it by `cellGrowth`, so cheap parts coarsen in
// larger cells while costly ones wait, until the cell covers the bounding box.
//
// A large mesh is simplified in rounds by two threads at once, each on its own piece of
// the surface (a range of vertices in locality order) while the vertices between the
// pieces wait for the next round, which cuts elsewhere; each round's steps are merged
// cheapest first. The steps never depend on the threads' timing, and are the same where
// no second thread starts. The last few hundred vertices go in the exact queue order.
#pragma once

#include <cstdint>
#include <functional>

#include "polder/mesh/region_partition.hpp"
#include "polder/mesh/simplification_steps.hpp"
#include "polder/mesh/triangle_mesh.hpp"
#include "polder/result.hpp"

namespace polder::mesh {

struct ClusterOptions {
  // Initial cell size tau0 as a fraction of the bounding-box diagonal; 0 picks twice the
  // mean edge length (a cell reaching about one ring of neighbours).
  double initialCellFraction = 0.0;
  // A representative whose cell holds nothing it may gather multiplies its cell by this (> 1).
  double cellGrowth = 1.5;
  // Weight of the colour term: a colour difference of 1 costs as much as a distance of
  // `colourWeight` bounding-box diagonals. 0 ignores colours (and colour borders).
  double colourWeight = 0.5;
  // Edges whose two face normals differ by more than this angle are sharp; boundaries and
  // feature lines that turn by more than it make corners. 180 turns features off.
  double featureAngleDegrees = 40.0;
  // Stop once at most this many triangles remain (0: go as far as the rules allow).
  std::uint32_t stopAtTriangles = 0;
  // Called now and then with the fraction of vertices removed so far.
  std::function<void(double)> progress;
  // The most threads the build runs on at once (0: one per hardware thread); the steps do
  // not depend on it.
  int threads = 0;
};

// The steps from the original mesh to the coarsest mesh the rules allow; no step joins two
// regions and every step removes at least one vertex. Errors in the steps are object-space
// distances: the largest root-mean-square plane distance, at the representative, of the
// clusters it holds after the step.
Result<SimplificationSteps> buildClusterSteps(const TriangleMesh& mesh, const RegionPartition& partition,
                                              const ClusterOptions& options = {});

}  // namespace polder::mesh
