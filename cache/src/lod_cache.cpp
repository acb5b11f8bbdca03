// The LOD cache: per-block meshes under a byte budget, reused by the block-level test of
// lod_reuse.hpp. Follows Chuang, "Level-of-Detail Modeling Technique for Virtual Reality (I)", 2001, part B, "LOD
// caching".
//
// Storage. Blocks live in slots that never move (callers hold references to their meshes),
// threaded on an intrusive LRU list and found through an open-addressing index, so that
// neither a lookup, a rebuild, nor an eviction that hands its slot to a new block allocates:
// memory is taken only when the cache grows past the most blocks it has held, or a mesh past
// the largest it has held.
#include <polder/cache/lod_cache.hpp>

#include <cassert>
#include <utility>

#include <polder/mix_bits.hpp>

namespace polder::cache {

using terrain::BlockLod;
using terrain::BlockMesh;
using terrain::LodView;
using terrain::NodeId;

namespace {

// What a slot's mesh was extracted for.
enum class BuiltFor : std::uint8_t { View, Count, Uncached };

std::uint64_t hashNode(NodeId node) {
  // splitmix64's finaliser over the packed id: neighbouring blocks land far apart.
  return mixBits((std::uint64_t(node.bx) << 32 | node.by) ^ (std::uint64_t(node.level) * 0x9e3779b97f4a7c15ull));
}

}  // namespace

std::size_t meshBytes(const BlockMesh& mesh) {
  std::size_t bytes =
      mesh.vertices.capacity() * sizeof(terrain::GridVertex) + mesh.indices.capacity() * sizeof(std::uint32_t);
  for (const auto& side : mesh.edges) bytes += side.capacity() * sizeof(std::uint32_t);
  return bytes;
}

struct LodCache::Slot {
  NodeId node;
  bool used = false;
  std::uint32_t prev = kNone;  // towards the most recently used
  std::uint32_t next = kNone;
  std::uint64_t lastFrame = 0;
  std::size_t bytes = 0;  // meshBytes(mesh) as counted in m_bytes

  // What the mesh was built from.
  BuiltFor built = BuiltFor::Uncached;
  terrain::BlockFootprint footprint;
  int cellsX = 0;
  int cellsY = 0;
  float lodMaxError = 0.0f;
  std::size_t countTarget = 0;  // acquireCount: the target t0 ...
  std::size_t countLow = 0;     // ... and the least target that gives the same mesh
  LodSummary summary;           // acquire: the reuse test's summary
  terrain::BoundaryPins pins;   // acquire: side vertices the mesh must keep (pin())
  bool pinsChanged = false;     // pins were added since the mesh was built

  BlockMesh mesh;

  void record(const BlockLod& lod) {
    footprint = lod.footprint();
    cellsX = lod.cellsX();
    cellsY = lod.cellsY();
    lodMaxError = lod.maxError();
  }
  // A cheap fingerprint: a different footprint or clipping means other data for sure.
  bool sameBlock(const BlockLod& lod) const {
    const terrain::BlockFootprint& fp = lod.footprint();
    return fp.x0 == footprint.x0 && fp.y0 == footprint.y0 && fp.k == footprint.k && fp.stride == footprint.stride &&
           lod.cellsX() == cellsX && lod.cellsY() == cellsY && lod.maxError() == lodMaxError;
  }
};

LodCache::LodCache(const LodCacheOptions& options) : m_options(options) {
  assert(options.reuse.fineFactor > 1.0 && "LodCache: reuse.fineFactor must exceed 1");
  assert(options.countHysteresis >= 0.0 && "LodCache: countHysteresis must not be negative");
  assert(options.headroom >= 0.0 && "LodCache: headroom must not be negative");
}

LodCache::~LodCache() = default;
LodCache::LodCache(LodCache&&) noexcept = default;
LodCache& LodCache::operator=(LodCache&&) noexcept = default;

void LodCache::beginFrame() {
  ++m_frame;
  // Last frame's blocks are no longer pinned: a frame that went over the budget returns under it.
  evictToBudget(kNone);
}

double LodCache::reuseRate() const {
  return m_counters.lookups == 0 ? 0.0 : double(m_counters.hits) / double(m_counters.lookups);
}

// ---- acquire ----------------------------------------------------------------------------

std::uint32_t LodCache::lookUp(NodeId node, bool& cached) {
  ++m_counters.lookups;
  const std::uint32_t index = findSlot(node);
  cached = index != kNone;
  if (!cached) return takeSlot(node);
  touch(index);
  return index;
}

const BlockMesh& LodCache::acquire(NodeId node, const BlockLod& lod, const LodView& view, LodOutcome* outcome) {
  bool cached = false;
  const std::uint32_t index = lookUp(node, cached);
  LodOutcome result = LodOutcome::Built;
  if (cached) {
    Slot& slot = *m_slots[index];
    if (!m_options.enabled) {
      result = LodOutcome::RebuiltUncached;
    } else if (!slot.sameBlock(lod)) {
      slot.pins.clear();  // pins were for the old data
      result = LodOutcome::RebuiltChanged;
    } else if (slot.built != BuiltFor::View) {
      result = LodOutcome::RebuiltChanged;
    } else if (slot.pinsChanged) {
      result = LodOutcome::RebuiltPinned;
    } else {
      switch (testLodReuse(slot.summary, view, m_options.reuse)) {
        case LodVerdict::Reuse:
          ++m_counters.hits;
          if (outcome) *outcome = LodOutcome::Reused;
          return slot.mesh;
        case LodVerdict::TooCoarse:
          result = LodOutcome::RebuiltTooCoarse;
          break;
        case LodVerdict::NeedlesslyFine:
          // The camera moved away: the pins were for a nearer view. The frame's dike check
          // pins again what the new view still needs.
          slot.pins.clear();
          result = LodOutcome::RebuiltNeedlesslyFine;
          break;
      }
    }
  }
  Slot& slot = *m_slots[index];
  slot.pinsChanged = false;
  const terrain::BoundaryPins* pins = slot.pins.any() ? &slot.pins : nullptr;
  if (m_options.enabled) {
    // Built a little finer than tau asks (headroom), so the reuse test has slack to spend;
    // the summary vouches for tau itself.
    LodView build = view;
    build.tolerancePx = view.tolerancePx / (1.0 + m_options.headroom);
    lod.extractView(build, slot.mesh, m_scratch, pins);
    summarizeLod(lod, view, slot.mesh, slot.summary);
    slot.built = BuiltFor::View;
  } else {
    lod.extractView(view, slot.mesh, m_scratch, pins);  // the no-cache baseline: extraction only
    slot.built = BuiltFor::Uncached;
  }
  slot.record(lod);
  finishBuild(index, result);
  if (outcome) *outcome = result;
  return slot.mesh;
}

const BlockMesh& LodCache::acquireCount(NodeId node, const BlockLod& lod, std::size_t targetTriangles,
                                        LodOutcome* outcome) {
  bool cached = false;
  const std::uint32_t index = lookUp(node, cached);
  LodOutcome result = LodOutcome::Built;
  if (cached) {
    Slot& slot = *m_slots[index];
    if (!m_options.enabled) {
      result = LodOutcome::RebuiltUncached;
    } else if (slot.built == BuiltFor::Count && slot.sameBlock(lod) && targetTriangles >= slot.countLow &&
               double(targetTriangles) <= double(slot.countTarget) * (1.0 + m_options.countHysteresis)) {
      ++m_counters.hits;
      if (outcome) *outcome = LodOutcome::Reused;
      return slot.mesh;
    } else {
      result = LodOutcome::RebuiltChanged;
    }
  }
  Slot& slot = *m_slots[index];
  lod.extractCount(targetTriangles, slot.mesh, m_scratch);
  slot.built = m_options.enabled ? BuiltFor::Count : BuiltFor::Uncached;
  slot.countTarget = targetTriangles;
  // Greedy refinement is a prefix of one split order, cut at the first split past the
  // target: any target from the count reached up to t0 stops at the same split. A mesh over
  // its target is the coarsest, which every smaller target gives too.
  const std::size_t count = slot.mesh.triangleCount();
  slot.countLow = count > targetTriangles ? 0 : count;
  slot.record(lod);
  finishBuild(index, result);
  if (outcome) *outcome = result;
  return slot.mesh;
}

void LodCache::finishBuild(std::uint32_t index, LodOutcome outcome) {
  Slot& slot = *m_slots[index];
  slot.mesh.revision = ++m_builds;
  const std::size_t bytes = meshBytes(slot.mesh);
  m_bytes = m_bytes - slot.bytes + bytes;
  slot.bytes = bytes;
  ++m_counters.rebuilds;
  switch (outcome) {
    case LodOutcome::Built:
      ++m_counters.built;
      break;
    case LodOutcome::RebuiltTooCoarse:
      ++m_counters.tooCoarse;
      break;
    case LodOutcome::RebuiltNeedlesslyFine:
      ++m_counters.needlesslyFine;
      break;
    case LodOutcome::RebuiltChanged:
      ++m_counters.changed;
      break;
    case LodOutcome::RebuiltPinned:
      ++m_counters.pinned;
      break;
    case LodOutcome::RebuiltUncached:
      ++m_counters.uncached;
      break;
    case LodOutcome::Reused:
      assert(false && "LodCache::finishBuild: a reuse is not a build");
      break;
  }
  evictToBudget(index);
}

// ---- queries and maintenance ------------------------------------------------------------

const BlockMesh* LodCache::find(NodeId node) const {
  const std::uint32_t index = findSlot(node);
  return index == kNone ? nullptr : &m_slots[index]->mesh;
}

bool LodCache::invalidate(NodeId node) {
  const std::uint32_t index = findSlot(node);
  if (index == kNone) return false;
  drop(index, false);
  return true;
}

bool LodCache::pin(NodeId node, terrain::BlockEdge side, int from, int to) {
  const std::uint32_t index = findSlot(node);
  if (index == kNone) return false;
  Slot& slot = *m_slots[index];
  if (!slot.pins.pin(side, from, to)) return false;
  slot.pinsChanged = true;
  return true;
}

const terrain::BoundaryPins* LodCache::pins(NodeId node) const {
  const std::uint32_t index = findSlot(node);
  return index == kNone ? nullptr : &m_slots[index]->pins;
}

void LodCache::clear() {
  while (m_head != kNone) drop(m_head, false);
}

void LodCache::setReuseOptions(const LodReuseOptions& reuse) {
  assert(reuse.fineFactor > 1.0 && "LodCache::setReuseOptions: fineFactor must exceed 1");
  m_options.reuse = reuse;
}

void LodCache::setBudget(std::size_t budgetBytes) {
  m_options.budgetBytes = budgetBytes;
  evictToBudget(kNone);
}

// ---- slots, LRU list and eviction --------------------------------------------------------

std::uint32_t LodCache::takeSlot(NodeId node) {
  std::uint32_t index = kNone;
  // A cache at its budget hands the least recently used block's slot, memory included, to
  // the new block: the usual case while flying, and allocation-free.
  const std::size_t expected = m_size == 0 ? 0 : m_bytes / m_size;
  if (m_tail != kNone && m_bytes + expected > m_options.budgetBytes && evictable(m_tail, kNone)) {
    index = m_tail;
    drop(index, true);
    ++m_counters.evictions;
  } else if (!m_free.empty()) {
    index = m_free.back();
    m_free.pop_back();
  } else {
    index = std::uint32_t(m_slots.size());
    m_slots.push_back(std::make_unique<Slot>());
    m_free.reserve(m_slots.size());  // so that drop() never allocates
  }
  if (2 * (m_size + 1) > m_index.size()) growIndex(m_size + 1);  // before the new slot counts as used
  Slot& slot = *m_slots[index];
  slot.node = node;
  slot.used = true;
  slot.built = BuiltFor::Uncached;
  slot.pins.clear();
  slot.pinsChanged = false;
  slot.bytes = meshBytes(slot.mesh);
  m_bytes += slot.bytes;
  ++m_size;
  indexInsert(index);
  linkFront(index);
  slot.lastFrame = m_frame;
  return index;
}

void LodCache::drop(std::uint32_t index, bool keepMemory) {
  Slot& slot = *m_slots[index];
  assert(slot.used && "LodCache::drop: slot not in use");
  unlink(index);
  indexErase(index);
  m_bytes -= slot.bytes;
  --m_size;
  slot.used = false;
  slot.bytes = 0;
  if (!keepMemory) {
    slot.mesh = BlockMesh{};
    m_free.push_back(index);
  }
}

bool LodCache::evictable(std::uint32_t index, std::uint32_t protect) const {
  // Blocks acquired this frame may be drawn this frame: their references must hold.
  return index != protect && !(m_frame != 0 && m_slots[index]->lastFrame == m_frame);
}

void LodCache::evictToBudget(std::uint32_t protect) {
  // Every acquire moves its block to the front, so once the tail is pinned all are.
  while (m_bytes > m_options.budgetBytes && m_tail != kNone && evictable(m_tail, protect)) {
    drop(m_tail, false);
    ++m_counters.evictions;
  }
}

void LodCache::linkFront(std::uint32_t index) {
  Slot& slot = *m_slots[index];
  slot.prev = kNone;
  slot.next = m_head;
  if (m_head != kNone) m_slots[m_head]->prev = index;
  m_head = index;
  if (m_tail == kNone) m_tail = index;
}

void LodCache::unlink(std::uint32_t index) {
  Slot& slot = *m_slots[index];
  if (slot.prev != kNone)
    m_slots[slot.prev]->next = slot.next;
  else
    m_head = slot.next;
  if (slot.next != kNone)
    m_slots[slot.next]->prev = slot.prev;
  else
    m_tail = slot.prev;
  slot.prev = slot.next = kNone;
}

void LodCache::touch(std::uint32_t index) {
  m_slots[index]->lastFrame = m_frame;
  if (m_head == index) return;
  unlink(index);
  linkFront(index);
}

// ---- index: linear probing with backward-shift deletion (no tombstones) ------------------

std::uint32_t LodCache::findSlot(NodeId node) const {
  if (m_index.empty()) return kNone;
  const std::size_t mask = m_index.size() - 1;
  for (std::size_t pos = hashNode(node) & mask;; pos = (pos + 1) & mask) {
    const std::uint32_t index = m_index[pos];
    if (index == kNone) return kNone;
    if (m_slots[index]->node == node) return index;
  }
}

void LodCache::indexInsert(std::uint32_t index) {
  const std::size_t mask = m_index.size() - 1;
  std::size_t pos = hashNode(m_slots[index]->node) & mask;
  while (m_index[pos] != kNone) pos = (pos + 1) & mask;
  m_index[pos] = index;
}

void LodCache::indexErase(std::uint32_t index) {
  const std::size_t mask = m_index.size() - 1;
  std::size_t pos = hashNode(m_slots[index]->node) & mask;
  while (m_index[pos] != index) pos = (pos + 1) & mask;
  m_index[pos] = kNone;
  // Pull back every later entry of the run that may live at the hole (its home is not
  // cyclically between the hole and itself), so lookups never stop early.
  for (std::size_t next = (pos + 1) & mask; m_index[next] != kNone; next = (next + 1) & mask) {
    const std::size_t home = hashNode(m_slots[m_index[next]]->node) & mask;
    if (((next - home) & mask) >= ((next - pos) & mask)) {
      m_index[pos] = m_index[next];
      m_index[next] = kNone;
      pos = next;
    }
  }
}

void LodCache::growIndex(std::size_t blocks) {
  std::size_t size = m_index.empty() ? 16 : 2 * m_index.size();
  while (size < 2 * blocks) size *= 2;
  m_index.assign(size, kNone);
  for (std::uint32_t index = 0; index < m_slots.size(); ++index)
    if (m_slots[index]->used) indexInsert(index);
}

}  // namespace polder::cache
