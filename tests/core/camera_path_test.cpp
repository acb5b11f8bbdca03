#include <polder/camera.hpp>
#include <polder/camera_path.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

namespace polder {
namespace {

TEST(CameraPath, InterpolatesPositionAndTakesTheShorterArcForYaw) {
  auto path = CameraPath::fromPoses({{0.0, {0, 0, 100}, 350.0, -10.0}, {2.0, {200, 0, 100}, 10.0, 10.0}});
  ASSERT_TRUE(path.ok());
  const CameraPose mid = path->at(1.0);
  EXPECT_NEAR(mid.position.x, 100.0, 1e-9);
  EXPECT_NEAR(std::remainder(mid.yawDeg, 360.0), 0.0, 1e-9);  // through north, not through south
  EXPECT_NEAR(mid.pitchDeg, 0.0, 1e-9);
  EXPECT_NEAR(path->at(-5.0).position.x, 0.0, 1e-12);   // holds before the start
  EXPECT_NEAR(path->at(9.0).position.x, 200.0, 1e-12);  // and after the end
}

TEST(CameraPath, ParsesTextWithCommentsAndNamesTheBadLine) {
  auto path = CameraPath::parse("# t x y z yaw pitch\n0 1 2 3 45 -5\n\n1.5 4 5 6 90 -10 # cruise\n");
  ASSERT_TRUE(path.ok()) << path.error().message;
  ASSERT_EQ(path->poses().size(), 2u);
  EXPECT_DOUBLE_EQ(path->poses()[1].position.z, 6.0);

  auto bad = CameraPath::parse("0 1 2 3 45 -5\n1 4 5 six 90 -10\n");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("line 2"), std::string::npos) << bad.error().message;

  auto backwards = CameraPath::parse("1 0 0 0 0 0\n0.5 0 0 0 0 0\n");
  ASSERT_FALSE(backwards.ok());
  EXPECT_NE(backwards.error().message.find("does not increase"), std::string::npos);

  EXPECT_FALSE(CameraPath::parse("# nothing\n").ok());
  EXPECT_FALSE(CameraPath::parse("0 0 0 0 0 95\n").ok());
}

TEST(FlyoverLoop, StaysAboveTheGroundAtTheRequestedAltitudeAndCloses) {
  // A ridge across the middle of a 10 km square.
  auto ground = [](double x, double y) { return 800.0 * std::exp(-std::pow((y - 5000.0) / 600.0, 2.0)) + 0.01 * x; };
  FlyoverOptions options;
  options.altitudeM = 250.0;
  const CameraPath path = makeFlyoverLoop(10000.0, 10000.0, ground, options).value();
  ASSERT_TRUE(path.closedLoop());
  double closest = 1e300;
  for (double t = 0.0; t < path.durationS() * 1.5; t += path.durationS() / 997.0) {
    const CameraPose pose = path.at(t);
    closest = std::min(closest, pose.position.z - ground(pose.position.x, pose.position.y));
    EXPECT_GE(pose.position.x, 0.0);
    EXPECT_LE(pose.position.x, 10000.0);
  }
  EXPECT_GE(closest, options.altitudeM - 1.0);
  // Speed along the loop is the requested one.
  const CameraPose a = path.at(10.0), b = path.at(11.0);
  EXPECT_NEAR(glm::length(glm::dvec2(b.position - a.position)), options.speedMps, 0.02 * options.speedMps);
  // Looking along the direction of travel.
  const glm::dvec2 travel = glm::normalize(glm::dvec2(b.position - a.position));
  const double yaw = a.yawDeg * 3.14159265358979323846 / 180.0;
  EXPECT_GT(glm::dot(travel, glm::dvec2(std::sin(yaw), std::cos(yaw))), 0.99);
}

// A rough ground: neighbouring poses see unrelated heights, so a wrong window shows.
double roughGround(double x, double y) {
  const double h = std::sin(x * 12.9898 + y * 78.233) * 43758.5453;
  return 500.0 * (h - std::floor(h)) + 0.05 * x;
}

// What the loop's heights must be, computed directly: the highest ground within the window
// either way, its mean over the window, never under the point's own ground.
std::vector<double> directClearance(double extentX, double extentY, const FlyoverOptions& options) {
  const int n = options.samples;
  const auto count = std::size_t(n);
  std::vector<glm::dvec2> points(count);
  std::vector<double> ground(count);
  for (int i = 0; i < n; ++i) {
    const double angle = 2.0 * 3.14159265358979323846 * double(i) / double(n);
    points[std::size_t(i)] = glm::dvec2(0.5 * extentX + options.radiusFraction * extentX * std::sin(angle),
                                        0.5 * extentY + options.radiusFraction * extentY * std::cos(angle));
    ground[std::size_t(i)] = roughGround(points[std::size_t(i)].x, points[std::size_t(i)].y);
  }
  double perimeter = 0.0;
  for (int i = 0; i < n; ++i) perimeter += glm::length(points[std::size_t((i + 1) % n)] - points[std::size_t(i)]);
  const int window = int(std::clamp(std::ceil(600.0 / (perimeter / n)), 2.0, double(n)));
  const auto at = [&](const std::vector<double>& v, int i) { return v[std::size_t(((i % n) + n) % n)]; };
  std::vector<double> highest(count), out(count);
  for (int i = 0; i < n; ++i) {
    highest[std::size_t(i)] = -1e300;
    for (int k = -window; k <= window; ++k)
      highest[std::size_t(i)] = std::max(highest[std::size_t(i)], at(ground, i + k));
  }
  for (int i = 0; i < n; ++i) {
    double sum = 0.0;
    for (int k = -window; k <= window; ++k) sum += at(highest, i + k);
    out[std::size_t(i)] = std::max(sum / (2 * window + 1), ground[std::size_t(i)]) + options.altitudeM;
  }
  return out;
}

TEST(FlyoverLoop, HeightsAreTheWindowedClearanceForNarrowAndWholeLoopWindows) {
  // 10 km: a window of a few dozen poses; 300 m: the window spans the whole loop.
  for (const double extent : {10000.0, 300.0}) {
    FlyoverOptions options;
    options.samples = 360;
    const CameraPath path = makeFlyoverLoop(extent, extent, roughGround, options).value();
    const std::vector<double> expected = directClearance(extent, extent, options);
    ASSERT_EQ(path.poses().size(), expected.size());
    for (std::size_t i = 0; i < expected.size(); ++i)
      ASSERT_NEAR(path.poses()[i].position.z, expected[i], 1e-6 * std::abs(expected[i])) << extent << " m, pose " << i;
  }
}

TEST(FlyoverLoop, ATinyTerrainStillGivesAFinitePath) {
  // A 0.1 m terrain: the 600 m window is millions of poses wide, the work stays O(samples).
  const CameraPath path = makeFlyoverLoop(0.1, 0.1, [](double, double) { return 3.0; }, {}).value();
  for (const CameraPose& pose : path.poses()) {
    ASSERT_TRUE(std::isfinite(pose.position.z) && std::isfinite(pose.timeS));
    ASSERT_NEAR(pose.position.z, 303.0, 1e-9);
  }
}

TEST(FlightLoops, RefuseSettingsThatAreNotFiniteOrOutOfRange) {
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  auto flat = [](double, double) { return 0.0; };
  // One setting spoiled in both loops' options: both must refuse it.
  const auto refusedByBoth = [&](auto spoil) {
    FlyoverOptions fly;
    spoil(fly);
    OrbitOptions orbit;
    spoil(orbit);
    return !makeFlyoverLoop(1000, 1000, flat, fly).ok() && !makeOrbitLoop(1000, 1000, flat, orbit).ok();
  };
  for (const double speed : {nan, inf, -inf, -1.0, 0.0})
    EXPECT_TRUE(refusedByBoth([speed](auto& options) { options.speedMps = speed; })) << speed;
  for (const double altitude : {nan, inf, -1.0})
    EXPECT_TRUE(refusedByBoth([altitude](auto& options) { options.altitudeM = altitude; })) << altitude;
  for (const double radius : {nan, 0.0, 1.5})
    EXPECT_TRUE(refusedByBoth([radius](auto& options) { options.radiusFraction = radius; })) << radius;
  for (const int samples : {0, 7, 2000000})
    EXPECT_TRUE(refusedByBoth([samples](auto& options) { options.samples = samples; })) << samples;
  for (const double extent : {nan, inf, 0.0, -5.0}) {
    EXPECT_FALSE(makeFlyoverLoop(extent, 1000, flat, {}).ok()) << extent;
    EXPECT_FALSE(makeOrbitLoop(1000, extent, flat, {}).ok()) << extent;
  }
  FlyoverOptions steep;
  steep.pitchDeg = 120.0;
  EXPECT_FALSE(makeFlyoverLoop(1000, 1000, flat, steep).ok());
  // Ground that is not finite everywhere does not poison the orbit's path with NaN: refused.
  EXPECT_FALSE(makeOrbitLoop(1000, 1000, [nan](double, double) { return nan; }, {}).ok());
}

TEST(OrbitLoop, CirclesTheCentreLookingAtIt) {
  auto ground = [](double x, double y) { return 100.0 + 0.02 * x + 0.01 * y; };
  OrbitOptions options;
  options.altitudeM = 500.0;
  const CameraPath path = makeOrbitLoop(8000.0, 6000.0, ground, options).value();
  const glm::dvec3 centre{4000.0, 3000.0, ground(4000.0, 3000.0)};
  for (double t = 0.0; t < path.durationS(); t += path.durationS() / 37.0) {
    const CameraPose pose = path.at(t);
    EXPECT_NEAR(glm::length(glm::dvec2(pose.position) - glm::dvec2(centre)), 0.35 * 6000.0, 1.0);
    Camera lens;
    lens.fovYDeg = 35.0;
    const Camera camera = pose.placed(lens);
    EXPECT_EQ(camera.position, pose.position);
    EXPECT_EQ(camera.fovYDeg, 35.0) << "the lens stays";
    EXPECT_GT(glm::dot(camera.forward(), glm::normalize(centre - pose.position)), 0.9999);
    EXPECT_GE(pose.position.z - ground(pose.position.x, pose.position.y), options.altitudeM);
  }
}

}  // namespace
}  // namespace polder
