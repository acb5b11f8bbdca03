#include <polder/camera.hpp>
#include <polder/camera_path.hpp>

#include <cmath>

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
  const CameraPath path = makeFlyoverLoop(10000.0, 10000.0, ground, options);
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

}  // namespace
}  // namespace polder

namespace polder {
namespace {

TEST(OrbitLoop, CirclesTheCentreLookingAtIt) {
  auto ground = [](double x, double y) { return 100.0 + 0.02 * x + 0.01 * y; };
  OrbitOptions options;
  options.altitudeM = 500.0;
  const CameraPath path = makeOrbitLoop(8000.0, 6000.0, ground, options);
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
