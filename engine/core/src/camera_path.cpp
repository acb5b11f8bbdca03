#include <polder/camera_path.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <string>

namespace polder {

namespace {

constexpr double kPi = 3.14159265358979323846;

double lerpAngleDeg(double a, double b, double t) {
  const double delta = std::remainder(b - a, 360.0);  // shortest signed arc
  return a + delta * t;
}

CameraPose interpolate(const CameraPose& a, const CameraPose& b, double timeS) {
  const double span = b.timeS - a.timeS;
  const double t = span > 0.0 ? std::clamp((timeS - a.timeS) / span, 0.0, 1.0) : 0.0;
  return CameraPose{timeS, glm::mix(a.position, b.position, t), lerpAngleDeg(a.yawDeg, b.yawDeg, t),
                    a.pitchDeg + (b.pitchDeg - a.pitchDeg) * t};
}

bool parseLineNumbers(std::string_view line, double (&values)[6]) {
  std::size_t count = 0;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    if (i >= line.size()) break;
    if (count == 6) return false;
    const char* begin = line.data() + i;
    const auto [end, error] = std::from_chars(begin, line.data() + line.size(), values[count]);
    if (error != std::errc() || !std::isfinite(values[count])) return false;
    i += std::size_t(end - begin);
    if (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') return false;
    ++count;
  }
  return count == 6;
}

}  // namespace

Result<CameraPath> CameraPath::fromPoses(std::vector<CameraPose> poses, bool closedLoop) {
  if (poses.empty()) return makeError(ErrorKind::InvalidArgument, "a camera path needs at least one pose");
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const auto& p = poses[i];
    if (!std::isfinite(p.timeS) || !std::isfinite(p.position.x) || !std::isfinite(p.position.y) ||
        !std::isfinite(p.position.z) || !std::isfinite(p.yawDeg) || !std::isfinite(p.pitchDeg))
      return makeError(ErrorKind::InvalidArgument, "camera pose " + std::to_string(i + 1) + " has a non-finite value");
    if (i > 0 && !(p.timeS > poses[i - 1].timeS))
      return makeError(ErrorKind::InvalidArgument,
                       "camera pose " + std::to_string(i + 1) + ": times must increase strictly");
  }
  CameraPath path;
  path.m_poses = std::move(poses);
  path.m_closedLoop = closedLoop && path.m_poses.size() > 1;
  return path;
}

Result<CameraPath> CameraPath::parse(std::string_view text) {
  std::vector<CameraPose> poses;
  std::size_t lineNumber = 0;
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t newline = std::min(text.find('\n', start), text.size());
    std::string_view line = text.substr(start, newline - start);
    start = newline + 1;
    ++lineNumber;
    line = line.substr(0, std::min(line.find('#'), line.size()));
    if (line.find_first_not_of(" \t\r") == std::string_view::npos) continue;
    double v[6];
    if (!parseLineNumbers(line, v))
      return makeError(ErrorKind::InvalidData, "line " + std::to_string(lineNumber) +
                                                   ": expected 't x y z yaw pitch' (six numbers), got '" +
                                                   std::string(line) + "'");
    if (!poses.empty() && !(v[0] > poses.back().timeS))
      return makeError(ErrorKind::InvalidData,
                       "line " + std::to_string(lineNumber) + ": time " + std::to_string(v[0]) + " does not increase");
    if (std::abs(v[5]) > 90.0)
      return makeError(ErrorKind::InvalidData, "line " + std::to_string(lineNumber) + ": pitch must be within -90..90");
    poses.push_back(CameraPose{v[0], {v[1], v[2], v[3]}, v[4], v[5]});
  }
  if (poses.empty()) return makeError(ErrorKind::InvalidData, "the camera path has no poses");
  return fromPoses(std::move(poses));
}

CameraPose CameraPath::at(double timeS) const {
  const double start = m_poses.front().timeS;
  if (m_closedLoop) {
    // The loop closes from the last pose back to the first over one mean step.
    const double step = durationS() / double(m_poses.size() - 1);
    const double period = durationS() + step;
    double local = std::fmod(timeS - start, period);
    if (local < 0.0) local += period;
    if (local > durationS()) {
      CameraPose wrapped = m_poses.front();
      wrapped.timeS = m_poses.back().timeS + step;
      CameraPose pose = interpolate(m_poses.back(), wrapped, start + local);
      pose.timeS = timeS;
      return pose;
    }
    timeS = start + local;
  }
  if (timeS <= start)
    return CameraPose{timeS, m_poses.front().position, m_poses.front().yawDeg, m_poses.front().pitchDeg};
  if (timeS >= m_poses.back().timeS)
    return CameraPose{timeS, m_poses.back().position, m_poses.back().yawDeg, m_poses.back().pitchDeg};
  const auto next = std::upper_bound(m_poses.begin(), m_poses.end(), timeS,
                                     [](double t, const CameraPose& pose) { return t < pose.timeS; });
  return interpolate(*(next - 1), *next, timeS);
}

CameraPath makeFlyoverLoop(double extentX, double extentY, const std::function<double(double, double)>& groundHeight,
                           const FlyoverOptions& options) {
  const int n = std::max(options.samples, 8);
  const auto count = static_cast<std::size_t>(n);
  const glm::dvec2 centre{0.5 * extentX, 0.5 * extentY};
  const glm::dvec2 radius{options.radiusFraction * extentX, options.radiusFraction * extentY};

  std::vector<glm::dvec2> points(count);
  std::vector<double> ground(count);
  for (int i = 0; i < n; ++i) {
    const double angle = 2.0 * kPi * double(i) / double(n);
    points[std::size_t(i)] = centre + glm::dvec2(radius.x * std::sin(angle), radius.y * std::cos(angle));
    ground[std::size_t(i)] = groundHeight(points[std::size_t(i)].x, points[std::size_t(i)].y);
  }
  double perimeter = 0.0;
  for (int i = 0; i < n; ++i) perimeter += glm::length(points[std::size_t((i + 1) % n)] - points[std::size_t(i)]);
  const double stepM = perimeter / double(n);

  // Clear the highest ground within ~600 m (at least two samples) either way, then smooth
  // the result so the flight does not bob.
  const int window = std::max(2, int(std::ceil(600.0 / std::max(stepM, 1e-9))));
  auto wrap = [n](int i) { return std::size_t(((i % n) + n) % n); };
  std::vector<double> clearance(count);
  for (int i = 0; i < n; ++i) {
    double highest = ground[std::size_t(i)];
    for (int k = -window; k <= window; ++k) highest = std::max(highest, ground[wrap(i + k)]);
    clearance[std::size_t(i)] = highest;
  }
  std::vector<double> smoothed(count);
  for (int i = 0; i < n; ++i) {
    double sum = 0.0;
    for (int k = -window; k <= window; ++k) sum += clearance[wrap(i + k)];
    // The mean never dips under the point's own ground: keep the max of both.
    smoothed[std::size_t(i)] = std::max(sum / double(2 * window + 1), ground[std::size_t(i)]);
  }

  std::vector<CameraPose> poses(count);
  const double stepS = stepM / std::max(options.speedMps, 1e-6);
  for (int i = 0; i < n; ++i) {
    const glm::dvec2 ahead = points[wrap(i + 1)] - points[wrap(i - 1)];
    const double yaw = std::atan2(ahead.x, ahead.y) * 180.0 / kPi;
    poses[std::size_t(i)] =
        CameraPose{i * stepS,
                   {points[std::size_t(i)].x, points[std::size_t(i)].y, smoothed[std::size_t(i)] + options.altitudeM},
                   yaw,
                   options.pitchDeg};
  }
  return std::move(CameraPath::fromPoses(std::move(poses), true).value());
}

CameraPath makeOrbitLoop(double extentX, double extentY, const std::function<double(double, double)>& groundHeight,
                         const OrbitOptions& options) {
  const int n = std::max(options.samples, 8);
  const glm::dvec2 centre{0.5 * extentX, 0.5 * extentY};
  const double radius = options.radiusFraction * std::min(extentX, extentY);
  double highest = groundHeight(centre.x, centre.y);
  for (int i = 0; i < n; ++i) {
    const double angle = 2.0 * kPi * double(i) / double(n);
    highest = std::max(highest, groundHeight(centre.x + radius * std::sin(angle), centre.y + radius * std::cos(angle)));
  }
  const double altitude = highest + options.altitudeM;
  const glm::dvec3 target{centre.x, centre.y, groundHeight(centre.x, centre.y)};
  const double stepS = 2.0 * kPi * radius / double(n) / std::max(options.speedMps, 1e-6);
  std::vector<CameraPose> poses;
  poses.reserve(std::size_t(n));
  for (int i = 0; i < n; ++i) {
    const double angle = 2.0 * kPi * double(i) / double(n);
    const glm::dvec3 position{centre.x + radius * std::sin(angle), centre.y + radius * std::cos(angle), altitude};
    const glm::dvec3 look = target - position;
    const double yaw = std::atan2(look.x, look.y) * 180.0 / kPi;
    const double pitch = std::atan2(look.z, std::hypot(look.x, look.y)) * 180.0 / kPi;
    poses.push_back(CameraPose{i * stepS, position, yaw, pitch});
  }
  return std::move(CameraPath::fromPoses(std::move(poses), true).value());
}

}  // namespace polder
