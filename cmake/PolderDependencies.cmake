# Polder's components, bottom-up (docs/design.md "Layers"), the options that build them and
# every third-party package each needs, found once here for the components that are built.
# All come from Debian 12's packages. Adding a package to a component is one
# polder_dependency() line here (and its target_link_libraries() in the module).
include(PolderComponents)

polder_component(core)
polder_dependency(core glm CONFIG)
polder_dependency(core TBB CONFIG)

# PNG image data is inflated once before libpng sees it, so that corrupt data is reported
# without libpng printing to stderr; used by every reader of images.
polder_component(image_check IF POLDER_WITH_OPENIMAGEIO)
polder_dependency(image_check ZLIB)

polder_component(terrain)

polder_component(terrain_io IF POLDER_WITH_OPENIMAGEIO)
polder_dependency(terrain_io OpenImageIO 2.4 CONFIG)
polder_dependency(terrain_io TIFF)

polder_component(cache)

polder_component(mesh)

# Mesh import and export (OBJ, PLY ascii/binary; glTF skins and MD2 animation later).
polder_component(mesh_io IF POLDER_WITH_ASSIMP POLDER_WITH_OPENIMAGEIO)
polder_dependency(mesh_io assimp 5 CONFIG)
polder_dependency(mesh_io OpenImageIO 2.4 CONFIG)

# glad, the GL loader, is generated into the renderer (cmake/PolderGlad.cmake): no package.
polder_component(render IF POLDER_WITH_GL)

polder_component(query IF POLDER_WITH_EMBREE)
polder_dependency(query embree 3 CONFIG)

polder_component(platform_osmesa IF POLDER_WITH_GL)
polder_dependency(platform_osmesa OSMesa)

polder_component(platform_glfw IF POLDER_WITH_GL POLDER_BUILD_GLFW)
polder_dependency(platform_glfw glfw3 3.3 CONFIG)

polder_component(terrain_engine)

polder_component(scene)

# A scene from its description: reads DEMs (OpenImageIO) and mesh files (Assimp).
polder_component(scene_build IF POLDER_WITH_OPENIMAGEIO POLDER_WITH_ASSIMP)

# Recorded flights over the frame pipeline, and their statistics.
polder_component(flight)

# The terrain frame on the GL renderer.
polder_component(terrain_draw IF POLDER_WITH_GL)

# The façade: <polder/polder.hpp> and every component this build has.
polder_component(engine)

# The programs: the demo, the tests and the benchmarks.
# The scene file's fuzz target compiles the program's reader, so fuzzing needs CLI11 too.
if(POLDER_BUILD_DEMO OR POLDER_FUZZ)
  find_package(CLI11 CONFIG REQUIRED)
  find_package(nlohmann_json 3 CONFIG REQUIRED)
endif()
if(POLDER_BUILD_TESTS)
  find_package(GTest CONFIG REQUIRED)
  find_package(nlohmann_json 3 CONFIG REQUIRED)
  # For the scene file's replay test without the program (the sanitized build); optional.
  find_package(CLI11 CONFIG QUIET)
endif()
if(POLDER_BUILD_BENCHMARKS)
  find_package(benchmark CONFIG REQUIRED)
  # The reference simplifier the quality benchmark compares against; nothing else uses it.
  find_package(meshoptimizer CONFIG REQUIRED)
endif()
