#include "polder/mesh/progressive_mesh.hpp"

#include "progressive_mesh_assembler.hpp"

namespace polder::mesh {

namespace {

template <class T>
std::size_t bytesOf(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}

}  // namespace

std::uint32_t RegionSequence::levelForTriangles(std::uint32_t triangles) const {
  // trianglesAt grows with the level: find the last level whose count fits.
  std::uint32_t lo = 0, hi = levelCount();
  if (trianglesAt(0) > triangles) return 0;
  while (lo < hi) {
    const std::uint32_t mid = lo + (hi - lo + 1) / 2;
    if (trianglesAt(mid) <= triangles)
      lo = mid;
    else
      hi = mid - 1;
  }
  return lo;
}

std::uint32_t RegionSequence::levelForError(float error) const {
  // errorAt shrinks as the level grows: find the first level whose error fits.
  std::uint32_t lo = 0, hi = levelCount();
  while (lo < hi) {
    const std::uint32_t mid = lo + (hi - lo) / 2;
    if (errorAt(mid) <= error)
      hi = mid;
    else
      lo = mid + 1;
  }
  return lo;
}

std::size_t RegionSequence::memoryBytes() const {
  return bytesOf(m_trianglesAfterSteps) + bytesOf(m_verticesAfterSteps) + bytesOf(m_errorAfterSteps) +
         bytesOf(m_fullIndices) + bytesOf(m_foreignCorners) + bytesOf(m_borderVertices) + bytesOf(m_readers) +
         bytesOf(m_cornerChangeBegin) + bytesOf(m_cornerChanges) + bytesOf(m_borderChangeBegin) +
         bytesOf(m_borderChanges);
}

std::size_t ProgressiveMesh::memoryBytes() const {
  std::size_t bytes = bytesOf(m_vertices.positions) + bytesOf(m_vertices.normals) + bytesOf(m_vertices.colours) +
                      bytesOf(m_vertices.uvs) + bytesOf(m_vertices.indices) + bytesOf(m_originalVertex) +
                      bytesOf(m_vertexRegion);
  for (const RegionSequence& r : m_regions) bytes += r.memoryBytes();
  return bytes;
}

Result<ProgressiveMesh> ProgressiveMesh::assemble(const TriangleMesh& mesh, const RegionPartition& partition,
                                                  const SimplificationSteps& steps) {
  ProgressiveMeshAssembler assembler(mesh, partition);
  if (Status begun = assembler.begin(); !begun) return begun.error();
  if (steps.removedBegin.size() != steps.size() + 1 || steps.error.size() != steps.size() ||
      steps.removedBegin.back() != steps.removed.size() || steps.onto.size() != steps.removed.size())
    return makeError(ErrorKind::InvalidArgument, "simplification steps: inconsistent array sizes");
  for (std::size_t s = 0; s < steps.size(); ++s)
    if (Status added = assembler.addStep(steps.representative[s], steps.removedBy(s), steps.ontoBy(s), steps.error[s]);
        !added)
      return added.error();
  core::ThreadPool pool;
  return assembler.finish(pool);
}

}  // namespace polder::mesh
