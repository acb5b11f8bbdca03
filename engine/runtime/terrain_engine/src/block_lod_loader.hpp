// Builds blocks' error hierarchies (BlockLod) on the engine's worker threads, so that the
// frame thread never builds one (docs/streaming.md "Run time").
//
// The frame thread posts, once a frame, the nodes it wants, most wanted first; the list
// replaces the last one, so a node the camera has left behind is never built. Workers take
// the most wanted node not already being built, build it, and leave it in a finished list
// that the frame thread collects at the start of its next frame. Both hand-offs swap vectors
// under a mutex the frame thread only ever try-locks: when a worker holds it (for the few
// instructions of a push or a pop) the frame goes on and hands off next frame, so the frame
// thread never waits for a loader, and with both sides' vectors reserved it never allocates.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <vector>

#include <polder/result.hpp>
#include <polder/terrain/block_layout.hpp>
#include <polder/terrain/rtin.hpp>
#include <polder/thread_pool.hpp>

namespace polder {

struct BlockLodRequest {
  terrain::NodeId node;
  double priority = 0.0;  // higher first: the projected error the node's absence leaves, px
};

struct LoadedBlockLod {
  terrain::NodeId node;
  std::unique_ptr<terrain::BlockLod> lod;  // null when the build failed
  std::string error;                       // why, when it failed
  double buildMs = 0.0;
};

class BlockLodLoader {
 public:
  // Runs on the workers, any number at once, for one node at a time.
  using Build = std::function<Result<terrain::BlockLod>(const terrain::NodeId&)>;

  // `reserve`: the most requests one post carries (more are dropped, least wanted first).
  BlockLodLoader(core::ThreadPool& pool, Build build, std::size_t reserve);
  // Stops taking requests and waits for the builds under way.
  ~BlockLodLoader();
  BlockLodLoader(const BlockLodLoader&) = delete;
  BlockLodLoader& operator=(const BlockLodLoader&) = delete;

  // Frame thread. Sorts `requests` (most wanted first) and makes them the loader's work,
  // handing back the previous list in `requests`, cleared. false, with `requests` as it was,
  // when a worker held the hand-off: post again next frame.
  bool post(std::vector<BlockLodRequest>& requests);
  // Frame thread. Swaps the finished builds into `finished` (which must be empty); false when
  // a worker held the hand-off.
  bool collect(std::vector<LoadedBlockLod>& finished);

  // Blocks until no build is pending or under way: for single pictures and tests, never in
  // a frame.
  void waitIdle();
  bool idle() const;

 private:
  void work();
  void startWorkers();

  core::ThreadPool& m_pool;
  Build m_build;
  std::size_t m_reserve;
  int m_maxWorkers;

  mutable std::mutex m_mutex;
  std::condition_variable m_changed;
  std::vector<BlockLodRequest> m_pending;  // most wanted first
  std::size_t m_next = 0;                  // first request of m_pending not yet taken
  std::vector<terrain::NodeId> m_building;
  std::vector<LoadedBlockLod> m_finished;
  int m_workers = 0;  // tasks running work()
  bool m_stopping = false;
};

}  // namespace polder
