// Where a builder hands each step the moment it takes it: a pipelined build
// (buildProgressiveMesh) assembles the steps on a second thread meanwhile.
#pragma once

#include <cstdint>
#include <span>

#include "polder/mesh/cluster_builder.hpp"
#include "polder/mesh/collapse_builder.hpp"
#include "polder/mesh/region_partition.hpp"
#include "polder/mesh/simplification_steps.hpp"
#include "polder/mesh/triangle_mesh.hpp"
#include "polder/result.hpp"
#include "polder/thread_pool.hpp"

namespace polder::mesh {

class StepListener {
 public:
  virtual ~StepListener() = default;
  // Before the first step: the builder works on a renumbered copy of the mesh, whose
  // vertex v is the caller's vertex originalOf[v] (the span lives until the build ends).
  virtual void renumbered(std::span<const std::uint32_t> originalOf) = 0;
  // After each step: the builder's steps so far, in its numbering; the last one is new.
  virtual void stepTaken(const SimplificationSteps& steps) = 0;
  // The builder starts (true) or stops (false) keeping two cores busy with its own threads.
  virtual void builderOnTwoCores(bool /*busy*/) {}
};

// buildCollapseSteps and buildClusterSteps on `pool`, telling `listener` (when not null) of
// every step.
Result<SimplificationSteps> buildCollapseSteps(const TriangleMesh& mesh, const RegionPartition& partition,
                                               const CollapseOptions& options, StepListener* listener,
                                               core::ThreadPool& pool);
Result<SimplificationSteps> buildClusterSteps(const TriangleMesh& mesh, const RegionPartition& partition,
                                              const ClusterOptions& options, StepListener* listener,
                                              core::ThreadPool& pool);

}  // namespace polder::mesh
