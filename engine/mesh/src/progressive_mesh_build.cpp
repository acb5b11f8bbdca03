#include "polder/mesh/progressive_mesh_build.hpp"

#include <mutex>
#include <optional>

#include "halves.hpp"
#include "polder/thread_pool.hpp"
#include "progressive_mesh_assembler.hpp"
#include "step_listener.hpp"

namespace polder::mesh {

namespace {

// The builder's side fills a batch with each step, renamed to the caller's ids, and hands
// full batches over; the assembler's side replays them in a background task that runs while
// batches are waiting and ends when none is (it never waits, so it never holds a thread the
// builder could use). Batches keep the locking rare (a step takes a few microseconds).
class StepHandover final : public StepListener {
 public:
  StepHandover(ProgressiveMeshAssembler& assembler, core::ThreadPool& pool)
      : m_assembler(assembler), m_fewCores(pool.threadCount() <= 2) {}

  void startOn(core::ThreadPool::Background& background) { m_background = &background; }

  void renumbered(std::span<const std::uint32_t> originalOf) override { m_originalOf = originalOf; }

  void stepTaken(const SimplificationSteps& steps) override {
    m_filling.addCopyOf(steps, steps.size() - 1);
    const std::size_t s = m_filling.size() - 1;
    m_filling.representative[s] = m_originalOf[m_filling.representative[s]];
    for (std::size_t i = m_filling.removedBegin[s]; i < m_filling.removed.size(); ++i)
      m_filling.removed[i] = m_originalOf[m_filling.removed[i]], m_filling.onto[i] = m_originalOf[m_filling.onto[i]];
    if (m_filling.size() >= kBatchSteps) handOver();
  }

  // While the builder's halves fill both cores of a two-core machine, the assembler waits:
  // taking a core from one of them would hold up both, since they meet after every round
  // (on the bunny, the cluster build's whole sequence takes 61-65 ms instead of 68-73).
  void builderOnTwoCores(bool busy) override {
    bool start = false;
    {
      std::lock_guard lock(m_mutex);
      m_builderHoldsTheCores = busy && m_fewCores;
      start = claimReplay();
    }
    if (start) startReplay();
  }

  // The builder is done (or failed): the last batch goes over.
  void close() {
    handOver();
    std::lock_guard lock(m_mutex);
    m_builderHoldsTheCores = false;
  }

  // After the build and every replay task ended: replays what is left, and the result.
  Status finishReplay() {
    replay();
    return m_status;
  }

 private:
  static constexpr std::size_t kBatchSteps = 256;

  void handOver() {
    if (m_filling.size() == 0) return;
    bool start = false;
    {
      std::lock_guard lock(m_mutex);
      if (m_ready.size() == 0)
        std::swap(m_ready, m_filling);
      else  // the assembler is behind
        for (std::size_t s = 0; s < m_filling.size(); ++s) m_ready.addCopyOf(m_filling, s);
      start = claimReplay();
    }
    m_filling.clear();
    if (start) startReplay();
  }

  // Under m_mutex: whether a replay task should start now (and, if so, that one runs).
  bool claimReplay() {
    if (m_replaying || m_ready.size() == 0 || m_builderHoldsTheCores || !m_background) return false;
    m_replaying = true;
    return true;
  }

  void startReplay() {
    m_background->start([this] { replay(); });
  }

  // Replays the waiting batches until none is left or the builder wants both cores; one
  // replay runs at a time (m_replaying, cleared together with finding nothing to do).
  void replay() {
    for (;;) {
      {
        std::lock_guard lock(m_mutex);
        if (m_ready.size() == 0 || m_builderHoldsTheCores) {
          m_replaying = false;
          return;
        }
        std::swap(m_taken, m_ready);
      }
      for (std::size_t s = 0; s < m_taken.size() && m_status; ++s)
        m_status =
            m_assembler.addStep(m_taken.representative[s], m_taken.removedBy(s), m_taken.ontoBy(s), m_taken.error[s]);
      m_taken.clear();
    }
  }

  ProgressiveMeshAssembler& m_assembler;
  const bool m_fewCores;
  core::ThreadPool::Background* m_background = nullptr;
  std::span<const std::uint32_t> m_originalOf;
  SimplificationSteps m_filling;  // the builder's thread only, in the caller's ids
  SimplificationSteps m_taken;    // the running replay's only
  Status m_status;                // the running replay's only
  std::mutex m_mutex;
  SimplificationSteps m_ready;          // guarded by m_mutex
  bool m_replaying = false;             // guarded by m_mutex
  bool m_builderHoldsTheCores = false;  // guarded by m_mutex
};

// Runs build(listener, pool) -> Result<SimplificationSteps> on the calling thread with the
// assembler replaying its steps in the background meanwhile (or after it, where no other
// thread is free: the builder never waits for the assembler).
template <class Build>
Result<ProgressiveMesh> buildAndAssemble(const TriangleMesh& mesh, const RegionPartition& partition, int threads,
                                         const Build& build) {
  core::ThreadPool pool(threads);
  ProgressiveMeshAssembler assembler(mesh, partition);
  // Where the assembler refuses the input, the builder still runs (alone), so that the
  // error reported is the builder's where it has one.
  const Status begun = assembler.begin();
  StepHandover handover(assembler, pool);
  std::optional<Result<SimplificationSteps>> steps;
  pool.runWithBackground([&](core::ThreadPool::Background& background) {
    handover.startOn(background);
    try {
      steps.emplace(build(begun ? &handover : nullptr, pool));
    } catch (...) {
      handover.close();
      throw;
    }
    handover.close();
  });
  if (!*steps) return steps->error();
  if (!begun) return begun.error();
  if (Status replayed = handover.finishReplay(); !replayed) return replayed.error();
  return assembler.finish(pool);
}

}  // namespace

Result<ProgressiveMesh> buildProgressiveMesh(const TriangleMesh& mesh, const RegionPartition& partition,
                                             const CollapseOptions& options) {
  return buildAndAssemble(mesh, partition, options.threads, [&](StepListener* listener, core::ThreadPool& pool) {
    return buildCollapseSteps(mesh, partition, options, listener, pool);
  });
}

Result<ProgressiveMesh> buildProgressiveMesh(const TriangleMesh& mesh, const RegionPartition& partition,
                                             const ClusterOptions& options) {
  return buildAndAssemble(mesh, partition, options.threads, [&](StepListener* listener, core::ThreadPool& pool) {
    return buildClusterSteps(mesh, partition, options, listener, pool);
  });
}

}  // namespace polder::mesh
