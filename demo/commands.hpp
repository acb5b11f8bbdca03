// The `polder` subcommands. Each add*Command registers its options on the app and, when
// chosen, stores its exit code in `exitCode`.
#pragma once

#include <optional>
#include <string>

#include <CLI/CLI.hpp>

namespace polder::cli {

void addInfoCommand(CLI::App& app, int& exitCode);
void addGenCommand(CLI::App& app, int& exitCode);
void addRenderCommand(CLI::App& app, int& exitCode);
void addQueryCommand(CLI::App& app, int& exitCode);
void addFlyoverCommand(CLI::App& app, int& exitCode);
void addBenchCommand(CLI::App& app, int& exitCode);
void addSimplifyCommand(CLI::App& app, int& exitCode);
void addSceneCommand(CLI::App& app, int& exitCode);
void addMeshCommand(CLI::App& app, int& exitCode);
void addPrepCommand(CLI::App& app, int& exitCode);

// `polder bench --scene SCENE.json`: runs the scene's frames and reports them.
int benchScene(const std::string& sceneFile, std::optional<int> frames, const std::string& jsonPath);

}  // namespace polder::cli
