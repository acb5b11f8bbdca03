#include "progressive_mesh_assembler.hpp"

#include <algorithm>
#include <functional>
#include <limits>
#include <optional>
#include <string>

#include "builder_setup.hpp"
#include "halves.hpp"
#include "polder/thread_pool.hpp"

namespace polder::mesh {

namespace {

constexpr std::uint32_t kNever = std::numeric_limits<std::uint32_t>::max();
// Below this many triangles finish() stays on one thread: starting a second costs more.
constexpr std::size_t kPairedFinishTriangles = 4096;

// The items 0..count-1 ordered by bucket (stable within a bucket); bucketOf(i) < buckets.
template <class BucketOf>
std::vector<std::uint32_t> countingSort(std::uint32_t count, std::uint32_t buckets, const BucketOf& bucketOf) {
  std::vector<std::uint32_t> start(std::size_t(buckets) + 1, 0);
  for (std::uint32_t i = 0; i < count; ++i) ++start[bucketOf(i) + 1];
  for (std::uint32_t b = 0; b < buckets; ++b) start[b + 1] += start[b];
  std::vector<std::uint32_t> order(count);
  for (std::uint32_t i = 0; i < count; ++i) order[start[bucketOf(i)]++] = i;
  return order;
}

}  // namespace

Status ProgressiveMeshAssembler::begin() {
  if (Status s = validateMesh(m_mesh, "progressive mesh input"); !s) return s;
  if (Status s = validatePartition(m_partition, m_mesh.vertexCount(), "progressive mesh regions"); !s) return s;
  m_removalStep.assign(m_mesh.vertexCount(), kNever);
  m_regionStepCount.assign(m_partition.regionCount, 0);
  m_recorded.resize(m_partition.regionCount);
  m_recordedBegin.assign(m_partition.regionCount, {0});
  m_borderRecorded.resize(m_partition.regionCount);
  m_borderRecordedBegin.assign(m_partition.regionCount, {0});
  collectTriangles();
  return {};
}

Status ProgressiveMeshAssembler::addStep(std::uint32_t rep, std::span<const std::uint32_t> removed,
                                         std::span<const std::uint32_t> onto, float error) {
  if (Status s = checkStep(rep, removed, onto); !s) return s;
  const std::uint32_t region = m_partition.regionOf(rep);
  const std::uint32_t local = m_regionStepCount[region]++;
  m_stepRegion.push_back(region);
  m_localStep.push_back(local);
  m_stepError.push_back(error);
  replayStep(region, local, removed, onto);
  return {};
}

Status ProgressiveMeshAssembler::checkStep(std::uint32_t rep, std::span<const std::uint32_t> removed,
                                           std::span<const std::uint32_t> onto) {
  const std::size_t vertexCount = m_mesh.vertexCount();
  const auto s = static_cast<std::uint32_t>(m_stepRegion.size());
  auto fail = [s](const std::string& problem) {
    return makeError(ErrorKind::InvalidArgument, "simplification step " + std::to_string(s) + ": " + problem);
  };
  if (removed.size() != onto.size()) return fail("removed and onto differ in length");
  if (rep >= vertexCount) return fail("representative out of range");
  if (m_removalStep[rep] != kNever) return fail("representative " + std::to_string(rep) + " was removed");
  const std::uint32_t region = m_partition.regionOf(rep);
  for (std::size_t i = 0; i < removed.size(); ++i) {
    const std::uint32_t v = removed[i], target = onto[i];
    if (v >= vertexCount || target >= vertexCount) return fail("vertex out of range");
    if (v == rep || v == target || m_removalStep[v] != kNever)
      return fail("vertex " + std::to_string(v) + " is not active");
    if (m_removalStep[target] != kNever)
      return fail("vertex " + std::to_string(v) + " goes onto vertex " + std::to_string(target) +
                  ", which is not active");
    if (m_partition.regionOf(v) != region || m_partition.regionOf(target) != region)
      return fail("joins vertices of two regions");
    m_removalStep[v] = s;
  }
  for (std::uint32_t target : onto)
    if (m_removalStep[target] == s)
      return fail("vertex " + std::to_string(target) + " is removed and takes a place in one step");
  return {};
}

void ProgressiveMeshAssembler::collectTriangles() {
  m_corners = liveTriangleCorners(m_mesh);
  m_owner.reserve(m_corners.size() / 3);
  for (std::size_t i = 0; i < m_corners.size(); i += 3)
    m_owner.push_back(triangleRegion(m_partition, m_corners[i], m_corners[i + 1], m_corners[i + 2]));
  m_originalCorners = m_corners;
  m_vanishStep.assign(m_owner.size(), kNever);
  // Own corners per vertex; border-table entries for vertices that foreign triangles use.
  m_cornerHead.assign(m_mesh.vertexCount(), kNever);
  m_cornerNext.assign(m_corners.size(), kNever);
  m_entryOf.assign(m_mesh.vertexCount(), kNever);
  m_entryHead.assign(m_mesh.vertexCount(), kNever);
  m_borderVertices.assign(m_partition.regionCount, {});
  for (std::uint32_t k = 0; k < m_corners.size(); ++k) {
    const std::uint32_t v = m_corners[k];
    const std::uint32_t region = m_partition.regionOf(v);
    if (region == m_owner[k / 3]) {
      m_cornerNext[k] = m_cornerHead[v];
      m_cornerHead[v] = k;
    } else if (m_entryOf[v] == kNever) {
      m_entryOf[v] = static_cast<std::uint32_t>(m_borderVertices[region].size());
      m_borderVertices[region].push_back(v);
      m_entryNodes.push_back({m_entryOf[v], m_entryHead[v]});
      m_entryHead[v] = static_cast<std::uint32_t>(m_entryNodes.size() - 1);
    }
  }
}

void ProgressiveMeshAssembler::replayStep(std::uint32_t region, std::uint32_t local,
                                          std::span<const std::uint32_t> removed, std::span<const std::uint32_t> onto) {
  std::vector<RecordedChange>& changes = m_recorded[region];
  const std::size_t changesBefore = changes.size();
  bool anyVanished = false;
  for (std::size_t i = 0; i < removed.size(); ++i) {
    const std::uint32_t v = removed[i], rep = onto[i];
    for (std::uint32_t k = m_cornerHead[v], next; k != kNever; k = next) {
      next = m_cornerNext[k];
      const std::uint32_t t = k / 3;
      if (m_vanishStep[t] != kNever && m_vanishStep[t] != local) continue;  // vanished earlier
      m_corners[k] = rep;
      if (m_vanishStep[t] == kNever) {
        changes.push_back({t, k % 3, v, rep});
        if (hasDegenerated(t)) {
          m_vanishStep[t] = local;
          anyVanished = true;
        }
      }
      m_cornerNext[k] = m_cornerHead[rep];
      m_cornerHead[rep] = k;
    }
    m_cornerHead[v] = kNever;
    for (std::uint32_t node = m_entryHead[v], next; node != kNever; node = next) {
      next = m_entryNodes[node].next;
      m_borderRecorded[region].push_back({m_entryNodes[node].entry, 0, v, rep});
      m_entryNodes[node].next = m_entryHead[rep];
      m_entryHead[rep] = node;
    }
    m_entryHead[v] = kNever;
  }
  if (anyVanished) {
    auto kept = std::remove_if(changes.begin() + static_cast<std::ptrdiff_t>(changesBefore), changes.end(),
                               [&](const RecordedChange& c) { return m_vanishStep[c.triangle] == local; });
    changes.erase(kept, changes.end());
  }
  m_recordedBegin[region].push_back(static_cast<std::uint32_t>(changes.size()));
  m_borderRecordedBegin[region].push_back(static_cast<std::uint32_t>(m_borderRecorded[region].size()));
}

bool ProgressiveMeshAssembler::hasDegenerated(std::uint32_t t) const {
  return isDegenerate(m_corners[3 * t], m_corners[3 * t + 1], m_corners[3 * t + 2]);
}

// The vertex table and the triangles' slots do not depend on each other, nor do the index
// buffers and the changes once both are known: each pair runs as two halves on `pool` (on the bunny
// this is a seventh of a pipelined build, left for after the builder ends).
ProgressiveMesh ProgressiveMeshAssembler::finish(core::ThreadPool& pool) {
  ProgressiveMesh out;
  out.m_stepCount = m_stepRegion.size();
  out.m_regions.resize(m_partition.regionCount);
  Layout layout;
  const bool paired = m_owner.size() >= kPairedFinishTriangles;
  auto inPairs = [&](const auto& half) {
    if (paired) {
      pool.runHalves(half);
    } else {
      half(0);
      half(1);
    }
  };
  inPairs([&](int half) { half == 0 ? layOutVertices(out, layout) : layOutTriangles(out, layout); });
  inPairs([&](int half) { half == 0 ? fillIndexBuffers(out, layout) : translateChanges(out, layout); });
  for (const RegionSequence& seq : out.m_regions)
    out.m_vertices.indices.insert(out.m_vertices.indices.end(), seq.m_fullIndices.begin(), seq.m_fullIndices.end());
  return out;
}

// A removed vertex's local step, or kNever.
std::uint32_t ProgressiveMeshAssembler::removalKey(std::uint32_t v) const {
  return m_removalStep[v] == kNever ? kNever : m_localStep[m_removalStep[v]];
}

// Vertex order: by region, then the vertices removed last first (counting sorts: the keys
// are step numbers, so this stays linear); the vertex table in that order.
void ProgressiveMeshAssembler::layOutVertices(ProgressiveMesh& out, Layout& layout) const {
  const std::uint32_t regionCount = m_partition.regionCount;
  const auto vertexCount = static_cast<std::uint32_t>(m_mesh.vertexCount());
  std::vector<std::uint32_t> regionBucketBase(regionCount + 1, 0);
  for (std::uint32_t r = 0; r < regionCount; ++r)
    regionBucketBase[r + 1] = regionBucketBase[r] + m_regionStepCount[r] + 1;
  // Within a region: never removed first (bucket 0), then the last removed.
  auto vertexBucket = [&](std::uint32_t v) {
    const std::uint32_t r = m_partition.regionOf(v), key = removalKey(v);
    return regionBucketBase[r] + (key == kNever ? 0 : m_regionStepCount[r] - key);
  };
  layout.order = countingSort(vertexCount, regionBucketBase[regionCount], vertexBucket);
  layout.newIndex.resize(vertexCount);
  for (std::uint32_t i = 0; i < vertexCount; ++i) layout.newIndex[layout.order[i]] = i;
  out.m_originalVertex = layout.order;
  out.m_vertexRegion.resize(vertexCount);
  out.m_vertices.positions.resize(vertexCount);
  if (m_mesh.hasNormals()) out.m_vertices.normals.resize(vertexCount);
  if (m_mesh.hasColours()) out.m_vertices.colours.resize(vertexCount);
  if (m_mesh.hasUvs()) out.m_vertices.uvs.resize(vertexCount);
  for (std::uint32_t i = 0; i < vertexCount; ++i) {
    const std::uint32_t v = layout.order[i];
    out.m_vertexRegion[i] = m_partition.regionOf(v);
    out.m_vertices.positions[i] = m_mesh.positions[v];
    if (m_mesh.hasNormals()) out.m_vertices.normals[i] = m_mesh.normals[v];
    if (m_mesh.hasColours()) out.m_vertices.colours[i] = m_mesh.colours[v];
    if (m_mesh.hasUvs()) out.m_vertices.uvs[i] = m_mesh.uvs[v];
  }
}

// Each region's triangles (in the input's order) and their slots: survivors first, then
// those that vanish last; the triangle counts and the (monotone) errors after each step.
void ProgressiveMeshAssembler::layOutTriangles(ProgressiveMesh& out, Layout& layout) const {
  const std::uint32_t regionCount = m_partition.regionCount;
  layout.trianglesOf.assign(regionCount, {});
  for (std::uint32_t t = 0; t < m_owner.size(); ++t) layout.trianglesOf[m_owner[t]].push_back(t);
  layout.slotOf.resize(m_owner.size());
  for (std::uint32_t r = 0; r < regionCount; ++r) {
    RegionSequence& seq = out.m_regions[r];
    const std::size_t stepCount = m_regionStepCount[r];
    seq.m_stepCount = stepCount;
    const std::vector<std::uint32_t>& tris = layout.trianglesOf[r];
    const auto bucket = [&](std::uint32_t i) {
      const std::uint32_t key = m_vanishStep[tris[i]];
      return key == kNever ? 0u : std::uint32_t(stepCount) - key;
    };
    const std::vector<std::uint32_t> sorted =
        countingSort(static_cast<std::uint32_t>(tris.size()), std::uint32_t(stepCount) + 1, bucket);
    for (std::uint32_t i = 0; i < sorted.size(); ++i) layout.slotOf[tris[sorted[i]]] = 3 * i;
    std::vector<std::uint32_t> vanishing(stepCount + 1, 0);
    for (std::uint32_t t : tris) ++vanishing[std::min<std::size_t>(m_vanishStep[t], stepCount)];
    seq.m_trianglesAfterSteps.resize(stepCount + 1);
    auto alive = static_cast<std::uint32_t>(tris.size());
    for (std::size_t m = 0; m <= stepCount; ++m) {
      seq.m_trianglesAfterSteps[m] = alive;
      if (m < stepCount) alive -= vanishing[m];
    }
    seq.m_errorAfterSteps.assign(stepCount + 1, 0.0f);
  }
  std::vector<float> runningError(regionCount, 0.0f);
  for (std::size_t s = 0; s < m_stepRegion.size(); ++s) {
    const std::uint32_t r = m_stepRegion[s];
    runningError[r] = std::max(runningError[r], m_stepError[s]);
    out.m_regions[r].m_errorAfterSteps[m_localStep[s] + 1] = runningError[r];
  }
}

// Each region's full index buffer in slot order, its corners that read a neighbour's
// border table (and the neighbours' reader lists), its vertex range and counts after each
// step, and its border vertices, in the new numbering.
void ProgressiveMeshAssembler::fillIndexBuffers(ProgressiveMesh& out, const Layout& layout) const {
  const std::uint32_t regionCount = m_partition.regionCount;
  const std::size_t vertexCount = m_mesh.vertexCount();
  std::uint32_t vertexCursor = 0;
  for (std::uint32_t r = 0; r < regionCount; ++r) {
    RegionSequence& seq = out.m_regions[r];
    const std::size_t stepCount = m_regionStepCount[r];
    const std::vector<std::uint32_t>& tris = layout.trianglesOf[r];
    // Corners in the input's triangle order: the reads run in order and the writes scatter,
    // which costs less than the other way round.
    seq.m_fullIndices.resize(3 * tris.size());
    for (std::uint32_t t : tris) {
      const std::uint32_t slot = layout.slotOf[t];
      for (std::uint32_t c = 0; c < 3; ++c) {
        const std::uint32_t original = m_originalCorners[3 * t + c];
        seq.m_fullIndices[slot + c] = layout.newIndex[original];
        const std::uint32_t cornerRegion = m_partition.regionOf(original);
        if (cornerRegion == r) continue;
        seq.m_foreignCorners.push_back({slot + c, cornerRegion, m_entryOf[original]});
        // Regions are visited in order, so each reader list stays ascending.
        std::vector<std::uint32_t>& readers = out.m_regions[cornerRegion].m_readers;
        if (readers.empty() || readers.back() != r) readers.push_back(r);
      }
    }
    std::sort(seq.m_foreignCorners.begin(), seq.m_foreignCorners.end(),
              [](const ForeignCorner& a, const ForeignCorner& b) { return a.slot < b.slot; });
    std::vector<std::uint32_t> removing(stepCount + 1, 0);
    std::uint32_t regionVertices = 0;
    for (std::size_t i = vertexCursor; i < vertexCount && out.m_vertexRegion[i] == r; ++i) {
      ++regionVertices;
      ++removing[std::min<std::size_t>(removalKey(layout.order[i]), stepCount)];
    }
    seq.m_vertexBegin = vertexCursor;
    seq.m_vertexEnd = vertexCursor + regionVertices;
    vertexCursor += regionVertices;
    seq.m_verticesAfterSteps.resize(stepCount + 1);
    std::uint32_t alive = regionVertices;
    for (std::size_t m = 0; m <= stepCount; ++m) {
      seq.m_verticesAfterSteps[m] = alive;
      if (m < stepCount) alive -= removing[m];
    }
    seq.m_borderVertices.reserve(m_borderVertices[r].size());
    for (std::uint32_t v : m_borderVertices[r]) seq.m_borderVertices.push_back(layout.newIndex[v]);
  }
}

// The recorded corner and border-table changes, in the new numbering and slots.
void ProgressiveMeshAssembler::translateChanges(ProgressiveMesh& out, const Layout& layout) {
  for (std::uint32_t r = 0; r < m_partition.regionCount; ++r) {
    RegionSequence& seq = out.m_regions[r];
    seq.m_cornerChanges.reserve(m_recorded[r].size());
    for (const RecordedChange& c : m_recorded[r])
      seq.m_cornerChanges.push_back(
          {layout.slotOf[c.triangle] + c.corner, layout.newIndex[c.before], layout.newIndex[c.after]});
    seq.m_cornerChangeBegin = std::move(m_recordedBegin[r]);
    seq.m_borderChanges.reserve(m_borderRecorded[r].size());
    for (const RecordedChange& c : m_borderRecorded[r])
      seq.m_borderChanges.push_back({c.triangle, layout.newIndex[c.before], layout.newIndex[c.after]});
    seq.m_borderChangeBegin = std::move(m_borderRecordedBegin[r]);
  }
}

}  // namespace polder::mesh
