// Embree point queries (Embree 3 API: rtcPointQuery with a per-query callback). Like
// query_scene.cpp, the only other file that calls Embree, this one moves to Embree 4 as a
// whole.
#include "closest_point_scene.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include <embree3/rtcore.h>

namespace polder::query::detail {

namespace {

using TriangleCorners = std::array<glm::dvec3, 3>;

// Embree compares the query sphere with its boxes in single precision, from a query point
// rounded to float. The radius it searches is the best distance so far plus this many
// times the largest coordinate involved, so rounding never prunes a triangle that is
// closer in double precision.
constexpr double kRadiusSlack = 8.0 * double(std::numeric_limits<float>::epsilon());

ErrorKind errorKindOf(RTCError code) {
  switch (code) {
    case RTC_ERROR_OUT_OF_MEMORY: return ErrorKind::OutOfMemory;
    case RTC_ERROR_UNSUPPORTED_CPU: return ErrorKind::Unsupported;
    default: return ErrorKind::Environment;
  }
}

// The first error the device reported, owned per scene (the callback may run on Embree's
// build threads).
struct DeviceErrors {
  std::mutex mutex;
  std::optional<Error> first;
};

void onDeviceError(void* user, RTCError code, const char* message) {
  auto* errors = static_cast<DeviceErrors*>(user);
  std::lock_guard lock(errors->mutex);
  if (errors->first) return;  // later errors follow from the first
  std::string text = "Embree (closest-point scene): error " + std::to_string(int(code));
  if (message && *message) text += std::string(": ") + message;
  errors->first = makeError(errorKindOf(code), std::move(text));
}

}  // namespace

struct ClosestPointScene::Impl {
  DeviceErrors errors;  // first: the device's callback points at it
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<glm::vec3> positions;    // one spare at the end: Embree reads vertices 16 bytes at a time
  std::vector<std::uint32_t> indices;  // shared with Embree
  std::vector<TriangleCorners> corners;  // per triangle, in double: the callback reads only these
  std::size_t vertexCount = 0;
  double largestCoordinate = 0.0;

  Impl() = default;
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;
  ~Impl() {
    if (scene) rtcReleaseScene(scene);  // first: it reads the buffers until released
    if (device) rtcReleaseDevice(device);
  }

  Status status() {
    std::lock_guard lock(errors.mutex);
    if (errors.first) return *std::exchange(errors.first, std::nullopt);
    return {};
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
  impl->vertexCount = positions.size();
  impl->positions.reserve(positions.size() + 1);
  impl->positions.assign(positions.begin(), positions.end());
  impl->positions.emplace_back(0.0f);
  impl->indices.assign(indices.begin(), indices.end());
  impl->corners.resize(impl->indices.size() / 3);
  for (std::size_t t = 0; t < impl->corners.size(); ++t) {
    for (int k = 0; k < 3; ++k) impl->corners[t][std::size_t(k)] = glm::dvec3(positions[impl->indices[3 * t + std::size_t(k)]]);
  }
  for (const glm::vec3& p : positions) {
    impl->largestCoordinate = std::max({impl->largestCoordinate, double(std::abs(p.x)), double(std::abs(p.y)),
                                        double(std::abs(p.z))});
  }

  const std::string config = buildThreads > 0 ? "threads=" + std::to_string(buildThreads) : "";
  impl->device = rtcNewDevice(config.c_str());
  if (!impl->device) {
    return makeError(ErrorKind::Environment, "Embree: cannot create a device (error " +
                                                 std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
  }
  rtcSetDeviceErrorFunction(impl->device, onDeviceError, &impl->errors);
  impl->scene = rtcNewScene(impl->device);
  if (!impl->scene) return impl->status().error();

  const std::size_t triangleCount = impl->indices.size() / 3;
  if (triangleCount > 0) {
    RTCGeometry geometry = rtcNewGeometry(impl->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    if (!geometry) return impl->status().error();
    rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, impl->positions.data(), 0,
                               sizeof(glm::vec3), impl->vertexCount);
    rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, impl->indices.data(), 0,
                               3 * sizeof(std::uint32_t), triangleCount);
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(impl->scene, geometry);
    rtcReleaseGeometry(geometry);
  }
  rtcCommitScene(impl->scene);
  if (Status status = impl->status(); !status) return status.error();
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
  query.radius = radius < double(std::numeric_limits<float>::max()) ? float(radius)
                                                                     : std::numeric_limits<float>::infinity();
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  rtcPointQuery(m_impl->scene, &query, &context, onCandidate, &search);
  return search.best;
}

}  // namespace polder::query::detail
