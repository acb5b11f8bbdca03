#include "polder/mesh/progressive_mesh_build.hpp"

#include <condition_variable>
#include <mutex>
#include <optional>
#include <thread>

#include "paired_work.hpp"
#include "progressive_mesh_assembler.hpp"
#include "step_listener.hpp"

namespace polder::mesh {

namespace {

// The builder's side fills a batch with each step, renamed to the caller's ids, and hands
// full batches over; the assembler's side waits for them. Batches keep the locking rare
// (a step takes a few microseconds).
class StepHandover final : public StepListener {
 public:
  void renumbered(std::span<const std::uint32_t> originalOf) override { m_originalOf = originalOf; }

  void stepTaken(const SimplificationSteps& steps) override {
    m_filling.addCopyOf(steps, steps.size() - 1);
    const std::size_t s = m_filling.size() - 1;
    m_filling.representative[s] = m_originalOf[m_filling.representative[s]];
    for (std::size_t i = m_filling.removedBegin[s]; i < m_filling.removed.size(); ++i)
      m_filling.removed[i] = m_originalOf[m_filling.removed[i]], m_filling.onto[i] = m_originalOf[m_filling.onto[i]];
    if (m_filling.size() >= kBatchSteps) handOver(false);
  }

  // While the builder's threads fill both cores of a two-core machine, the assembler waits:
  // taking a core from one of them would hold up both, since they meet after every round
  // (on the bunny, the cluster build's whole sequence takes 61-65 ms instead of 68-73).
  void builderOnTwoCores(bool busy) override {
    {
      std::lock_guard lock(m_mutex);
      m_builderHoldsTheCores = busy && m_fewCores;
    }
    m_changed.notify_one();
  }

  // The builder is done (or failed): the last batch goes over.
  void close() { handOver(true); }

  // Waits for the next batch (into `batch`, which must be empty) and for a free core; false
  // once the builder is done and everything was taken.
  bool take(SimplificationSteps& batch) {
    std::unique_lock lock(m_mutex);
    m_changed.wait(lock, [&] { return (m_ready.size() > 0 && !m_builderHoldsTheCores) || m_closed; });
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
      else  // the assembler is behind
        for (std::size_t s = 0; s < m_filling.size(); ++s) m_ready.addCopyOf(m_filling, s);
      m_closed = last;
    }
    m_changed.notify_one();
    m_filling.clear();
  }

  std::span<const std::uint32_t> m_originalOf;
  SimplificationSteps m_filling;        // the builder's thread only, in the caller's ids
  std::mutex m_mutex;
  std::condition_variable m_changed;
  SimplificationSteps m_ready;  // guarded by m_mutex
  bool m_closed = false;
  bool m_builderHoldsTheCores = false;  // guarded by m_mutex
  const bool m_fewCores = std::thread::hardware_concurrency() <= 2;
};

// Runs build(listener) -> Result<SimplificationSteps> with the assembler on a second thread
// (or after it, where no second thread starts: the builder never waits for the assembler).
template <class Build>
Result<ProgressiveMesh> buildAndAssemble(const TriangleMesh& mesh, const RegionPartition& partition,
                                         const Build& build) {
  StepHandover handover;
  std::optional<Result<SimplificationSteps>> steps;
  std::optional<Result<ProgressiveMesh>> assembled;
  auto buildSteps = [&] {
    try {
      steps.emplace(build(&handover));
    } catch (...) {
      handover.close();  // the assembler waits for it
      throw;
    }
    handover.close();
  };
  auto assemble = [&] {
    ProgressiveMeshAssembler assembler(mesh, partition);
    Status status = assembler.begin();
    SimplificationSteps batch;
    while (handover.take(batch)) {
      for (std::size_t s = 0; s < batch.size() && status; ++s)
        status = assembler.addStep(batch.representative[s], batch.removedBy(s), batch.ontoBy(s), batch.error[s]);
      batch.clear();
    }
    if (status) assembled.emplace(assembler.finish());
    else assembled.emplace(status.error());
  };
  PairedWork().run([&](int half) { half == 0 ? buildSteps() : assemble(); });
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
