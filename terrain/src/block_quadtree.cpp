// The block quadtree: node data built from the full-resolution samples, and the per-frame
// cut selection. See block_quadtree.hpp for the contract and the papers it follows.
#include <polder/terrain/block_quadtree.hpp>

#include <algorithm>
#include <atomic>
#include <cassert>
#include <cmath>
#include <limits>
#include <mutex>
#include <new>
#include <optional>
#include <string>
#include <thread>

#include <polder/terrain/rtin.hpp>

namespace polder::terrain {
namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();
// Share of the progress bar the node errors take; the rest is the height ranges and dikes.
constexpr float kErrorProgressStart = 0.02f;
constexpr float kErrorProgressEnd = 0.98f;

std::string nodeName(const NodeId& node) {
  return "(level " + std::to_string(node.level) + ", " + std::to_string(node.bx) + ", " + std::to_string(node.by) + ")";
}

// Whether BlockLod can build the node: at least one whole strided cell inside the field each way
// (the test BlockLod::rebuild makes before reporting "no whole cell").
bool drawableAtStride(const BlockFootprint& fp, const Heightfield& field) {
  return (field.width - 1 - fp.x0) / fp.stride >= 1 && (field.height - 1 - fp.y0) / fp.stride >= 1;
}

// Full-resolution samples BlockLod::build scans for the node: the build's cost.
double interiorSamples(const BlockFootprint& fp, const Heightfield& field) {
  if (!drawableAtStride(fp, field)) return 1.0;
  const int cellsX = std::min(fp.cells(), (field.width - 1 - fp.x0) / fp.stride);
  const int cellsY = std::min(fp.cells(), (field.height - 1 - fp.y0) / fp.stride);
  return double(cellsX * fp.stride + 1) * double(cellsY * fp.stride + 1);
}

}  // namespace

void SelectionScratch::reserve(const BlockQuadtree& tree) {
  // Depth-first: each level on the way down leaves at most three siblings waiting.
  m_stack.reserve(std::size_t(3 * tree.layout().rootLevel() + 4));
}

std::size_t BlockQuadtree::nodeIndex(const NodeId& node) const {
  assert(m_layout.exists(node) && "BlockQuadtree: node outside the layout");
  return m_levelOffset[node.level] + std::size_t(node.by) * std::size_t(m_layout.nodesX(node.level)) + node.bx;
}

Aabb BlockQuadtree::box(const NodeId& node) const {
  const SampleRect area = m_layout.footprint(node);
  const NodeInfo& data = info(node);
  return Aabb{glm::dvec3(area.x0 * m_spacingX, area.y0 * m_spacingY, double(data.minHeight)),
              glm::dvec3(area.x1 * m_spacingX, area.y1 * m_spacingY, double(data.maxHeight))};
}

Aabb BlockQuadtree::relativeBox(const NodeId& node, const glm::dvec3& camera) const {
  const Aabb world = box(node);
  return Aabb{world.minCorner - camera, world.maxCorner - camera};
}

std::size_t BlockQuadtree::memoryBytes() const {
  return sizeof(*this) + m_nodes.capacity() * sizeof(NodeInfo) + m_levelOffset.capacity() * sizeof(std::size_t);
}

Result<BlockQuadtree> BlockQuadtree::build(const Heightfield& field, const BlockLayout& layout,
                                           const BlockQuadtreeOptions& options) {
  if (field.width != layout.width() || field.height != layout.height()) {
    return makeError(ErrorKind::InvalidArgument, "BlockQuadtree::build: the field is " + std::to_string(field.width) +
                                                     " x " + std::to_string(field.height) + " samples, the layout " +
                                                     std::to_string(layout.width()) + " x " +
                                                     std::to_string(layout.height()));
  }
  if (field.heights.size() != field.sampleCount()) {
    return makeError(ErrorKind::InvalidArgument, "BlockQuadtree::build: the field's heights do not match its size");
  }
  if (layout.k() > kRtinMaxK) {
    return makeError(ErrorKind::InvalidArgument, "BlockQuadtree::build: block size k = " + std::to_string(layout.k()) +
                                                     " is above BlockLod's limit " + std::to_string(kRtinMaxK));
  }
  auto report = [&](float fraction) {
    if (options.progress) options.progress(fraction);
  };
  report(0.0f);

  BlockQuadtree tree;
  tree.m_layout = layout;
  tree.m_spacingX = field.spacingX;
  tree.m_spacingY = field.spacingY;
  const int levels = layout.rootLevel() + 1;
  std::size_t total = 0;
  try {
    tree.m_levelOffset.resize(std::size_t(levels));
    for (int level = 0; level < levels; ++level) {
      tree.m_levelOffset[std::size_t(level)] = total;
      total += std::size_t(layout.nodesX(level)) * std::size_t(layout.nodesY(level));
    }
    tree.m_nodes.resize(total);
  } catch (const std::bad_alloc&) {
    return makeError(ErrorKind::OutOfMemory, "BlockQuadtree::build: no memory for " + std::to_string(total) + " nodes");
  }

  // Height ranges: level 0 from the samples, every footprint exactly; a parent's footprint is
  // the union of its existing children's (block_layout.hpp), so it takes their range.
  for (int by = 0; by < layout.nodesY(0); ++by) {
    for (int bx = 0; bx < layout.nodesX(0); ++bx) {
      const NodeId node{0, std::uint32_t(bx), std::uint32_t(by)};
      const SampleRect area = layout.footprint(node);
      float lo = kInfinity, hi = -kInfinity;
      bool finite = true;
      for (int y = area.y0; y <= area.y1; ++y) {
        const float* row = field.heights.data() + field.index(0, y);
        for (int x = area.x0; x <= area.x1; ++x) {
          finite &= std::isfinite(row[x]);
          lo = std::min(lo, row[x]);
          hi = std::max(hi, row[x]);
        }
      }
      if (!finite) {
        return makeError(ErrorKind::InvalidData, "BlockQuadtree::build: block " + nodeName(node) +
                                                     " has non-finite heights (no-data left unfilled?)");
      }
      NodeInfo& data = tree.m_nodes[tree.nodeIndex(node)];
      data.minHeight = lo;
      data.maxHeight = hi;
    }
  }
  for (int level = 1; level < levels; ++level) {
    for (int by = 0; by < layout.nodesY(level); ++by) {
      for (int bx = 0; bx < layout.nodesX(level); ++bx) {
        const NodeId node{std::uint8_t(level), std::uint32_t(bx), std::uint32_t(by)};
        float lo = kInfinity, hi = -kInfinity;
        for (int quadrant = 0; quadrant < 4; ++quadrant) {
          const NodeId child = node.child(quadrant);
          if (!layout.exists(child)) continue;
          const NodeInfo& c = tree.m_nodes[tree.nodeIndex(child)];
          lo = std::min(lo, c.minHeight);
          hi = std::max(hi, c.maxHeight);
        }
        NodeInfo& data = tree.m_nodes[tree.nodeIndex(node)];
        data.minHeight = lo;
        data.maxHeight = hi;
      }
    }
  }
  report(kErrorProgressStart);

  // Node errors, one BlockLod::build per node. Jobs run coarsest first (node index order is
  // finest first, so walk it backwards): the big nodes start early and the small ones fill in.
  std::vector<NodeId> jobs;
  std::vector<double> jobCost;
  try {
    jobs.reserve(total);
    jobCost.reserve(total);
  } catch (const std::bad_alloc&) {
    return makeError(ErrorKind::OutOfMemory, "BlockQuadtree::build: no memory for the job list");
  }
  double totalCost = 0.0;
  for (int level = levels - 1; level >= 0; --level) {
    for (int by = 0; by < layout.nodesY(level); ++by) {
      for (int bx = 0; bx < layout.nodesX(level); ++bx) {
        const NodeId node{std::uint8_t(level), std::uint32_t(bx), std::uint32_t(by)};
        jobs.push_back(node);
        jobCost.push_back(interiorSamples(layout.interior(node), field));
        totalCost += jobCost.back();
      }
    }
  }

  std::atomic<std::size_t> nextJob{0};
  std::atomic<double> doneCost{0.0};
  std::mutex errorMutex;
  std::size_t errorJob = jobs.size();  // the first failing job, so the reported error is deterministic
  Error firstError;
  bool errorIsOutOfMemory = false;
  // Each worker takes jobs in order from the shared counter until none is left; the calling
  // thread, one of them, reports progress.
  const std::thread::id caller = std::this_thread::get_id();
  auto work = [&] {
    const bool reportsProgress = std::this_thread::get_id() == caller;
    BlockLod lod;  // one per worker, rebuilt in place: no allocation after the first node
    for (;;) {
      const std::size_t job = nextJob.fetch_add(1, std::memory_order_relaxed);
      if (job >= jobs.size()) break;
      const NodeId node = jobs[job];
      const BlockFootprint fp = layout.interior(node);
      NodeInfo& data = tree.m_nodes[tree.nodeIndex(node)];
      if (!drawableAtStride(fp, field)) {
        data.lodError = kInfinity;  // always refined (see the header)
        data.floorError = kInfinity;
      } else {
        // Nothing may escape a worker thread (it would terminate the program): a failed
        // allocation is recorded without allocating, and reported after the join.
        bool outOfMemory = false;
        Status status;
        try {
          status = lod.rebuild(field, fp);
        } catch (const std::bad_alloc&) {
          outOfMemory = true;
        }
        if (!outOfMemory && status) {
          data.lodError = lod.maxError();
          data.floorError = lod.floorError();
        } else {
          std::lock_guard<std::mutex> lock(errorMutex);
          if (job < errorJob) {
            errorJob = job;
            errorIsOutOfMemory = outOfMemory;
            if (!outOfMemory) firstError = status.error();
          }
        }
      }
      const double done = doneCost.fetch_add(jobCost[job], std::memory_order_relaxed) + jobCost[job];
      if (reportsProgress) {
        report(kErrorProgressStart + (kErrorProgressEnd - kErrorProgressStart) * float(done / totalCost));
      }
    }
  };

  std::optional<core::ThreadPool> ownPool;
  core::ThreadPool& pool = options.pool ? *options.pool : ownPool.emplace();
  const std::size_t workers =
      std::min<std::size_t>(std::size_t(pool.threadCount()), std::max<std::size_t>(jobs.size(), 1));
  pool.forRanges(workers, 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t w = begin; w < end; ++w) work();
  });
  if (errorJob < jobs.size()) {
    if (errorIsOutOfMemory) {
      return makeError(ErrorKind::OutOfMemory,
                       "BlockQuadtree::build: no memory for the BlockLod of node " + nodeName(jobs[errorJob]));
    }
    return firstError;
  }

  // Dike bounds, on the calling thread as promised in the options.
  if (options.dikeErrorBound) {
    for (int level = 0; level < levels; ++level) {
      for (int by = 0; by < layout.nodesY(level); ++by) {
        for (int bx = 0; bx < layout.nodesX(level); ++bx) {
          const NodeId node{std::uint8_t(level), std::uint32_t(bx), std::uint32_t(by)};
          const float bound = options.dikeErrorBound(node);
          if (!(bound >= 0.0f)) {
            return makeError(ErrorKind::InvalidArgument, "BlockQuadtree::build: dikeErrorBound gave " +
                                                             std::to_string(bound) + " for node " + nodeName(node) +
                                                             " (must be >= 0)");
          }
          tree.m_nodes[tree.nodeIndex(node)].dikeError = bound;
        }
      }
    }
  }
  report(1.0f);
  return tree;
}

Result<BlockQuadtree> BlockQuadtree::fromNodes(const BlockLayout& layout, double spacingX, double spacingY,
                                               std::vector<NodeInfo> nodes) {
  if (!(spacingX > 0.0) || !(spacingY > 0.0))
    return makeError(ErrorKind::InvalidArgument, "BlockQuadtree::fromNodes: the spacing must be positive");
  BlockQuadtree tree;
  tree.m_layout = layout;
  tree.m_spacingX = spacingX;
  tree.m_spacingY = spacingY;
  std::size_t total = 0;
  tree.m_levelOffset.resize(std::size_t(layout.rootLevel()) + 1);
  for (int level = 0; level <= layout.rootLevel(); ++level) {
    tree.m_levelOffset[std::size_t(level)] = total;
    total += std::size_t(layout.nodesX(level)) * std::size_t(layout.nodesY(level));
  }
  if (nodes.size() != total)
    return makeError(ErrorKind::InvalidArgument, "BlockQuadtree::fromNodes: " + std::to_string(nodes.size()) +
                                                     " nodes for a layout of " + std::to_string(total));
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const NodeInfo& n = nodes[i];
    const bool rangeOk = std::isfinite(n.minHeight) && std::isfinite(n.maxHeight) && n.minHeight <= n.maxHeight;
    const bool errorsOk = n.lodError >= 0.0f && n.floorError >= 0.0f && n.dikeError >= 0.0f;
    if (!rangeOk || !errorsOk)
      return makeError(ErrorKind::InvalidData, "BlockQuadtree::fromNodes: node " + std::to_string(i) +
                                                   " has an invalid height range or a negative error");
  }
  tree.m_nodes = std::move(nodes);
  return tree;
}

SelectionStats BlockQuadtree::select(const Camera& camera, const SelectionOptions& options, SelectionScratch& scratch,
                                     std::vector<SelectedNode>& out, NodePredicate isResident) const {
  assert(options.tolerancePx > 0.0 && "BlockQuadtree::select: tolerancePx must be > 0");
  assert(!m_nodes.empty() && "BlockQuadtree::select: the tree is not built");
  SelectionStats stats;
  out.clear();
  scratch.reserve(*this);

  const Frustum frustum = Frustum::fromCamera(camera);
  const glm::dvec3 eye = camera.position;
  const double projection = camera.errorProjectionConstant();
  const double tau = options.tolerancePx;
  const bool floorMeasure = options.errorMeasure == NodeErrorMeasure::Floor;

  // Node is a forced split or one of its ancestors.
  auto forced = [&](const NodeId& node) {
    for (const NodeId& f : options.forcedSplits) {
      if (f.level == 0 || node.level < f.level) continue;
      const int up = node.level - f.level;
      if ((f.bx >> up) == node.bx && (f.by >> up) == node.by) return true;
    }
    return false;
  };

  auto& stack = scratch.m_stack;
  stack.clear();
  stack.push_back(SelectionScratch::Entry{m_layout.root(), FrustumTest::Intersecting, false});
  while (!stack.empty()) {
    const SelectionScratch::Entry entry = stack.back();
    stack.pop_back();
    const NodeId node = entry.node;
    ++stats.nodesVisited;

    const Aabb box = relativeBox(node, eye);
    const FrustumTest test = entry.tested ? entry.test : frustum.classifyRelative(box);
    const double distance = distanceToOrigin(box);
    if (test == FrustumTest::Outside) {
      // Culled nodes stay in the cut for the dikes, which need every node drawable at its
      // stride: an edge node that is not (infinite error) gives way to its children.
      bool descend = node.level > 0 && (!std::isfinite(m_nodes[nodeIndex(node)].delta()) || forced(node));
      if (descend && options.culledNeedResidency && isResident) {
        for (int quadrant = 0; quadrant < 4; ++quadrant) {
          const NodeId child = node.child(quadrant);
          if (m_layout.exists(child) && !isResident(child)) descend = false;
        }
      }
      if (descend) {
        for (int quadrant = 3; quadrant >= 0; --quadrant) {
          const NodeId child = node.child(quadrant);
          if (m_layout.exists(child)) stack.push_back(SelectionScratch::Entry{child, FrustumTest::Outside, true});
        }
        continue;
      }
      out.push_back(SelectedNode{node, distance, false, false});
      ++stats.culledNodes;
      continue;
    }

    // Refine while the node's projected error exceeds tau; written without the division so that
    // distance 0 (camera in the box) refines any node with an error and keeps exact ones.
    const NodeInfo& data = m_nodes[nodeIndex(node)];
    const double error = floorMeasure ? data.floorDelta() : data.delta();
    bool refine = node.level > 0 && ((error > 0.0 && projection * error > tau * distance) || forced(node));

    // Children, with their frustum test; a parent inside the frustum has children inside.
    SelectionScratch::Entry children[4];
    int childCount = 0;
    bool blocked = false;
    if (refine) {
      for (int quadrant = 0; quadrant < 4; ++quadrant) {
        const NodeId child = node.child(quadrant);
        if (!m_layout.exists(child)) continue;  // beyond the DEM
        const FrustumTest childTest =
            test == FrustumTest::Inside ? FrustumTest::Inside : frustum.classifyRelative(relativeBox(child, eye));
        const bool asked = childTest != FrustumTest::Outside || options.culledNeedResidency;
        if (asked && isResident && !isResident(child)) blocked = true;
        children[childCount++] = SelectionScratch::Entry{child, childTest, true};
      }
      refine = !blocked;
    }
    if (refine) {
      // Reversed, so that the output runs SW, SE, NW, NE within each parent.
      for (int c = childCount - 1; c >= 0; --c) stack.push_back(children[c]);
      continue;
    }
    out.push_back(SelectedNode{node, distance, true, blocked});
    ++stats.visibleNodes;
    stats.blockedNodes += blocked;
  }
  return stats;
}

}  // namespace polder::terrain
