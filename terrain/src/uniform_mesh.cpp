// The uniform-error mesh (uniform_mesh.hpp): a bottom-up choice of the cut, then stitching
// rounds that pin block sides or split coarse nodes until every dike triangle is within the
// bound, every triangle measured exactly.
#include <polder/terrain/uniform_mesh.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <new>
#include <string>

#include <polder/terrain/block_quadtree.hpp>
#include <polder/terrain/dike_error_cache.hpp>
#include <polder/terrain/dike_errors.hpp>
#include <polder/terrain/dike_stage.hpp>
#include <polder/terrain/normals.hpp>
#include <polder/terrain/rtin.hpp>

namespace polder::terrain {
namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();
// Stitching rounds before giving up; each adds a pin or splits a node, and real DEMs need a
// handful (uniform_mesh.hpp, step 2). A guard against a hang, not a tuning knob.
constexpr std::size_t kMaxRounds = 1000;
// Extractions below a failing block triangle's stored error before the block goes to full
// detail (level 0) or is split: the stored and the measured errors differ only by rounding.
constexpr int kMaxLoweredExtractions = 3;

// Phase 1's record per node of every level.
struct Choice {
  double cost = kInfinity;  // triangles plus kept side vertices of the best cut under the node
  bool self = false;        // that best cut is the node alone
  bool feasible = false;    // the node itself can be drawn within the bound at its stride
};

// One node of the cut during the stitching rounds.
struct CutEntry {
  NodeId node;
  BlockMesh mesh;
  BoundaryPins pins;
  float threshold = 0.0f;
  int lowered = 0;          // extractions below a failing block triangle's error so far
  float measuredM = 0.0f;   // the largest measured error of the mesh's triangles
  bool dirty = true;        // to be extracted (and checked) again
  bool fromChoice = false;  // the mesh is phase 1's, extracted but not checked yet
  bool split = false;       // to be replaced by its children's best cuts
};

DikeVertex globalVertex(const BlockMesh& mesh, std::uint32_t index) {
  const GridVertex& v = mesh.vertices[index];
  return DikeVertex{mesh.footprint.x0 + int(v.i) * mesh.footprint.stride,
                    mesh.footprint.y0 + int(v.j) * mesh.footprint.stride};
}

std::size_t keptSideVertices(const BlockMesh& mesh) {
  std::size_t count = 0;
  for (const auto& side : mesh.edges) count += side.size();
  return count - 4;  // each corner sits on two sides
}

// The largest float not above `bound`: extraction thresholds are floats, and a float rounded
// up past the bound would let through an error above it.
float floatAtMost(double bound) {
  float f = float(bound);
  if (double(f) > bound) f = std::nextafter(f, 0.0f);
  return f;
}

class UniformMeshBuilder {
 public:
  UniformMeshBuilder(const Heightfield& field, const UniformMeshOptions& options, const BlockLayout& layout)
      : m_field(field), m_options(options), m_layout(layout), m_threshold(floatAtMost(options.maxErrorM)) {}

  Result<UniformMesh> run() {
    chooseCut();
    if (Status status = stitchUntilWithinBound(); !status) return status.error();
    return finish();
  }

 private:
  std::size_t choiceIndex(const NodeId& node) const {
    return m_levelOffset[node.level] + std::size_t(node.by) * std::size_t(m_layout.nodesX(node.level)) + node.bx;
  }
  void progress(float fraction) const {
    if (m_options.progress) m_options.progress(std::clamp(fraction, 0.0f, 1.0f));
  }

  // Builds the node's hierarchy; false when it cannot be drawn at its stride (no whole cell).
  bool buildLod(const NodeId& node) { return m_lod.rebuild(m_field, m_layout.interior(node)).ok(); }

  // Phase 1 (uniform_mesh.hpp, step 1).
  void chooseCut() {
    const int levels = m_options.coarserLevels ? m_layout.rootLevel() + 1 : 1;
    m_levelOffset.assign(std::size_t(m_layout.rootLevel()) + 2, 0);
    for (int level = 0; level <= m_layout.rootLevel(); ++level)
      m_levelOffset[std::size_t(level) + 1] =
          m_levelOffset[std::size_t(level)] + std::size_t(m_layout.nodesX(level)) * std::size_t(m_layout.nodesY(level));
    m_choices.assign(m_levelOffset.back(), Choice{});
    m_chosenMeshes.assign(m_levelOffset.back(), BlockMesh{});
    for (int level = 0; level < levels; ++level) {
      const int nx = m_layout.nodesX(level), ny = m_layout.nodesY(level);
      for (int by = 0; by < ny; ++by) {
        for (int bx = 0; bx < nx; ++bx) chooseNode(NodeId{std::uint8_t(level), std::uint32_t(bx), std::uint32_t(by)});
        progress(0.6f * (float(level) + float(by + 1) / float(ny)) / float(levels));
      }
    }
    // The cut: the best choice from the top level tried down.
    const int top = levels - 1;
    for (int by = 0; by < m_layout.nodesY(top); ++by)
      for (int bx = 0; bx < m_layout.nodesX(top); ++bx)
        appendBestCut(NodeId{std::uint8_t(top), std::uint32_t(bx), std::uint32_t(by)}, m_entries, true);
    m_chosenMeshes.clear();
    m_chosenMeshes.shrink_to_fit();
  }

  void chooseNode(const NodeId& node) {
    Choice& choice = m_choices[choiceIndex(node)];
    double childCost = 0.0;
    bool childrenFeasible = true;
    if (node.level > 0) {
      for (int quadrant = 0; quadrant < 4; ++quadrant) {
        const NodeId child = node.child(quadrant);
        if (!m_layout.exists(child)) continue;
        childCost += m_choices[choiceIndex(child)].cost;
        childrenFeasible &= m_choices[choiceIndex(child)].feasible;
      }
    }
    // A node is tried only where all its children could be drawn themselves: where a finer
    // stride already misses the bound, a coarser one almost always does.
    double ownCost = kInfinity;
    BlockMesh& mesh = m_chosenMeshes[choiceIndex(node)];
    if (childrenFeasible && buildLod(node) && m_lod.floorError() <= m_threshold) {
      m_lod.extractThreshold(m_threshold, mesh, m_scratch);
      ownCost = double(mesh.triangleCount() + keptSideVertices(mesh));
      choice.feasible = true;
    }
    if (node.level == 0 || ownCost < childCost) {
      choice.cost = ownCost;
      choice.self = true;
      if (node.level > 0)
        for (int quadrant = 0; quadrant < 4; ++quadrant) releaseMeshes(node.child(quadrant));
    } else {
      choice.cost = childCost;
      mesh = BlockMesh{};
    }
  }

  // Frees the kept meshes under a node that its parent replaces.
  void releaseMeshes(const NodeId& node) {
    if (!m_layout.exists(node)) return;
    m_chosenMeshes[choiceIndex(node)] = BlockMesh{};
    if (node.level > 0 && !m_choices[choiceIndex(node)].self)
      for (int quadrant = 0; quadrant < 4; ++quadrant) releaseMeshes(node.child(quadrant));
  }

  // Appends the nodes of the best cut under `node`; with `keptMesh`, their phase-1 meshes (still
  // to be checked), else they are extracted afresh.
  void appendBestCut(const NodeId& node, std::vector<CutEntry>& out, bool keptMesh) {
    if (!m_layout.exists(node)) return;
    if (m_choices[choiceIndex(node)].self) {
      CutEntry entry;
      entry.node = node;
      entry.threshold = m_threshold;
      if (keptMesh) entry.mesh = std::move(m_chosenMeshes[choiceIndex(node)]);
      entry.fromChoice = keptMesh;
      out.push_back(std::move(entry));
      return;
    }
    for (int quadrant = 0; quadrant < 4; ++quadrant) appendBestCut(node.child(quadrant), out, keptMesh);
  }

  // Extracts a dirty entry (unless phase 1 just did) and measures every triangle exactly;
  // where one exceeds the bound, extracts again below its stored error, then at full detail
  // (level 0) or marks the entry for splitting.
  void extractChecked(CutEntry& entry) {
    bool haveLod = false;
    auto lodReady = [&] {
      if (!haveLod) haveLod = buildLod(entry.node);
      return haveLod;
    };
    bool extract = !entry.fromChoice;
    entry.fromChoice = false;
    while (true) {
      if (extract) {
        if (!lodReady()) {
          entry.split = true;
          return;
        }
        m_lod.extractThreshold(entry.threshold, entry.mesh, m_scratch, &entry.pins);
        ++m_stats.reextractions;
      }
      extract = true;
      float measured = 0.0f, loweredTo = entry.threshold;
      bool failing = false;
      const BlockMesh& mesh = entry.mesh;
      for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const float e =
            dikeTriangleError(m_field, globalVertex(mesh, mesh.indices[t]), globalVertex(mesh, mesh.indices[t + 1]),
                              globalVertex(mesh, mesh.indices[t + 2]));
        measured = std::max(measured, e);
        if (!(double(e) > m_options.maxErrorM)) continue;
        failing = true;
        if (!lodReady()) {
          entry.split = true;
          return;
        }
        // Emitted triangles start at their right-angle apex (rtin_grid.hpp, walkTriangle).
        const float stored = m_lod.triangleError(mesh.vertices[mesh.indices[t]], mesh.vertices[mesh.indices[t + 1]],
                                                 mesh.vertices[mesh.indices[t + 2]]);
        loweredTo = std::min(loweredTo, std::nextafter(stored, -1.0f));
      }
      entry.measuredM = measured;
      if (!failing) break;
      if (++entry.lowered > kMaxLoweredExtractions) {
        if (entry.node.level > 0 || entry.threshold < 0.0f) {
          entry.split = true;  // (level 0 at full detail is the surface itself: never reached)
          return;
        }
        loweredTo = -1.0f;  // every vertex: the surface itself
      }
      entry.threshold = loweredTo;
    }
    entry.dirty = false;
  }

  // Replaces entries marked for splitting by their children's best cuts; false when a level-0
  // entry is marked (no finer node exists).
  bool applySplits() {
    std::vector<CutEntry> next;
    next.reserve(m_entries.size() + 3);
    for (CutEntry& entry : m_entries) {
      if (!entry.split) {
        next.push_back(std::move(entry));
        continue;
      }
      if (entry.node.level == 0) return false;
      ++m_stats.splitNodes;
      for (int quadrant = 0; quadrant < 4; ++quadrant) appendBestCut(entry.node.child(quadrant), next, false);
    }
    m_entries = std::move(next);
    return true;
  }

  // Level-0 block -> the entry whose footprint holds it.
  void mapBlocks() {
    const int nx = m_layout.nodesX(0), ny = m_layout.nodesY(0);
    m_blockEntry.assign(std::size_t(nx) * std::size_t(ny), 0);
    for (std::uint32_t e = 0; e < m_entries.size(); ++e) {
      const NodeId& node = m_entries[e].node;
      const int span = 1 << node.level;
      for (int by = int(node.by) * span; by < std::min(ny, int(node.by + 1) * span); ++by)
        for (int bx = int(node.bx) * span; bx < std::min(nx, int(node.bx + 1) * span); ++bx)
          m_blockEntry[std::size_t(by) * std::size_t(nx) + std::size_t(bx)] = e;
    }
  }

  // Pins the sides of every entry beside the failing dike triangle with bounding box `box`;
  // where none was added (nor is waiting for the next extraction), marks the coarsest entry of level 1 or more that the
  // box touches for splitting. False when neither is possible.
  bool refineAround(const SampleRect& box) {
    const int pitch = m_layout.pitch(), nx = m_layout.nodesX(0), ny = m_layout.nodesY(0);
    // Level-0 blocks whose footprints (ends shared with the next block) meet the box.
    const int bx0 = std::max(0, (box.x0 - 1) / pitch), bx1 = std::min(nx - 1, box.x1 / pitch);
    const int by0 = std::max(0, (box.y0 - 1) / pitch), by1 = std::min(ny - 1, box.y1 / pitch);
    m_touched.clear();
    for (int by = by0; by <= by1; ++by)
      for (int bx = bx0; bx <= bx1; ++bx) {
        const std::uint32_t e = m_blockEntry[std::size_t(by) * std::size_t(nx) + std::size_t(bx)];
        if (std::find(m_touched.begin(), m_touched.end(), e) == m_touched.end()) m_touched.push_back(e);
      }
    bool added = false;
    std::uint32_t coarsest = std::uint32_t(m_entries.size());
    for (const std::uint32_t e : m_touched) {
      CutEntry& entry = m_entries[e];
      const SampleRect area = m_layout.footprint(entry.node);
      if (area.x0 > box.x1 || box.x0 > area.x1 || area.y0 > box.y1 || box.y0 > area.y1) continue;
      SideRange sides[2];
      const int count = sidesBesideDikeTriangle(entry.mesh, box, sides);
      bool entryAdded = false;
      for (int i = 0; i < count; ++i) entryAdded |= entry.pins.pin(sides[i].side, sides[i].from, sides[i].to);
      // A pin set earlier this round, for another triangle, takes effect next round too.
      if (entryAdded || (count > 0 && entry.dirty)) {
        entry.dirty = true;
        added = true;
      }
      if (entry.node.level > 0 && (coarsest == m_entries.size() || entry.node.level > m_entries[coarsest].node.level))
        coarsest = e;
    }
    if (added) return true;
    if (coarsest == m_entries.size()) return false;
    m_entries[coarsest].split = true;
    return true;
  }

  // Phase 2 and 3 (uniform_mesh.hpp).
  Status stitchUntilWithinBound() {
    DikeStage stage(m_layout);
    const ExactDikeError exact(m_field);
    DikeErrorCache errors(exact);
    std::vector<SelectedNode> cut;
    std::vector<const BlockMesh*> meshes;
    for (std::size_t round = 1; round <= kMaxRounds; ++round) {
      m_stats.rounds = round;
      bool splits = false;
      for (CutEntry& entry : m_entries) {
        if (entry.dirty) extractChecked(entry);
        splits |= entry.split;
      }
      if (splits) {
        if (!applySplits()) return internalError("a level-0 block misses the bound at full detail");
        --round;  // the new entries are extracted before anything is stitched
        continue;
      }
      cut.clear();
      meshes.clear();
      for (const CutEntry& entry : m_entries) {
        cut.push_back(SelectedNode{entry.node, 0.0, true, false});
        meshes.push_back(&entry.mesh);
      }
      stage.stitch(cut, meshes);
      if (!stage.stitched()) return internalError("the cut could not be stitched");
      mapBlocks();
      const DikeMesh& dikes = stage.mesh();
      errors.beginPass(dikes.triangleCount());
      bool failing = false;
      float worst = 0.0f;
      for (std::size_t t = 0; t + 2 < dikes.indices.size(); t += 3) {
        const DikeVertex& a = dikes.vertices[dikes.indices[t]];
        const DikeVertex& b = dikes.vertices[dikes.indices[t + 1]];
        const DikeVertex& c = dikes.vertices[dikes.indices[t + 2]];
        const DikeTriangleRef where{{dikes.indices[t], dikes.indices[t + 1], dikes.indices[t + 2]},
                                    dikes.owners[t / 3]};
        const float e = errors.lookUp(a, b, c, where).error;
        worst = std::max(worst, e);
        if (!(double(e) > m_options.maxErrorM)) continue;
        failing = true;
        const SampleRect box{std::min({a.x, b.x, c.x}), std::min({a.y, b.y, c.y}), std::max({a.x, b.x, c.x}),
                             std::max({a.y, b.y, c.y})};
        if (!refineAround(box))
          return internalError("a dike triangle misses the bound between level-0 blocks at full detail");
      }
      progress(0.6f + 0.4f * (1.0f - 1.0f / float(round + 1)));
      if (!failing) {
        m_dikes = dikes;
        m_stats.dikeMaxErrorM = worst;
        return {};
      }
    }
    return internalError("the dikes did not reach the bound in " + std::to_string(kMaxRounds) + " rounds");
  }

  Error internalError(const std::string& what) const {
    return makeError(ErrorKind::InvalidData,
                     "uniform mesh within " + std::to_string(m_options.maxErrorM) + " m: " + what);
  }

  Result<UniformMesh> finish() {
    UniformMesh out;
    out.layout = m_layout;
    out.dikes = std::move(m_dikes);
    out.stats = m_stats;
    out.stats.nodesPerLevel.assign(std::size_t(m_layout.rootLevel()) + 1, 0);
    for (CutEntry& entry : m_entries) {
      out.stats.blockTriangles += entry.mesh.triangleCount();
      out.stats.blockMaxErrorM = std::max(out.stats.blockMaxErrorM, entry.measuredM);
      out.stats.pinnedNodes += entry.pins.any();
      ++out.stats.nodesPerLevel[entry.node.level];
      out.nodes.push_back(entry.node);
      out.meshes.push_back(std::move(entry.mesh));
    }
    out.stats.dikeTriangles = out.dikes.triangleCount();
    progress(1.0f);
    return out;
  }

  const Heightfield& m_field;
  const UniformMeshOptions& m_options;
  BlockLayout m_layout;
  float m_threshold;
  BlockLod m_lod;
  RtinScratch m_scratch;
  std::vector<std::size_t> m_levelOffset;  // first choice of each level
  std::vector<Choice> m_choices;           // per node of every level
  std::vector<BlockMesh> m_chosenMeshes;   // phase 1: the mesh of each node chosen so far
  std::vector<CutEntry> m_entries;         // the cut
  std::vector<std::uint32_t> m_blockEntry;
  std::vector<std::uint32_t> m_touched;
  DikeMesh m_dikes;
  UniformMeshStats m_stats;
};

}  // namespace

Result<UniformMesh> buildUniformMesh(const Heightfield& field, const UniformMeshOptions& options) {
  if (!(options.maxErrorM >= kUniformMeshMinErrorM && options.maxErrorM <= kUniformMeshMaxErrorM))
    return makeError(ErrorKind::InvalidArgument, "the error bound must be between 0.001 and 100000 metres");
  if (field.heights.size() != field.sampleCount())
    return makeError(ErrorKind::InvalidArgument, "the heights do not match the field's size");
  auto layout = BlockLayout::create(field.width, field.height, options.blockK);
  if (!layout) return layout.error();
  for (const float h : field.heights)
    if (!std::isfinite(h))
      return makeError(ErrorKind::InvalidData, "the DEM has non-finite heights (no-data left unfilled?)");
  try {
    UniformMeshBuilder builder(field, options, *layout);
    return builder.run();
  } catch (const std::bad_alloc&) {
    return makeError(ErrorKind::OutOfMemory, "not enough memory for the uniform mesh");
  }
}

TriangleSoup uniformMeshSoup(const UniformMesh& mesh) {
  TriangleSoup soup;
  for (const BlockMesh& block : mesh.meshes) soup.addBlock(block);
  soup.addDikes(mesh.dikes);
  return soup;
}

float soupMaxError(const Heightfield& field, const TriangleSoup& soup) {
  float worst = 0.0f;
  for (std::size_t t = 0; t < soup.triangleCount(); ++t) {
    const GridPoint& a = soup.points[soup.indices[3 * t]];
    const GridPoint& b = soup.points[soup.indices[3 * t + 1]];
    const GridPoint& c = soup.points[soup.indices[3 * t + 2]];
    worst = std::max(worst, dikeTriangleError(field, DikeVertex{a.x, a.y}, DikeVertex{b.x, b.y}, DikeVertex{c.x, c.y}));
  }
  return worst;
}

mesh::TriangleMesh uniformMeshTriangles(const Heightfield& field, const UniformMesh& mesh) {
  auto key = [](int x, int y) { return (std::uint64_t(std::uint32_t(y)) << 32) | std::uint32_t(x); };
  std::vector<std::uint64_t> keys;
  for (const BlockMesh& block : mesh.meshes)
    for (std::uint32_t v = 0; v < block.vertices.size(); ++v) {
      const DikeVertex p = globalVertex(block, v);
      keys.push_back(key(p.x, p.y));
    }
  for (const DikeVertex& p : mesh.dikes.vertices) keys.push_back(key(p.x, p.y));
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  auto indexOf = [&](int x, int y) {
    return std::uint32_t(std::lower_bound(keys.begin(), keys.end(), key(x, y)) - keys.begin());
  };

  mesh::TriangleMesh out;
  out.positions.reserve(keys.size());
  out.normals.reserve(keys.size());
  for (const std::uint64_t k : keys) {
    const int x = int(k & 0xffffffffu), y = int(k >> 32);
    out.positions.push_back(glm::vec3(field.worldPosition(x, y)));
    out.normals.push_back(sampleNormal(field, x, y));
  }
  out.indices.reserve(3 * mesh.triangleCount());
  std::vector<std::uint32_t> remap;
  for (const BlockMesh& block : mesh.meshes) {
    remap.resize(block.vertices.size());
    for (std::uint32_t v = 0; v < block.vertices.size(); ++v) {
      const DikeVertex p = globalVertex(block, v);
      remap[v] = indexOf(p.x, p.y);
    }
    for (const std::uint32_t index : block.indices) out.indices.push_back(remap[index]);
  }
  remap.resize(mesh.dikes.vertices.size());
  for (std::uint32_t v = 0; v < mesh.dikes.vertices.size(); ++v)
    remap[v] = indexOf(mesh.dikes.vertices[v].x, mesh.dikes.vertices[v].y);
  for (const std::uint32_t index : mesh.dikes.indices) out.indices.push_back(remap[index]);
  return out;
}

}  // namespace polder::terrain
