// polder — the terrain engine's command-line program.
#include <cstdio>
#include <exception>
#include <new>

#include "cli_support.hpp"
#include "commands.hpp"

int main(int argc, char** argv) {
  CLI::App app{"Polder: crack-free, view-dependent terrain from raster DEMs of any size", "polder"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "polder 0.1.0");
  int exitCode = 0;
  polder::cli::addInfoCommand(app, exitCode);
  polder::cli::addGenCommand(app, exitCode);
  polder::cli::addPrepCommand(app, exitCode);
  polder::cli::addRenderCommand(app, exitCode);
  polder::cli::addQueryCommand(app, exitCode);
  polder::cli::addFlyoverCommand(app, exitCode);
  polder::cli::addBenchCommand(app, exitCode);
  polder::cli::addSimplifyCommand(app, exitCode);
  polder::cli::addSceneCommand(app, exitCode);
  polder::cli::addMeshCommand(app, exitCode);
  const auto isCommand = [&app](const char* name) {
    for (const CLI::App* command : app.get_subcommands({}))
      if (command->get_name() == name) return true;
    return false;
  };
  if (argc > 1 && argv[1][0] != '-' && !isCommand(argv[1])) {
    std::fprintf(stderr,
                 "polder: error: unknown command '%s' (commands: info, gen, render, query, flyover, bench, simplify, "
                 "scene, mesh; see --help)\n",
                 argv[1]);
    return polder::cli::kExitUsage;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& success) {
    return app.exit(success);
  } catch (const CLI::ParseError& error) {
    if (error.get_exit_code() == 0) return app.exit(error);
    std::fprintf(stderr, "polder: error: %s (see polder --help)\n", error.what());
    return polder::cli::kExitUsage;
  } catch (const std::bad_alloc&) {
    // Allocations sized from input are checked before they are made; this is the last guard.
    std::fprintf(stderr, "polder: error: out of memory\n");
    return polder::cli::kExitData;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "polder: error: internal error: %s\n", error.what());
    return polder::cli::kExitData;
  }
  return exitCode;
}
