# Script mode: makes the Polder install the consumer tests build against, in PREFIX.
#   SOURCE=build:   installs the build in POLDER_BUILD_DIR (every component it built).
#   SOURCE=minimal: configures SCRATCH_DIR from POLDER_SOURCE_DIR with every POLDER_WITH_*
#     OFF and no programs, builds only the targets in COMPONENTS (comma-separated) and
#     installs them with the package files. SCRATCH_DIR is kept, so later runs rebuild only
#     what changed; -O0, as the consumer tests need the package, not speed.
include(${CMAKE_CURRENT_LIST_DIR}/run_step.cmake)

file(REMOVE_RECURSE ${PREFIX})
if(SOURCE STREQUAL "build")
  run_step(${CMAKE_COMMAND} --install ${POLDER_BUILD_DIR} --prefix ${PREFIX})
  return()
endif()
string(REPLACE "," ";" _components "${COMPONENTS}")
run_step(${CMAKE_COMMAND} -S ${POLDER_SOURCE_DIR} -B ${SCRATCH_DIR} -G ${GENERATOR}
         -DCMAKE_C_COMPILER=${C_COMPILER} -DCMAKE_CXX_COMPILER=${CXX_COMPILER}
         -DCMAKE_BUILD_TYPE=Debug -DCMAKE_C_FLAGS_DEBUG=-O0 -DCMAKE_CXX_FLAGS_DEBUG=-O0
         -DPOLDER_BUILD_DEMO=OFF -DPOLDER_BUILD_TESTS=OFF -DPOLDER_BUILD_BENCHMARKS=OFF
         -DPOLDER_WITH_EMBREE=OFF -DPOLDER_WITH_ASSIMP=OFF -DPOLDER_WITH_OPENIMAGEIO=OFF -DPOLDER_WITH_GL=OFF)
run_step(${CMAKE_COMMAND} --build ${SCRATCH_DIR} --parallel 2 --target ${_components})
foreach(_component IN ITEMS config LISTS _components)
  run_step(${CMAKE_COMMAND} --install ${SCRATCH_DIR} --prefix ${PREFIX} --component polder_${_component})
endforeach()
