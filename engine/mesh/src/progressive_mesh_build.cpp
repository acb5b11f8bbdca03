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

// Empties a batch of steps, keeping its room.
void clearSteps(SimplificationSteps& steps) {
  steps.representative.clear(), steps.removed.clear(), steps.onto.clear(), steps.error.clear();
  steps.removedBegin.assign(1, 0);
}

// Appends the steps of `more` to `steps`.
void appendSteps(SimplificationSteps& steps, const SimplificationSteps& more) {
  for (std::size_t s = 0; s < more.size(); ++s) steps.addCopyOf(more, s);
}

// The builder's side fills a batch with each step, renamed to the caller's ids, and hands
// full batches over; the assembler's side waits for them. Batches keep the locking rare
// (a step takes a few microseconds).
class StepHandover final : public StepListener {
 public:
  void renumbered(std::span<const std::uint32_t> originalOf) override { m_originalOf = originalOf; }

  void stepTaken(const SimplificationSteps& steps) override {
    const std::size_t s = steps.size() - 1;
    m_renamed.clear();
    for (std::uint32_t v : steps.removedBy(s)) m_renamed.push_back(m_originalOf[v]);
    for (std::uint32_t v : steps.ontoBy(s)) m_renamed.push_back(m_originalOf[v]);
    const std::span<const std::uint32_t> renamed(m_renamed);
    const std::size_t count = renamed.size() / 2;
    m_filling.add(m_originalOf[steps.representative[s]], renamed.first(count), renamed.last(count), steps.error[s]);
    if (m_filling.size() >= kBatchSteps) handOver(false);
  }

  // The builder is done (or failed): the last batch goes over.
  void close() { handOver(true); }

  // Waits for the next batch (into `batch`, which must be empty); false once the builder is
  // done and everything was taken.
  bool take(SimplificationSteps& batch) {
    std::unique_lock lock(m_mutex);
    m_changed.wait(lock, [&] { return m_ready.size() > 0 || m_closed; });
    if (m_ready.size() == 0) return false;
    std::swap(batch, m_ready);
    return true;
  }

 private:
  static constexpr std::size_t kBatchSteps = 256;

  void handOver(bool last) {
    {
      std::lock_guard lock(m_mutex);
      if (m_ready.size() == 0) std::swap(m_ready, m_filling);
      else appendSteps(m_ready, m_filling);  // the assembler is behind
      m_closed = last;
    }
    m_changed.notify_one();
    clearSteps(m_filling);
  }

  std::span<const std::uint32_t> m_originalOf;
  SimplificationSteps m_filling;        // the builder's thread only, in the caller's ids
  std::vector<std::uint32_t> m_renamed;  // stepTaken's room: removed, then onto
  std::mutex m_mutex;
  std::condition_variable m_changed;
  SimplificationSteps m_ready;  // guarded by m_mutex
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
      SimplificationSteps batch;
      while (handover.take(batch)) {
        for (std::size_t s = 0; s < batch.size() && status; ++s)
          status = assembler.addStep(batch.representative[s], batch.removedBy(s), batch.ontoBy(s), batch.error[s]);
        clearSteps(batch);
      }
      if (status) assembled.emplace(assembler.finish());
      else assembled.emplace(status.error());
    } catch (...) {
      assemblerFailure = std::current_exception();
      SimplificationSteps rest;  // keep draining so the builder's side is never left waiting
      while (handover.take(rest)) clearSteps(rest);
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
