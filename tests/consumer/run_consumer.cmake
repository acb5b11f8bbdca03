# Script mode: configures the consumer project CONSUMER_SOURCE_DIR against the Polder in
# PREFIX (with the extra -D arguments in CONSUMER_ARGS, separated by '|'), builds it and runs
# it; its output must match EXPECT. With EXPECT_CONFIGURE_ERROR, the configure must fail
# instead, with a message matching it. Fails on any other outcome.
include(${CMAKE_CURRENT_LIST_DIR}/run_step.cmake)

file(REMOVE_RECURSE ${WORK_DIR})
string(REPLACE "|" ";" _args "${CONSUMER_ARGS}")
set(_configure ${CMAKE_COMMAND} -S ${CONSUMER_SOURCE_DIR} -B ${WORK_DIR} -G ${GENERATOR}
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${PREFIX} ${_args})
if(DEFINED EXPECT_CONFIGURE_ERROR)
  execute_process(COMMAND ${_configure} RESULT_VARIABLE result OUTPUT_VARIABLE output ERROR_VARIABLE output)
  # CMake wraps long messages: compare with the line breaks and indents taken out.
  string(REGEX REPLACE "[ \t\r\n]+" " " _flat "${output}")
  if(result EQUAL 0 OR NOT _flat MATCHES "${EXPECT_CONFIGURE_ERROR}")
    message(FATAL_ERROR "configure should have failed with \"${EXPECT_CONFIGURE_ERROR}\" (${result}):\n${output}")
  endif()
  string(REGEX MATCH "${EXPECT_CONFIGURE_ERROR}" _message "${_flat}")
  message(STATUS "configure failed as expected: ${_message}")
  return()
endif()
run_step(${_configure})
if(NOT DEFINED EXPECT)
  message(STATUS "configured")
  return()
endif()
run_step(${CMAKE_COMMAND} --build ${WORK_DIR})
run_step(${WORK_DIR}/polder_consumer)
if(NOT STEP_OUTPUT MATCHES "${EXPECT}")
  message(FATAL_ERROR "unexpected consumer output: ${STEP_OUTPUT}")
endif()
message(STATUS "${STEP_OUTPUT}")
