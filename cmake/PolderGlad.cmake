# Generates the glad 2 OpenGL 3.3 core loader at configure time (offline, --reproducible).
# --mx puts the function table in a GladGLContext struct, so the renderer owns its
# entry points instead of sharing process-global ones.
find_program(POLDER_GLAD_EXECUTABLE glad REQUIRED)
set(_glad_dir ${CMAKE_CURRENT_BINARY_DIR}/glad)
if(NOT EXISTS ${_glad_dir}/src/gl.c)
  execute_process(
    COMMAND ${POLDER_GLAD_EXECUTABLE} --api gl:core=3.3 --extensions "" --out-path ${_glad_dir}
            --reproducible --quiet c --mx
    RESULT_VARIABLE _glad_result OUTPUT_QUIET ERROR_VARIABLE _glad_error)
  if(NOT _glad_result EQUAL 0)
    message(FATAL_ERROR "glad failed to generate the OpenGL loader: ${_glad_error}")
  endif()
endif()
add_library(polder_glad STATIC ${_glad_dir}/src/gl.c)
set_target_properties(polder_glad PROPERTIES POSITION_INDEPENDENT_CODE ON C_VISIBILITY_PRESET hidden)
target_include_directories(polder_glad PUBLIC $<BUILD_INTERFACE:${_glad_dir}/include>)
set_property(GLOBAL APPEND PROPERTY POLDER_INSTALL_TARGETS polder_glad)
