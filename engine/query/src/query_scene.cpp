// The Embree calls for ray queries live in this file (Embree 3 API: RTCIntersectContext,
// rtcIntersect1/16, rtcOccluded1), the point queries in closest_point_scene.cpp, the device
// in embree_device.cpp; a move to Embree 4 touches only these three.
#include <polder/query/query_scene.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <embree3/rtcore.h>

#include "embree_device.hpp"
#include "grid_surface.hpp"
#include "grid_triangulation.hpp"
#include "ray_triangle.hpp"

namespace polder::query {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kMaxGridCells = 32766;  // RTCGrid width/height (vertices) is at most 32767
constexpr int kPacketSize = 16;
// Geometry ids of a heightfield scene: the grid primitives, and the triangles of blocks
// that hold no-data samples.
constexpr unsigned kGridGeometryId = 0;
constexpr unsigned kHoleGeometryId = 1;
// Barycentric slack for accepting a double-precision re-intersection of a mesh triangle
// Embree reported: a ray Embree saw just inside an edge may land this far outside it.
constexpr double kMeshEdgeTolerance = 1e-6;
// Line-of-sight ends are pulled in by this many float ulps of the scene's coordinates.
constexpr double kSegmentEndUlps = 4.0;

// One grid primitive: a block of cells of the heightfield.
struct GridBlock {
  int x0 = 0, y0 = 0;          // first cell
  int cellsX = 0, cellsY = 0;  // cells in the block
};

// A mesh as given: its exact positions for refined hits, its indices for Embree too.
struct MeshCopy {
  glm::dvec3 origin{0.0};
  std::vector<glm::vec3> positions;    // relative to origin, as given
  std::vector<std::uint32_t> indices;  // shared with Embree
};

// A ray ready for Embree: unit direction in double, segment in metres.
struct PreparedRay {
  glm::dvec3 origin{0.0};
  glm::dvec3 direction{0.0};
  double tMin = 0.0;
  double tMax = kInf;
};

// Embree asserts that ray origins lie within about +-1.8e18 in single precision; points
// further out than this, far beyond any terrain, are taken as seeing nothing.
constexpr double kMaxTraceableCoordinate = 1e15;

bool isTraceable(const glm::dvec3& point) {
  return std::abs(point.x) <= kMaxTraceableCoordinate && std::abs(point.y) <= kMaxTraceableCoordinate &&
         std::abs(point.z) <= kMaxTraceableCoordinate;  // false for NaN too
}

std::optional<PreparedRay> prepare(const QueryRay& ray) {
  const double length = glm::length(ray.direction);
  if (!isTraceable(ray.origin) || !std::isfinite(length) || length == 0.0 ||
      !(ray.maxDistance >= std::max(ray.minDistance, 0.0)))
    return std::nullopt;
  return PreparedRay{ray.origin, ray.direction / length, std::max(ray.minDistance, 0.0), ray.maxDistance};
}

struct FloatRay {
  glm::vec3 origin{0.0f};
  glm::vec3 direction{0.0f};
  float tNear = 0.0f;
  float tFar = 0.0f;
};

// What Embree reported for one ray, independent of single rays or packets.
struct RawHit {
  float t = 0.0f;
  float u = 0.0f, v = 0.0f;
  unsigned geomID = RTC_INVALID_GEOMETRY_ID;
  unsigned primID = 0;
  glm::dvec3 ng{0.0};
};

glm::dvec3 facing(const glm::dvec3& normal, const glm::dvec3& direction) {
  return glm::dot(normal, direction) > 0.0 ? -normal : normal;
}

}  // namespace

struct QueryScene::Impl {
  detail::DeviceMonitor monitor;  // first: the device's callbacks point at it
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  QueryOptions options;
  glm::dvec3 origin{0.0};  // world position of the scene frame's origin
  glm::dvec3 boundsMin{kInf};
  glm::dvec3 boundsMax{-kInf};
  double resolution = 0.0;
  std::optional<detail::GridSurface> grid;
  std::vector<GridBlock> blocks;           // per grid primitive
  std::vector<std::uint32_t> holeIndices;  // triangles of blocks with no-data samples
  std::vector<glm::ivec2> holeCells;       // the cell of each of those triangles
  std::vector<MeshCopy> meshes;            // per geometry of a mesh scene

  Impl() = default;
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;
  ~Impl() {
    // The scene first: it reads the buffers below until released.
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }

  Status createDevice() {
    monitor.limitBytes = std::int64_t(
        std::min<std::size_t>(options.memoryLimitBytes, std::size_t(std::numeric_limits<std::int64_t>::max())));
    auto created = detail::newDevice(options.buildThreads, monitor);
    if (!created) return created.error();
    device = *created;
    scene = rtcNewScene(device);
    if (!scene) return deviceStatus();
    rtcSetSceneFlags(scene, options.robust ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE);
    return deviceStatus();
  }

  // The first error the device reported since the last call, if any.
  Status deviceStatus() { return detail::deviceStatus(device, monitor); }

  void setResolution() {
    double largest = 1.0;
    if (boundsMin.x <= boundsMax.x) {
      for (int i = 0; i < 3; ++i) {
        largest = std::max({largest, std::abs(boundsMin[i] - origin[i]), std::abs(boundsMax[i] - origin[i])});
      }
    }
    const float f = float(largest);
    resolution = double(std::nextafter(f, std::numeric_limits<float>::infinity()) - f);
  }

  // The ray in the scene's float frame; RTCRay and RTCRay16 take it field by field.
  FloatRay toSceneFrame(const PreparedRay& ray) const {
    const glm::vec3 local(ray.origin - origin);
    const auto toFloat = [](double t) {
      return t > double(std::numeric_limits<float>::max()) ? std::numeric_limits<float>::infinity() : float(t);
    };
    return FloatRay{local, glm::vec3(ray.direction), toFloat(ray.tMin), toFloat(ray.tMax)};
  }

  // Turns Embree's single-precision answer into a hit in the world frame, re-intersecting
  // the triangle it found in double precision when asked to (and when that succeeds).
  RayHit resolve(const PreparedRay& ray, const RawHit& raw) const {
    if (options.refineHits) {
      if (grid) {
        glm::ivec2 cell;
        if (raw.geomID == kGridGeometryId) {
          const GridBlock& block = blocks[raw.primID];
          // u, v run over [0, 1] across the whole grid primitive.
          cell.x = block.x0 + std::clamp(int(raw.u * float(block.cellsX)), 0, block.cellsX - 1);
          cell.y = block.y0 + std::clamp(int(raw.v * float(block.cellsY)), 0, block.cellsY - 1);
        } else {
          cell = holeCells[raw.primID];
        }
        if (auto hit = grid->intersectNear(ray.origin, ray.direction, ray.tMin, ray.tMax, cell.x, cell.y)) {
          return RayHit{ray.origin + ray.direction * hit->t, facing(hit->normal, ray.direction), hit->t};
        }
      } else {
        const MeshCopy& mesh = meshes[raw.geomID];
        const std::size_t first = std::size_t(raw.primID) * 3;
        const glm::dvec3 p0 = mesh.origin + glm::dvec3(mesh.positions[mesh.indices[first]]);
        const glm::dvec3 p1 = mesh.origin + glm::dvec3(mesh.positions[mesh.indices[first + 1]]);
        const glm::dvec3 p2 = mesh.origin + glm::dvec3(mesh.positions[mesh.indices[first + 2]]);
        const auto hit = detail::intersectTriangle(ray.origin, ray.direction, p0, p1, p2, kMeshEdgeTolerance);
        if (hit && hit->t >= ray.tMin && hit->t <= ray.tMax) {
          const glm::dvec3 normal = glm::normalize(glm::cross(p1 - p0, p2 - p0));
          return RayHit{ray.origin + ray.direction * hit->t, facing(normal, ray.direction), hit->t};
        }
      }
    }
    const double t = double(raw.t);
    return RayHit{ray.origin + ray.direction * t, facing(glm::normalize(raw.ng), ray.direction), t};
  }

  std::optional<RayHit> trace(const PreparedRay& ray) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    const FloatRay local = toSceneFrame(ray);
    RTCRayHit rayHit{};
    rayHit.ray.org_x = local.origin.x;
    rayHit.ray.org_y = local.origin.y;
    rayHit.ray.org_z = local.origin.z;
    rayHit.ray.dir_x = local.direction.x;
    rayHit.ray.dir_y = local.direction.y;
    rayHit.ray.dir_z = local.direction.z;
    rayHit.ray.tnear = local.tNear;
    rayHit.ray.tfar = local.tFar;
    rayHit.ray.mask = 0xFFFFFFFFu;
    rayHit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rayHit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene, &context, &rayHit);
    if (rayHit.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
    return resolve(ray, RawHit{rayHit.ray.tfar, rayHit.hit.u, rayHit.hit.v, rayHit.hit.geomID, rayHit.hit.primID,
                               glm::dvec3(rayHit.hit.Ng_x, rayHit.hit.Ng_y, rayHit.hit.Ng_z)});
  }

  void traceMany(std::span<const QueryRay> rays, std::span<std::optional<RayHit>> hits, RayCoherence coherence) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    if (coherence == RayCoherence::Coherent) context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    alignas(64) RTCRayHit16 packet;
    alignas(64) int valid[kPacketSize];
    PreparedRay prepared[kPacketSize];
    for (std::size_t base = 0; base < rays.size(); base += kPacketSize) {
      int active = 0;
      for (int lane = 0; lane < kPacketSize; ++lane) {
        const std::size_t i = base + std::size_t(lane);
        std::optional<PreparedRay> ray = i < rays.size() ? prepare(rays[i]) : std::nullopt;
        valid[lane] = ray ? -1 : 0;
        if (i < rays.size()) hits[i].reset();
        if (!ray) {
          // Inactive lanes still hold a well-formed ray: Embree's packet code may look at them.
          packet.ray.org_x[lane] = packet.ray.org_y[lane] = packet.ray.org_z[lane] = 0.0f;
          packet.ray.dir_x[lane] = packet.ray.dir_y[lane] = 0.0f;
          packet.ray.dir_z[lane] = 1.0f;
          packet.ray.tnear[lane] = 0.0f;
          packet.ray.tfar[lane] = 0.0f;
          packet.ray.time[lane] = 0.0f;
          packet.ray.mask[lane] = 0u;
          packet.ray.id[lane] = unsigned(lane);
          packet.ray.flags[lane] = 0;
          packet.hit.geomID[lane] = RTC_INVALID_GEOMETRY_ID;
          continue;
        }
        ++active;
        prepared[lane] = *ray;
        const FloatRay local = toSceneFrame(*ray);
        packet.ray.org_x[lane] = local.origin.x;
        packet.ray.org_y[lane] = local.origin.y;
        packet.ray.org_z[lane] = local.origin.z;
        packet.ray.dir_x[lane] = local.direction.x;
        packet.ray.dir_y[lane] = local.direction.y;
        packet.ray.dir_z[lane] = local.direction.z;
        packet.ray.tnear[lane] = local.tNear;
        packet.ray.tfar[lane] = local.tFar;
        packet.ray.time[lane] = 0.0f;
        packet.ray.mask[lane] = 0xFFFFFFFFu;
        packet.ray.id[lane] = unsigned(lane);
        packet.ray.flags[lane] = 0;
        packet.hit.geomID[lane] = RTC_INVALID_GEOMETRY_ID;
        packet.hit.instID[0][lane] = RTC_INVALID_GEOMETRY_ID;
      }
      if (active == 0) continue;
      rtcIntersect16(valid, scene, &context, &packet);
      for (int lane = 0; lane < kPacketSize; ++lane) {
        if (!valid[lane] || packet.hit.geomID[lane] == RTC_INVALID_GEOMETRY_ID) continue;
        RawHit raw;
        raw.t = packet.ray.tfar[lane];
        raw.u = packet.hit.u[lane];
        raw.v = packet.hit.v[lane];
        raw.geomID = packet.hit.geomID[lane];
        raw.primID = packet.hit.primID[lane];
        raw.ng = glm::dvec3(packet.hit.Ng_x[lane], packet.hit.Ng_y[lane], packet.hit.Ng_z[lane]);
        hits[base + std::size_t(lane)] = resolve(prepared[lane], raw);
      }
    }
  }

  bool occluded(const glm::dvec3& a, const glm::dvec3& b) const {
    const glm::dvec3 delta = b - a;
    const double length = glm::length(delta);
    const double margin = kSegmentEndUlps * resolution;
    if (length <= 2.0 * margin) return false;
    const PreparedRay ray{a, delta / length, margin, length - margin};
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    const FloatRay local = toSceneFrame(ray);
    RTCRay embreeRay{};
    embreeRay.org_x = local.origin.x;
    embreeRay.org_y = local.origin.y;
    embreeRay.org_z = local.origin.z;
    embreeRay.dir_x = local.direction.x;
    embreeRay.dir_y = local.direction.y;
    embreeRay.dir_z = local.direction.z;
    embreeRay.tnear = local.tNear;
    embreeRay.tfar = local.tFar;
    embreeRay.mask = 0xFFFFFFFFu;
    rtcOccluded1(scene, &context, &embreeRay);
    return embreeRay.tfar == -std::numeric_limits<float>::infinity();  // Embree's mark for "occluded"
  }
};

QueryScene::QueryScene(std::unique_ptr<Impl> impl) : m_impl(std::move(impl)) {}
QueryScene::~QueryScene() = default;

namespace {

Status validateOptions(const QueryOptions& options) {
  if (options.blockCells < 1 || options.blockCells > kMaxGridCells) {
    return makeError(ErrorKind::InvalidArgument, "QueryOptions::blockCells must be in 1.." +
                                                     std::to_string(kMaxGridCells) + ", got " +
                                                     std::to_string(options.blockCells));
  }
  if (options.buildThreads < 0) {
    return makeError(ErrorKind::InvalidArgument,
                     "QueryOptions::buildThreads must be >= 0, got " + std::to_string(options.buildThreads));
  }
  return {};
}

}  // namespace

Result<std::unique_ptr<QueryScene>> QueryScene::create(const terrain::Heightfield& field, const QueryOptions& options) {
  if (Status status = validateOptions(options); !status) return status.error();
  if (field.width < 2 || field.height < 2) {
    return makeError(ErrorKind::InvalidArgument, "QueryScene::create needs at least 2x2 samples, got " +
                                                     std::to_string(field.width) + "x" + std::to_string(field.height));
  }
  if (field.heights.size() != field.sampleCount()) {
    return makeError(ErrorKind::InvalidArgument, "QueryScene::create: the heightfield has " +
                                                     std::to_string(field.heights.size()) + " heights for " +
                                                     std::to_string(field.sampleCount()) + " samples");
  }
  if (!(field.spacingX > 0.0 && field.spacingY > 0.0) || !std::isfinite(field.spacingX) ||
      !std::isfinite(field.spacingY)) {
    return makeError(ErrorKind::InvalidArgument, "QueryScene::create: sample spacing must be finite and positive");
  }
  if (field.sampleCount() > std::size_t(std::numeric_limits<unsigned>::max())) {
    return makeError(ErrorKind::Unsupported,
                     "QueryScene::create: more samples than Embree's 32-bit vertex ids address");
  }

  auto impl = std::make_unique<Impl>();
  impl->options = options;
  // Centre the float frame on the footprint: the largest coordinate, hence the float
  // error, is half the extent.
  impl->origin = glm::dvec3(0.5 * field.extentX(), 0.5 * field.extentY(), 0.0);
  if (Status status = impl->createDevice(); !status) return status.error();

  impl->grid.emplace(field, impl->origin);
  // Embree drops a whole grid primitive that has one non-finite vertex, so blocks with
  // no-data samples go in as triangles instead, leaving out only the triangles that
  // touch such a sample.
  const auto finite = [&](int x, int y) { return std::isfinite(field.at(x, y)); };
  const auto vertexId = [&](glm::ivec2 s) {
    return std::uint32_t(std::size_t(s.y) * std::size_t(field.width) + std::size_t(s.x));
  };
  const int cellsX = field.width - 1, cellsY = field.height - 1, step = options.blockCells;
  for (int y0 = 0; y0 < cellsY; y0 += step) {
    for (int x0 = 0; x0 < cellsX; x0 += step) {
      const GridBlock block{x0, y0, std::min(step, cellsX - x0), std::min(step, cellsY - y0)};
      bool clean = true;
      for (int y = y0; y <= y0 + block.cellsY && clean; ++y) {
        for (int x = x0; x <= x0 + block.cellsX && clean; ++x) clean = finite(x, y);
      }
      if (clean) {
        impl->blocks.push_back(block);
        continue;
      }
      for (int cy = y0; cy < y0 + block.cellsY; ++cy) {
        for (int cx = x0; cx < x0 + block.cellsX; ++cx) {
          for (const detail::TriangleSamples& tri : detail::cellTriangles(cx, cy)) {
            if (!finite(tri[0].x, tri[0].y) || !finite(tri[1].x, tri[1].y) || !finite(tri[2].x, tri[2].y)) continue;
            impl->holeIndices.insert(impl->holeIndices.end(), {vertexId(tri[0]), vertexId(tri[1]), vertexId(tri[2])});
            impl->holeCells.emplace_back(cx, cy);
          }
        }
      }
    }
  }

  if (!impl->blocks.empty()) {
    RTCGeometry geometry = rtcNewGeometry(impl->device, RTC_GEOMETRY_TYPE_GRID);
    if (!geometry) return impl->deviceStatus().error();
    rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, impl->grid->vertexData(), 0,
                               3 * sizeof(float), impl->grid->vertexCount());
    auto* grids = static_cast<RTCGrid*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_GRID, 0, RTC_FORMAT_GRID,
                                                                sizeof(RTCGrid), impl->blocks.size()));
    if (grids) {
      for (std::size_t i = 0; i < impl->blocks.size(); ++i) {
        const GridBlock& block = impl->blocks[i];
        // Vertex (x0, y0) is Embree's "top-left"; its quads (v0, v1, v2, v3) = (x, y),
        // (x+1, y), (x+1, y+1), (x, y+1) split into (v0, v1, v3) and (v2, v3, v1): the
        // diagonal from (x+1, y) to (x, y+1), as terrain/heightfield.hpp requires.
        grids[i].startVertexID = vertexId(glm::ivec2(block.x0, block.y0));
        grids[i].stride = unsigned(field.width);
        grids[i].width = static_cast<unsigned short>(block.cellsX + 1);
        grids[i].height = static_cast<unsigned short>(block.cellsY + 1);
      }
    }
    rtcCommitGeometry(geometry);
    rtcAttachGeometryByID(impl->scene, geometry, kGridGeometryId);
    rtcReleaseGeometry(geometry);
  }
  if (!impl->holeCells.empty()) {
    RTCGeometry geometry = rtcNewGeometry(impl->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    if (!geometry) return impl->deviceStatus().error();
    rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, impl->grid->vertexData(), 0,
                               3 * sizeof(float), impl->grid->vertexCount());
    rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, impl->holeIndices.data(), 0,
                               3 * sizeof(std::uint32_t), impl->holeCells.size());
    rtcCommitGeometry(geometry);
    rtcAttachGeometryByID(impl->scene, geometry, kHoleGeometryId);
    rtcReleaseGeometry(geometry);
  }
  rtcCommitScene(impl->scene);
  if (Status status = impl->deviceStatus(); !status) return status.error();

  double minZ = kInf, maxZ = -kInf;
  for (float h : field.heights) {
    if (!std::isfinite(h)) continue;
    minZ = std::min(minZ, double(h));
    maxZ = std::max(maxZ, double(h));
  }
  if (minZ <= maxZ) {
    impl->boundsMin = glm::dvec3(0.0, 0.0, minZ);
    impl->boundsMax = glm::dvec3(field.extentX(), field.extentY(), maxZ);
  }
  impl->setResolution();
  return std::unique_ptr<QueryScene>(new QueryScene(std::move(impl)));
}

Result<std::unique_ptr<QueryScene>> QueryScene::createFromMeshes(std::span<const MeshData> meshes,
                                                                 const QueryOptions& options) {
  if (Status status = validateOptions(options); !status) return status.error();
  auto impl = std::make_unique<Impl>();
  impl->options = options;
  impl->meshes.reserve(meshes.size());

  for (std::size_t m = 0; m < meshes.size(); ++m) {
    const MeshData& mesh = meshes[m];
    if (mesh.indices.size() % 3 != 0) {
      return makeError(ErrorKind::InvalidArgument, "QueryScene::createFromMeshes: mesh " + std::to_string(m) + " has " +
                                                       std::to_string(mesh.indices.size()) +
                                                       " indices, not a multiple of three");
    }
    for (std::uint32_t index : mesh.indices) {
      if (index >= mesh.positions.size()) {
        return makeError(ErrorKind::InvalidArgument, "QueryScene::createFromMeshes: mesh " + std::to_string(m) +
                                                         " has index " + std::to_string(index) + " but only " +
                                                         std::to_string(mesh.positions.size()) + " positions");
      }
    }
    if (mesh.indices.empty()) continue;
    for (std::uint32_t index : mesh.indices) {
      const glm::dvec3 p = mesh.origin + glm::dvec3(mesh.positions[index]);
      impl->boundsMin = glm::min(impl->boundsMin, p);
      impl->boundsMax = glm::max(impl->boundsMax, p);
    }
  }
  if (impl->boundsMin.x <= impl->boundsMax.x) impl->origin = 0.5 * (impl->boundsMin + impl->boundsMax);
  if (Status status = impl->createDevice(); !status) return status.error();

  for (const MeshData& mesh : meshes) {
    if (mesh.indices.empty()) continue;
    MeshCopy& copy = impl->meshes.emplace_back(MeshCopy{mesh.origin, mesh.positions, mesh.indices});
    RTCGeometry geometry = rtcNewGeometry(impl->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    if (!geometry) return impl->deviceStatus().error();
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                                 3 * sizeof(float), copy.positions.size()));
    if (vertices) {
      const glm::dvec3 offset = copy.origin - impl->origin;
      for (const glm::vec3& p : copy.positions) {
        const glm::dvec3 local = offset + glm::dvec3(p);
        *vertices++ = float(local.x);
        *vertices++ = float(local.y);
        *vertices++ = float(local.z);
      }
    }
    rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, copy.indices.data(), 0,
                               3 * sizeof(std::uint32_t), copy.indices.size() / 3);
    rtcCommitGeometry(geometry);
    rtcAttachGeometryByID(impl->scene, geometry, unsigned(impl->meshes.size() - 1));
    rtcReleaseGeometry(geometry);
    if (Status status = impl->deviceStatus(); !status) return status.error();
  }
  rtcCommitScene(impl->scene);
  if (Status status = impl->deviceStatus(); !status) return status.error();
  impl->setResolution();
  return std::unique_ptr<QueryScene>(new QueryScene(std::move(impl)));
}

std::optional<double> QueryScene::height(double x, double y) const {
  if (m_impl->grid) return m_impl->grid->heightAt(x, y);
  const Impl& impl = *m_impl;
  if (!(x >= impl.boundsMin.x && x <= impl.boundsMax.x && y >= impl.boundsMin.y && y <= impl.boundsMax.y)) {
    return std::nullopt;
  }
  // Straight down from above the scene: the first hit is the highest surface.
  const double top = impl.boundsMax.z + 1.0;
  const auto hit = raycast(glm::dvec3(x, y, top), glm::dvec3(0.0, 0.0, -1.0), top - impl.boundsMin.z + 1.0);
  if (!hit) return std::nullopt;
  return hit->point.z;
}

std::optional<RayHit> QueryScene::raycast(const glm::dvec3& origin, const glm::dvec3& direction,
                                          double maxDistance) const {
  return raycast(QueryRay{origin, direction, 0.0, maxDistance});
}

std::optional<RayHit> QueryScene::raycast(const QueryRay& ray) const {
  const auto prepared = prepare(ray);
  if (!prepared) return std::nullopt;
  return m_impl->trace(*prepared);
}

bool QueryScene::lineOfSight(const glm::dvec3& a, const glm::dvec3& b) const {
  return isTraceable(a) && isTraceable(b) && !m_impl->occluded(a, b);
}

void QueryScene::raycastMany(std::span<const QueryRay> rays, std::span<std::optional<RayHit>> hits,
                             RayCoherence coherence) const {
  assert(rays.size() == hits.size() && "QueryScene::raycastMany: rays and hits differ in size");
  const std::size_t count = std::min(rays.size(), hits.size());
  m_impl->traceMany(rays.first(count), hits.first(count), coherence);
}

glm::dvec3 QueryScene::boundsMin() const { return m_impl->boundsMin; }
glm::dvec3 QueryScene::boundsMax() const { return m_impl->boundsMax; }
double QueryScene::floatResolution() const { return m_impl->resolution; }

std::size_t QueryScene::memoryBytes() const {
  std::size_t bytes = std::size_t(std::max<std::int64_t>(m_impl->monitor.bytes.load(), 0));
  if (m_impl->grid) bytes += m_impl->grid->byteSize();
  for (const MeshCopy& mesh : m_impl->meshes) {
    bytes += mesh.positions.capacity() * sizeof(glm::vec3) + mesh.indices.capacity() * sizeof(std::uint32_t);
  }
  bytes += m_impl->holeIndices.capacity() * sizeof(std::uint32_t) + m_impl->holeCells.capacity() * sizeof(glm::ivec2);
  return bytes + m_impl->blocks.capacity() * sizeof(GridBlock);
}

}  // namespace polder::query
