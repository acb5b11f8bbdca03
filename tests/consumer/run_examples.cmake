# Script mode: build examples/ against the Polder installed in PREFIX and run both host
# programs over the bundled sample for a few frames (ctest runs under a virtual display).
include(${CMAKE_CURRENT_LIST_DIR}/run_step.cmake)

file(REMOVE_RECURSE ${WORK_DIR})
run_step(${CMAKE_COMMAND} -S ${EXAMPLES_DIR} -B ${WORK_DIR}/build -G ${GENERATOR}
         -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${PREFIX})
run_step(${CMAKE_COMMAND} --build ${WORK_DIR}/build)

run_step(${WORK_DIR}/build/embed_window ${DEM} 20)
if(NOT STEP_OUTPUT MATCHES "drew 20 frames, [1-9][0-9]* pieces resident")
  message(FATAL_ERROR "unexpected embed_window output: ${STEP_OUTPUT}")
endif()
message(STATUS "embed_window: ${STEP_OUTPUT}")

# The host renderer holds still once the loaders are done: it must upload nothing in those
# 12 frames, and its own drawing of the pieces must show terrain.
run_step(${WORK_DIR}/build/host_renderer ${DEM} 24)
if(NOT STEP_OUTPUT MATCHES "uploaded [1-9][0-9]* pieces, 0 in 12 settled still frames; [1-9][0-9]* pieces held; terrain ([0-9]+)% of the last frame")
  message(FATAL_ERROR "unexpected host_renderer output: ${STEP_OUTPUT}")
endif()
if(CMAKE_MATCH_1 LESS 30)
  message(FATAL_ERROR "the host renderer drew too little terrain: ${STEP_OUTPUT}")
endif()
message(STATUS "host_renderer: ${STEP_OUTPUT}")
