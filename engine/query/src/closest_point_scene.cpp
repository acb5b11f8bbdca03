// Embree point queries (Embree 3 API: rtcPointQuery with a per-query callback). Like
// query_scene.cpp and embree_device.cpp, the other files that call Embree, this one moves
// to Embree 4 as a whole.
#include "closest_point_scene.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include <embree3/rtcore.h>

#include "embree_device.hpp"

namespace polder::query::detail {

namespace {

using TriangleCorners = std::array<glm::dvec3, 3>;

// Embree compares the query sphere with its boxes in single precision, from a query point
// rounded to float. The radius it searches is the best distance so far plus this many
// times the largest coordinate involved, so rounding never prunes a triangle that is
// closer in double precision.
constexpr double kRadiusSlack = 8.0 * double(std::numeric_limits<float>::epsilon());

}  // namespace

struct ClosestPointScene::Impl {
  DeviceMonitor monitor;  // first: the device's callbacks point at it
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<TriangleCorners> corners;  // per triangle, in double: the callback reads only these
  double largestCoordinate = 0.0;

  Impl() = default;
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

namespace {

// What one query carries through Embree's callbacks.
struct Search {
  const TriangleCorners* corners = nullptr;
  glm::dvec3 point{0.0};
  double slack = 0.0;
  std::optional<ClosestTriangle> best;
};

bool onCandidate(RTCPointQueryFunctionArguments* args) {
  auto* search = static_cast<Search*>(args->userPtr);
  const TriangleCorners& corner = search->corners[args->primID];
  const glm::dvec3& p = search->point;
  if (search->best) {
    // Embree calls back for every triangle of a leaf whose box meets the query sphere; the
    // triangle's own box rules most of them out at a fraction of the exact test's cost.
    const glm::dvec3 low = glm::min(glm::min(corner[0], corner[1]), corner[2]);
    const glm::dvec3 high = glm::max(glm::max(corner[0], corner[1]), corner[2]);
    const glm::dvec3 outside = glm::max(glm::max(low - p, p - high), glm::dvec3(0.0));
    if (glm::dot(outside, outside) >= search->best->distanceSquared) return false;
  }
  const TrianglePoint closest = closestPointOnTriangle(p, corner[0], corner[1], corner[2]);
  const glm::dvec3 offset = closest.point - search->point;
  const double distanceSquared = glm::dot(offset, offset);
  // Ties keep the first triangle found, so the answer does not flip between equals.
  if (search->best && distanceSquared >= search->best->distanceSquared) return false;
  search->best = ClosestTriangle{args->primID, closest, distanceSquared};
  args->query->radius = float(std::sqrt(distanceSquared) + search->slack);
  return true;  // the radius shrank
}

}  // namespace

ClosestPointScene::ClosestPointScene(std::unique_ptr<Impl> impl) : m_impl(std::move(impl)) {}
ClosestPointScene::~ClosestPointScene() = default;

Result<std::unique_ptr<ClosestPointScene>> ClosestPointScene::create(std::span<const glm::vec3> positions,
                                                                     std::span<const std::uint32_t> indices,
                                                                     int buildThreads) {
  auto impl = std::make_unique<Impl>();
  const std::size_t triangleCount = indices.size() / 3;
  impl->corners.resize(triangleCount);
  for (std::size_t t = 0; t < triangleCount; ++t) {
    for (int k = 0; k < 3; ++k)
      impl->corners[t][std::size_t(k)] = glm::dvec3(positions[indices[3 * t + std::size_t(k)]]);
  }
  for (const glm::vec3& p : positions) {
    impl->largestCoordinate =
        std::max({impl->largestCoordinate, double(std::abs(p.x)), double(std::abs(p.y)), double(std::abs(p.z))});
  }

  auto device = newDevice(buildThreads, impl->monitor);
  if (!device) return device.error();
  impl->device = *device;
  impl->scene = rtcNewScene(impl->device);
  if (!impl->scene) return deviceStatus(impl->device, impl->monitor).error();

  if (triangleCount > 0) {
    RTCGeometry geometry = rtcNewGeometry(impl->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    if (!geometry) return deviceStatus(impl->device, impl->monitor).error();
    // Buffers Embree allocates (and pads for its vector loads) and owns: copies of the mesh.
    if (auto* vertices = static_cast<glm::vec3*>(rtcSetNewGeometryBuffer(
            geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, sizeof(glm::vec3), positions.size()))) {
      std::copy(positions.begin(), positions.end(), vertices);
    }
    if (auto* triangles = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(
            geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(std::uint32_t), triangleCount))) {
      std::copy(indices.begin(), indices.begin() + std::ptrdiff_t(3 * triangleCount), triangles);
    }
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(impl->scene, geometry);
    rtcReleaseGeometry(geometry);
  }
  rtcCommitScene(impl->scene);
  if (Status status = deviceStatus(impl->device, impl->monitor); !status) return status.error();
  return std::unique_ptr<ClosestPointScene>(new ClosestPointScene(std::move(impl)));
}

std::optional<ClosestTriangle> ClosestPointScene::closest(const glm::dvec3& point, double within) const {
  if (!std::isfinite(point.x) || !std::isfinite(point.y) || !std::isfinite(point.z)) return std::nullopt;
  Search search;
  search.corners = m_impl->corners.data();
  search.point = point;
  const double largest =
      std::max({m_impl->largestCoordinate, std::abs(point.x), std::abs(point.y), std::abs(point.z), 1e-30});
  search.slack = kRadiusSlack * largest;

  RTCPointQuery query;
  query.x = float(point.x);
  query.y = float(point.y);
  query.z = float(point.z);
  query.time = 0.0f;
  // float() of a double past float's range is undefined; such a bound prunes nothing anyway.
  const double radius = within + search.slack;
  query.radius =
      radius < double(std::numeric_limits<float>::max()) ? float(radius) : std::numeric_limits<float>::infinity();
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  rtcPointQuery(m_impl->scene, &query, &context, onCandidate, &search);
  return search.best;
}

}  // namespace polder::query::detail
