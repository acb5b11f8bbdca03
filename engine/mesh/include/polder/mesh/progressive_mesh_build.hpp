// Building a progressive mesh in one call: the builder takes its steps on the calling
// thread while another thread of the pool (options.threads) checks and replays the steps
// as they come (what ProgressiveMesh::assemble does afterwards otherwise), so the whole
// sequence costs little more than the builder alone. The result equals buildCollapseSteps
// or buildClusterSteps followed by ProgressiveMesh::assemble. With one thread, the two run
// one after the other.
#pragma once

#include "polder/mesh/cluster_builder.hpp"
#include "polder/mesh/collapse_builder.hpp"
#include "polder/mesh/progressive_mesh.hpp"
#include "polder/mesh/region_partition.hpp"
#include "polder/mesh/triangle_mesh.hpp"
#include "polder/result.hpp"

namespace polder::mesh {

Result<ProgressiveMesh> buildProgressiveMesh(const TriangleMesh& mesh, const RegionPartition& partition,
                                             const CollapseOptions& options);
Result<ProgressiveMesh> buildProgressiveMesh(const TriangleMesh& mesh, const RegionPartition& partition,
                                             const ClusterOptions& options);

}  // namespace polder::mesh
