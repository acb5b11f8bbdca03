// Builds blocks' error hierarchies (BlockLod) on loader threads of its own, so that the
// frame thread never builds one (docs/streaming.md "Run time"). Its own threads, not tasks
// on the engine's oneTBB workers: a frame keeps those workers in its arena from one frame to
// the next, and a task left for them there would wait until the frame thread next blocks.
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
#include <string>
#include <thread>
#include <vector>

#include <polder/result.hpp>
#include <polder/terrain/block_layout.hpp>
#include <polder/terrain/rtin.hpp>

#include "resident_block.hpp"

namespace polder {

struct BlockLodRequest {
  terrain::NodeId node;
  double priority = 0.0;  // higher first: the projected error the node's absence leaves, px
};

struct LoadedBlockLod {
  terrain::NodeId node;
  std::unique_ptr<ResidentBlock> lod;  // null when the build failed
  std::string error;                   // why, when it failed
  double buildMs = 0.0;
};

class BlockLodLoader {
 public:
  // Runs on the workers, any number at once, for one node at a time.
  using Build = std::function<Result<ResidentBlock>(const terrain::NodeId&)>;

  // `threads`: how many builds run at once (at least one). `reserve`: the most requests one
  // post carries (more are dropped, least wanted first). `maxHeldBytes`: no build starts while
  // the finished builds not yet collected hold that many bytes (ResidentBlock::memoryBytes),
  // so that a frame thread slow to collect, or one that turns blocks away, leaves at most
  // that plus the builds under way in memory.
  BlockLodLoader(int threads, Build build, std::size_t reserve, std::size_t maxHeldBytes);
  // Stops taking requests, waits for the builds under way and ends the threads.
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

  // Blocks until no build is under way and none pending can start (none left, or
  // maxHeldBytes held): for single pictures and tests, never in a frame.
  void waitIdle();
  bool idle() const;

 private:
  void work();
  // Under m_mutex: moves m_next past requests already built or being built; true when one
  // is left to take and the finished builds hold less than maxHeldBytes.
  bool nextAvailable();

  Build m_build;
  std::size_t m_reserve;
  std::size_t m_maxHeldBytes;

  mutable std::mutex m_mutex;
  std::condition_variable m_wake;          // work posted, or stopping
  std::condition_variable m_changed;       // a build ended
  std::vector<BlockLodRequest> m_pending;  // most wanted first
  std::size_t m_next = 0;                  // first request of m_pending not yet taken
  std::vector<terrain::NodeId> m_building;
  std::vector<LoadedBlockLod> m_finished;
  std::size_t m_finishedBytes = 0;
  bool m_stopping = false;
  std::vector<std::thread> m_threads;  // last: they start once the rest is made
};

}  // namespace polder
