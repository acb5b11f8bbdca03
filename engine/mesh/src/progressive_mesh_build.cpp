#include "polder/mesh/progressive_mesh_build.hpp"

#include <condition_variable>
#include <exception>
#include <mutex>
#include <optional>
#include <system_error>
#include <thread>
#include <vector>

#include "progressive_mesh_assembler.hpp"
#include "step_listener.hpp"

namespace polder::mesh {

namespace {

// Steps in the caller's vertex ids, a batch at a time.
struct StepBatch {
  std::vector<std::uint32_t> representative, removedBegin{0}, removed, onto;
  std::vector<float> error;

  std::size_t size() const { return representative.size(); }
  bool empty() const { return representative.empty(); }
  void clear() {
    representative.clear(), removed.clear(), onto.clear(), error.clear();
    removedBegin.assign(1, 0);
  }
  void append(const StepBatch& other) {
    for (std::size_t s = 0; s < other.size(); ++s)
      removedBegin.push_back(static_cast<std::uint32_t>(removed.size()) + other.removedBegin[s + 1]);
    representative.insert(representative.end(), other.representative.begin(), other.representative.end());
    removed.insert(removed.end(), other.removed.begin(), other.removed.end());
    onto.insert(onto.end(), other.onto.begin(), other.onto.end());
    error.insert(error.end(), other.error.begin(), other.error.end());
  }
};

// The builder's side fills a batch with each step, renamed to the caller's ids, and hands
// full batches over; the assembler's side waits for them. Batches keep the locking rare
// (a step takes a few microseconds).
class StepHandover final : public StepListener {
 public:
  void renumbered(std::span<const std::uint32_t> originalOf) override { m_originalOf = originalOf; }

  void stepTaken(const SimplificationSteps& steps) override {
    const std::size_t s = steps.size() - 1;
    m_filling.representative.push_back(m_originalOf[steps.representative[s]]);
    for (std::uint32_t v : steps.removedBy(s)) m_filling.removed.push_back(m_originalOf[v]);
    for (std::uint32_t v : steps.ontoBy(s)) m_filling.onto.push_back(m_originalOf[v]);
    m_filling.removedBegin.push_back(static_cast<std::uint32_t>(m_filling.removed.size()));
    m_filling.error.push_back(steps.error[s]);
    if (m_filling.size() >= kBatchSteps) handOver(false);
  }

  // The builder is done (or failed): the last batch goes over.
  void close() { handOver(true); }

  // Waits for the next batch (into `batch`, which must be empty); false once the builder is
  // done and everything was taken.
  bool take(StepBatch& batch) {
    std::unique_lock lock(m_mutex);
    m_changed.wait(lock, [&] { return !m_ready.empty() || m_closed; });
    if (m_ready.empty()) return false;
    std::swap(batch, m_ready);
    return true;
  }

 private:
  static constexpr std::size_t kBatchSteps = 256;

  void handOver(bool last) {
    {
      std::lock_guard lock(m_mutex);
      if (m_ready.empty()) std::swap(m_ready, m_filling);
      else m_ready.append(m_filling);  // the assembler is behind
      m_closed = last;
    }
    m_changed.notify_one();
    m_filling.clear();
  }

  std::span<const std::uint32_t> m_originalOf;
  StepBatch m_filling;  // the builder's thread only
  std::mutex m_mutex;
  std::condition_variable m_changed;
  StepBatch m_ready;  // guarded by m_mutex
  bool m_closed = false;
};

// Runs build(listener) -> Result<SimplificationSteps> with the assembler on a second thread.
template <class Build>
Result<ProgressiveMesh> buildAndAssemble(const TriangleMesh& mesh, const RegionPartition& partition,
                                         const Build& build) {
  StepHandover handover;
  std::optional<Result<ProgressiveMesh>> assembled;
  std::exception_ptr assemblerFailure;
  auto assemble = [&] {
    try {
      ProgressiveMeshAssembler assembler(mesh, partition);
      Status status = assembler.begin();
      StepBatch batch;
      while (handover.take(batch)) {
        for (std::size_t s = 0; s < batch.size() && status; ++s) {
          const std::span<const std::uint32_t> removed(batch.removed.data() + batch.removedBegin[s],
                                                       batch.removedBegin[s + 1] - batch.removedBegin[s]);
          const std::span<const std::uint32_t> onto(batch.onto.data() + batch.removedBegin[s], removed.size());
          status = assembler.addStep(batch.representative[s], removed, onto, batch.error[s]);
        }
        batch.clear();
      }
      if (status) assembled.emplace(assembler.finish());
      else assembled.emplace(status.error());
    } catch (...) {
      assemblerFailure = std::current_exception();
      StepBatch rest;  // keep draining so the builder's side is never left waiting
      while (handover.take(rest)) rest.clear();
    }
  };
  std::thread assembling;
  try {
    assembling = std::thread(assemble);
  } catch (const std::system_error&) {
    Result<SimplificationSteps> steps = build(nullptr);
    if (!steps) return steps.error();
    return ProgressiveMesh::assemble(mesh, partition, *steps);
  }
  std::optional<Result<SimplificationSteps>> steps;
  try {
    steps.emplace(build(&handover));
  } catch (...) {
    handover.close();
    assembling.join();
    throw;
  }
  handover.close();
  assembling.join();
  if (assemblerFailure) std::rethrow_exception(assemblerFailure);
  if (!*steps) return steps->error();
  return std::move(*assembled);
}

}  // namespace

Result<ProgressiveMesh> buildProgressiveMesh(const TriangleMesh& mesh, const RegionPartition& partition,
                                             const CollapseOptions& options) {
  return buildAndAssemble(mesh, partition,
                          [&](StepListener* listener) { return buildCollapseSteps(mesh, partition, options, listener); });
}

Result<ProgressiveMesh> buildProgressiveMesh(const TriangleMesh& mesh, const RegionPartition& partition,
                                             const ClusterOptions& options) {
  return buildAndAssemble(mesh, partition,
                          [&](StepListener* listener) { return buildClusterSteps(mesh, partition, options, listener); });
}

}  // namespace polder::mesh
