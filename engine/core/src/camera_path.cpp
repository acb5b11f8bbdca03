#include <polder/camera_path.hpp>
#include <polder/file_contents.hpp>

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
    if (std::abs(p.position.x) > kMaxPoseCoordinateM || std::abs(p.position.y) > kMaxPoseCoordinateM ||
        std::abs(p.position.z) > kMaxPoseCoordinateM)
      return makeError(ErrorKind::InvalidArgument,
                       "camera pose " + std::to_string(i + 1) + " lies beyond 1e9 m of the origin");
    if (i > 0 && !(p.timeS > poses[i - 1].timeS))
      return makeError(ErrorKind::InvalidArgument,
                       "camera pose " + std::to_string(i + 1) + ": times must increase strictly");
  }
  CameraPath path;
  path.m_poses = std::move(poses);
  path.m_closedLoop = closedLoop && path.m_poses.size() > 1;
  return path;
}

// Millions of poses; a larger file is refused before it is read.
constexpr std::uint64_t kMaxCameraPathFileBytes = 256 << 20;

Result<CameraPath> CameraPath::readFile(const std::filesystem::path& file) {
  auto text = core::readFileContents(file, kMaxCameraPathFileBytes);
  if (!text) return makeError(text.error().kind, file.string() + ": " + text.error().message);
  auto path = parse(*text);
  if (!path) return makeError(ErrorKind::InvalidData, file.string() + ": " + path.error().message);
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

namespace {

// The options both loops share (FlyoverOptions, OrbitOptions).
template <typename LoopOptions>
Status checkLoopOptions(double extentX, double extentY, const LoopOptions& options) {
  if (!(extentX > 0.0) || !(extentY > 0.0) || !std::isfinite(extentX) || !std::isfinite(extentY))
    return makeError(ErrorKind::InvalidArgument, "a loop needs a finite, positive terrain extent");
  if (!(options.speedMps > 0.0) || !std::isfinite(options.speedMps))
    return makeError(ErrorKind::InvalidArgument, "the flight speed must be a finite, positive number");
  if (!(options.altitudeM >= 0.0) || !std::isfinite(options.altitudeM))
    return makeError(ErrorKind::InvalidArgument, "the flight altitude must be a finite number, not negative");
  if (!(options.radiusFraction > 0.0) || !(options.radiusFraction <= 1.0))
    return makeError(ErrorKind::InvalidArgument, "the loop's radius must be a fraction of the extent in (0, 1]");
  if (options.samples < 8 || options.samples > 1000000)
    return makeError(ErrorKind::InvalidArgument, "a loop takes 8..1,000,000 poses");
  return {};
}

// For each i, the largest of values[i - window .. i + window] around the loop, in O(n) (a
// monotonic queue); a window of half the loop or more sees all of it.
std::vector<double> loopWindowMax(const std::vector<double>& values, int window) {
  const int n = int(values.size());
  if (2 * window + 1 >= n) return std::vector<double>(values.size(), *std::max_element(values.begin(), values.end()));
  std::vector<double> out(values.size());
  std::vector<int> queue(std::size_t(3 * n));  // indices into the loop unrolled, values decreasing
  std::size_t head = 0, tail = 0;
  const auto at = [&](int i) { return values[std::size_t(((i % n) + n) % n)]; };
  for (int i = -2 * window; i < n; ++i) {
    const int entering = i + window;
    while (tail > head && at(queue[tail - 1]) <= at(entering)) --tail;
    queue[tail++] = entering;
    while (queue[head] < i - window) ++head;
    if (i >= 0) out[std::size_t(i)] = at(queue[head]);
  }
  return out;
}

// For each i, the mean of values[i - window .. i + window] around the loop, in O(n).
std::vector<double> loopWindowMean(const std::vector<double>& values, int window) {
  const int n = int(values.size());
  std::vector<double> prefix(std::size_t(n) + 1, 0.0);
  for (int i = 0; i < n; ++i) prefix[std::size_t(i) + 1] = prefix[std::size_t(i)] + values[std::size_t(i)];
  // Sum over the unrolled range [a, b] (any integers): whole laps plus the remainders.
  const auto sumTo = [&](long long end) {  // sum of unrolled indices [0, end)
    const long long laps = end >= 0 ? end / n : -((-end + n - 1) / n);
    const long long rest = end - laps * n;
    return double(laps) * prefix[std::size_t(n)] + prefix[std::size_t(rest)];
  };
  std::vector<double> out(values.size());
  for (int i = 0; i < n; ++i)
    out[std::size_t(i)] = (sumTo(i + window + 1LL) - sumTo(i - window)) / double(2LL * window + 1);
  return out;
}

}  // namespace

Result<CameraPath> makeFlyoverLoop(double extentX, double extentY,
                                   const std::function<double(double, double)>& groundHeight,
                                   const FlyoverOptions& options) {
  if (Status valid = checkLoopOptions(extentX, extentY, options); !valid) return valid.error();
  if (!std::isfinite(options.pitchDeg) || std::abs(options.pitchDeg) > 90.0)
    return makeError(ErrorKind::InvalidArgument, "the flight's pitch must lie in -90..90 degrees");
  const int n = options.samples;
  const auto count = static_cast<std::size_t>(n);
  const glm::dvec2 centre{0.5 * extentX, 0.5 * extentY};
  const glm::dvec2 radius{options.radiusFraction * extentX, options.radiusFraction * extentY};

  std::vector<glm::dvec2> points(count);
  std::vector<double> ground(count);
  for (int i = 0; i < n; ++i) {
    const double angle = 2.0 * kPi * double(i) / double(n);
    points[std::size_t(i)] = centre + glm::dvec2(radius.x * std::sin(angle), radius.y * std::cos(angle));
    ground[std::size_t(i)] = groundHeight(points[std::size_t(i)].x, points[std::size_t(i)].y);
    if (!std::isfinite(ground[std::size_t(i)])) ground[std::size_t(i)] = 0.0;
  }
  double perimeter = 0.0;
  for (int i = 0; i < n; ++i) perimeter += glm::length(points[std::size_t((i + 1) % n)] - points[std::size_t(i)]);
  const double stepM = perimeter / double(n);
  if (!(stepM > 0.0) || !std::isfinite(stepM))
    return makeError(ErrorKind::InvalidArgument, "the terrain's extent is too small or too large for a loop");

  // Clear the highest ground within ~600 m (at least two samples) either way, then smooth
  // the result so the flight does not bob; the mean never dips under the point's own ground.
  const int window = int(std::clamp(std::ceil(600.0 / stepM), 2.0, double(n)));
  const std::vector<double> clearance = loopWindowMax(ground, window);
  std::vector<double> smoothed = loopWindowMean(clearance, window);
  for (std::size_t i = 0; i < count; ++i) smoothed[i] = std::max(smoothed[i], ground[i]);
  auto wrap = [n](int i) { return std::size_t(((i % n) + n) % n); };

  std::vector<CameraPose> poses(count);
  const double stepS = stepM / options.speedMps;
  for (int i = 0; i < n; ++i) {
    const glm::dvec2 ahead = points[wrap(i + 1)] - points[wrap(i - 1)];
    const double yaw = std::atan2(ahead.x, ahead.y) * 180.0 / kPi;
    poses[std::size_t(i)] =
        CameraPose{i * stepS,
                   {points[std::size_t(i)].x, points[std::size_t(i)].y, smoothed[std::size_t(i)] + options.altitudeM},
                   yaw,
                   options.pitchDeg};
  }
  return CameraPath::fromPoses(std::move(poses), true);
}

Result<CameraPath> makeOrbitLoop(double extentX, double extentY,
                                 const std::function<double(double, double)>& groundHeight,
                                 const OrbitOptions& options) {
  if (Status valid = checkLoopOptions(extentX, extentY, options); !valid) return valid.error();
  const int n = options.samples;
  const glm::dvec2 centre{0.5 * extentX, 0.5 * extentY};
  const double radius = options.radiusFraction * std::min(extentX, extentY);
  double highest = groundHeight(centre.x, centre.y);
  for (int i = 0; i < n; ++i) {
    const double angle = 2.0 * kPi * double(i) / double(n);
    highest = std::max(highest, groundHeight(centre.x + radius * std::sin(angle), centre.y + radius * std::cos(angle)));
  }
  const double altitude = highest + options.altitudeM;
  const glm::dvec3 target{centre.x, centre.y, groundHeight(centre.x, centre.y)};
  const double stepS = 2.0 * kPi * radius / double(n) / options.speedMps;
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
  return CameraPath::fromPoses(std::move(poses), true);
}

}  // namespace polder
