#include "block_lod_loader.hpp"

#include <algorithm>
#include <chrono>

namespace polder {

BlockLodLoader::BlockLodLoader(int threads, Build build, std::size_t reserve, std::size_t maxHeldBytes)
    : m_build(std::move(build)), m_reserve(reserve), m_maxHeldBytes(maxHeldBytes) {
  threads = std::max(threads, 1);
  m_pending.reserve(reserve);
  m_building.reserve(std::size_t(threads));
  m_finished.reserve(reserve);
  m_threads.reserve(std::size_t(threads));
  for (int i = 0; i < threads; ++i) m_threads.emplace_back([this] { work(); });
}

BlockLodLoader::~BlockLodLoader() {
  {
    std::lock_guard lock(m_mutex);
    m_stopping = true;
  }
  m_wake.notify_all();
  for (std::thread& thread : m_threads) thread.join();
}

bool BlockLodLoader::post(std::vector<BlockLodRequest>& requests) {
  {
    std::unique_lock lock(m_mutex, std::try_to_lock);
    if (!lock.owns_lock()) return false;
    std::sort(requests.begin(), requests.end(),
              [](const BlockLodRequest& a, const BlockLodRequest& b) { return a.priority > b.priority; });
    if (requests.size() > m_reserve) requests.resize(m_reserve);
    m_pending.swap(requests);
    requests.clear();
    m_next = 0;
  }
  if (!m_pending.empty()) m_wake.notify_all();
  return true;
}

bool BlockLodLoader::collect(std::vector<LoadedBlockLod>& finished) {
  {
    std::unique_lock lock(m_mutex, std::try_to_lock);
    if (!lock.owns_lock()) return false;
    m_finished.swap(finished);
    m_finishedBytes = 0;
  }
  if (!finished.empty()) m_wake.notify_all();  // room again under maxHeldBytes
  return true;
}

void BlockLodLoader::waitIdle() {
  std::unique_lock lock(m_mutex);
  m_changed.wait(lock, [&] { return m_building.empty() && !nextAvailable(); });
}

bool BlockLodLoader::idle() const {
  std::lock_guard lock(m_mutex);
  return m_building.empty() && m_next == m_pending.size();
}

bool BlockLodLoader::nextAvailable() {
  // The most wanted request that no other thread builds and that is not waiting to be
  // collected.
  const auto taken = [&](const terrain::NodeId& node) {
    if (std::find(m_building.begin(), m_building.end(), node) != m_building.end()) return true;
    return std::any_of(m_finished.begin(), m_finished.end(),
                       [&](const LoadedBlockLod& done) { return done.node == node; });
  };
  while (m_next < m_pending.size() && taken(m_pending[m_next].node)) ++m_next;
  return m_next < m_pending.size() && m_finishedBytes < m_maxHeldBytes;
}

void BlockLodLoader::work() {
  std::unique_lock lock(m_mutex);
  for (;;) {
    m_wake.wait(lock, [&] { return m_stopping || nextAvailable(); });
    if (m_stopping) break;
    const terrain::NodeId node = m_pending[m_next++].node;
    m_building.push_back(node);
    lock.unlock();

    LoadedBlockLod loaded;
    loaded.node = node;
    const auto start = std::chrono::steady_clock::now();
    try {
      auto built = m_build(node);
      if (built)
        loaded.lod = std::make_unique<ResidentBlock>(std::move(*built));
      else
        loaded.error = built.error().message;
    } catch (const std::exception& failure) {  // out of memory, mostly: the node stays unloaded
      loaded.error = failure.what();
    }
    loaded.buildMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();

    const std::size_t bytes = loaded.lod ? loaded.lod->memoryBytes() : 0;

    lock.lock();
    m_building.erase(std::find(m_building.begin(), m_building.end(), node));
    m_finishedBytes += bytes;
    m_finished.push_back(std::move(loaded));
    m_changed.notify_all();
  }
}

}  // namespace polder
