// Assembles a ProgressiveMesh from a builder's steps, one step at a time: the steps are
// checked and replayed on the original's triangles as they come (a pipelined build hands
// them over while the builder is still running), and finish() lays out the sequence.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "polder/mesh/progressive_mesh.hpp"
#include "polder/mesh/region_partition.hpp"
#include "polder/mesh/triangle_mesh.hpp"
#include "polder/result.hpp"
#include "polder/thread_pool.hpp"

namespace polder::mesh {

class ProgressiveMeshAssembler {
 public:
  // Both must outlive the assembler.
  ProgressiveMeshAssembler(const TriangleMesh& mesh, const RegionPartition& partition)
      : m_mesh(mesh), m_partition(partition) {}

  // Validates the mesh and the partition and collects the triangles; first.
  Status begin();
  // Checks the next step (it only joins active vertices of one region onto active vertices
  // of that region) and replays it.
  Status addStep(std::uint32_t rep, std::span<const std::uint32_t> removed, std::span<const std::uint32_t> onto,
                 float error);
  // The sequence of the steps added; last.
  ProgressiveMesh finish(core::ThreadPool& pool);

 private:
  struct RecordedChange {
    std::uint32_t triangle, corner, before, after;
  };

  Status checkStep(std::uint32_t rep, std::span<const std::uint32_t> removed, std::span<const std::uint32_t> onto);
  void collectTriangles();
  void replayStep(std::uint32_t region, std::uint32_t local, std::span<const std::uint32_t> removed,
                  std::span<const std::uint32_t> onto);
  bool hasDegenerated(std::uint32_t t) const;  // its current corners repeat a vertex

  // finish()'s orders, shared by its halves.
  struct Layout {
    std::vector<std::uint32_t> order;                     // new vertex index -> original
    std::vector<std::uint32_t> newIndex;                  // original vertex -> new index
    std::vector<std::vector<std::uint32_t>> trianglesOf;  // per region, in the input's order
    std::vector<std::uint32_t> slotOf;                    // triangle -> its first corner's slot in its region
  };
  std::uint32_t removalKey(std::uint32_t v) const;
  void layOutVertices(ProgressiveMesh& out, Layout& layout) const;
  void layOutTriangles(ProgressiveMesh& out, Layout& layout) const;
  void fillIndexBuffers(ProgressiveMesh& out, const Layout& layout) const;
  void translateChanges(ProgressiveMesh& out, const Layout& layout);

  const TriangleMesh& m_mesh;
  const RegionPartition& m_partition;
  std::vector<std::uint32_t> m_removalStep;      // global step removing each vertex
  std::vector<std::uint32_t> m_stepRegion;       // per global step: its representative's region
  std::vector<std::uint32_t> m_localStep;        // per global step: its index in its region
  std::vector<float> m_stepError;                // per global step: the builder's error
  std::vector<std::uint32_t> m_regionStepCount;  // per region
  std::vector<std::uint32_t> m_corners;          // current vertex of every corner
  std::vector<std::uint32_t> m_originalCorners;  // corners before the replay
  std::vector<std::uint32_t> m_owner;            // region of every triangle
  std::vector<std::uint32_t> m_vanishStep;       // local step at which a triangle degenerates
  // Own corners per vertex and border-table entries per vertex, as linked lists that a step
  // splices onto its representative.
  std::vector<std::uint32_t> m_cornerHead, m_cornerNext;
  struct EntryNode {
    std::uint32_t entry, next;
  };
  std::vector<EntryNode> m_entryNodes;
  std::vector<std::uint32_t> m_entryHead;
  std::vector<std::uint32_t> m_entryOf;  // border-table entry of a vertex, in its region
  std::vector<std::vector<std::uint32_t>> m_borderVertices;
  std::vector<std::vector<RecordedChange>> m_recorded;
  std::vector<std::vector<std::uint32_t>> m_recordedBegin;
  std::vector<std::vector<RecordedChange>> m_borderRecorded;
  std::vector<std::vector<std::uint32_t>> m_borderRecordedBegin;
};

}  // namespace polder::mesh
