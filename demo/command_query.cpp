// polder query DEM --at X,Y | --ray X,Y,Z,DX,DY,DZ: the full-resolution surface, by Embree.
#include <cstdio>
#include <memory>

#include <polder/query/query_scene.hpp>

#include "cli_support.hpp"
#include "commands.hpp"

namespace polder::cli {
namespace {

struct QueryArguments {
  DemArguments dem;
  std::string at;
  std::string ray;
};

int runQuery(const QueryArguments& arguments) {
  if (arguments.at.empty() == arguments.ray.empty())
    return reportError(makeError(ErrorKind::InvalidArgument, "give exactly one of --at X,Y and --ray X,Y,Z,DX,DY,DZ"));
  std::vector<double> numbers;
  if (!arguments.at.empty()) {
    auto parsed = parseNumbers(arguments.at, 2, "--at X,Y");
    if (!parsed) return reportError(parsed.error());
    numbers = std::move(*parsed);
  } else {
    auto parsed = parseNumbers(arguments.ray, 6, "--ray X,Y,Z,DX,DY,DZ");
    if (!parsed) return reportError(parsed.error());
    numbers = std::move(*parsed);
    if (numbers[3] == 0.0 && numbers[4] == 0.0 && numbers[5] == 0.0)
      return reportError(makeError(ErrorKind::InvalidArgument, "--ray direction must not be zero"));
  }
  auto dem = loadDem(arguments.dem);
  if (!dem) return reportError(dem.error());
  auto scene = query::QueryScene::create(dem->field);
  if (!scene) return reportError(scene.error());

  if (!arguments.at.empty()) {
    const auto height = (*scene)->height(numbers[0], numbers[1]);
    if (!height)
      return reportError(makeError(ErrorKind::InvalidArgument, "--at " + arguments.at + " lies outside the DEM (0..." +
                                                                   std::to_string(dem->field.extentX()) + ", 0..." +
                                                                   std::to_string(dem->field.extentY()) + " m)"));
    std::printf("%.3f\n", *height);
    return 0;
  }
  const glm::dvec3 origin{numbers[0], numbers[1], numbers[2]};
  const glm::dvec3 direction = glm::normalize(glm::dvec3{numbers[3], numbers[4], numbers[5]});
  const auto hit = (*scene)->raycast(origin, direction);
  if (!hit) {
    std::printf("miss\n");
    return 0;
  }
  std::printf("%.3f %.3f %.3f %.3f\n", hit->point.x, hit->point.y, hit->point.z, hit->distance);
  return 0;
}

}  // namespace

void addQueryCommand(CLI::App& app, int& exitCode) {
  auto arguments = std::make_shared<QueryArguments>();
  CLI::App* command =
      app.add_subcommand("query", "Height under a point, or where a ray hits the terrain (metres, world frame)");
  addDemArguments(*command, arguments->dem);
  command->add_option("--at", arguments->at, "X,Y: print the surface height there");
  command->add_option("--ray", arguments->ray, "X,Y,Z,DX,DY,DZ: print 'X Y Z DISTANCE' of the hit, or 'miss'");
  command->callback([arguments, &exitCode] { exitCode = runQuery(*arguments); });
}

}  // namespace polder::cli
