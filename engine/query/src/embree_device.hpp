// The Embree device both Embree adapters start from (query_scene.cpp for rays,
// closest_point_scene.cpp for point queries): created with a build thread count, its errors
// and allocations recorded in a monitor the scene owns (never process-global).
#pragma once

#include <atomic>
#include <cstdint>
#include <mutex>
#include <optional>

#include <embree3/rtcore.h>

#include <polder/result.hpp>

namespace polder::query::detail {

// What the device's callbacks report. They may run on Embree's build threads, hence the
// mutex and the atomic. Must outlive the device.
struct DeviceMonitor {
  std::mutex mutex;
  std::optional<Error> firstError;
  std::atomic<std::int64_t> bytes{0};
  std::int64_t limitBytes = 0;  // 0 = none; allocations past it fail with OutOfMemory

  std::optional<Error> takeError();
};

// A device building with `threads` threads (0 or less = Embree's default), reporting to
// `monitor`. Fails with Environment where Embree cannot create one.
Result<RTCDevice> newDevice(int threads, DeviceMonitor& monitor);

// The first error the device reported since the last call, if any.
Status deviceStatus(RTCDevice device, DeviceMonitor& monitor);

}  // namespace polder::query::detail
