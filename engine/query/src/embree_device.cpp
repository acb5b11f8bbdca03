#include "embree_device.hpp"

#include <string>
#include <utility>

namespace polder::query::detail {

namespace {

ErrorKind errorKindOf(RTCError code) {
  switch (code) {
    case RTC_ERROR_OUT_OF_MEMORY:
      return ErrorKind::OutOfMemory;
    case RTC_ERROR_INVALID_ARGUMENT:
      return ErrorKind::InvalidArgument;
    case RTC_ERROR_UNSUPPORTED_CPU:
      return ErrorKind::Unsupported;
    default:
      return ErrorKind::Environment;
  }
}

const char* errorName(RTCError code) {
  switch (code) {
    case RTC_ERROR_NONE:
      return "no error";
    case RTC_ERROR_UNKNOWN:
      return "unknown error";
    case RTC_ERROR_INVALID_ARGUMENT:
      return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION:
      return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY:
      return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU:
      return "unsupported CPU";
    case RTC_ERROR_CANCELLED:
      return "cancelled";
  }
  return "unrecognised error";
}

void onDeviceError(void* user, RTCError code, const char* message) {
  auto* monitor = static_cast<DeviceMonitor*>(user);
  std::lock_guard lock(monitor->mutex);
  if (monitor->firstError) return;  // the first error is the cause, later ones follow from it
  std::string text = std::string("Embree: ") + errorName(code);
  if (message && *message) text += std::string(": ") + message;
  monitor->firstError = makeError(errorKindOf(code), std::move(text));
}

bool onDeviceMemory(void* user, ssize_t bytes, bool /*post*/) {
  auto* monitor = static_cast<DeviceMonitor*>(user);
  if (bytes > 0 && monitor->limitBytes > 0 &&
      monitor->bytes.load(std::memory_order_relaxed) + std::int64_t(bytes) > monitor->limitBytes) {
    return false;  // Embree cancels the build with RTC_ERROR_OUT_OF_MEMORY
  }
  monitor->bytes.fetch_add(std::int64_t(bytes), std::memory_order_relaxed);
  return true;
}

}  // namespace

std::optional<Error> DeviceMonitor::takeError() {
  std::lock_guard lock(mutex);
  return std::exchange(firstError, std::nullopt);
}

Result<RTCDevice> newDevice(int threads, DeviceMonitor& monitor) {
  const std::string config = threads > 0 ? "threads=" + std::to_string(threads) : "";
  RTCDevice device = rtcNewDevice(config.c_str());
  if (!device) {
    return makeError(ErrorKind::Environment,
                     std::string("Embree: cannot create a device: ") + errorName(rtcGetDeviceError(nullptr)));
  }
  rtcSetDeviceErrorFunction(device, onDeviceError, &monitor);
  rtcSetDeviceMemoryMonitorFunction(device, onDeviceMemory, &monitor);
  return device;
}

Status deviceStatus(RTCDevice device, DeviceMonitor& monitor) {
  if (auto error = monitor.takeError()) return *error;
  const RTCError code = rtcGetDeviceError(device);
  if (code != RTC_ERROR_NONE) return makeError(errorKindOf(code), std::string("Embree: ") + errorName(code));
  return {};
}

}  // namespace polder::query::detail
