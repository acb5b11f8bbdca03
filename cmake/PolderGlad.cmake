# Generates the glad 2 OpenGL 3.3 core loader at configure time (offline, --reproducible).
# --mx puts the function table in a GladGLContext struct, so the renderer owns its
# entry points instead of sharing process-global ones.
#
# glad's names are private to Polder: the generated gl.h starts by renaming every name with
# linkage (gladLoadGLContext, gladLoadGLContextUserPtr, the GladGLContext struct) to
# polder_<name>, so the loader compiled into polder::render defines only polder_glad* symbols
# and a host with its own glad, static or not, neither replaces ours nor clashes with them.
# (glad 2 has no option for a prefix; renaming is what works for a static library.)
#
# Defines polder_glad, the headers only (build tree), for polder::render and its tests, and
# POLDER_GLAD_SOURCE, the loader to compile into the renderer.
find_program(POLDER_GLAD_EXECUTABLE glad REQUIRED)
set(_glad_dir ${CMAKE_CURRENT_BINARY_DIR}/glad-private)
if(NOT EXISTS ${_glad_dir}/src/gl.c)
  file(REMOVE_RECURSE ${_glad_dir}.tmp)
  execute_process(
    COMMAND ${POLDER_GLAD_EXECUTABLE} --api gl:core=3.3 --extensions "" --out-path ${_glad_dir}.tmp
            --reproducible --quiet c --mx
    RESULT_VARIABLE _glad_result OUTPUT_QUIET ERROR_VARIABLE _glad_error)
  if(NOT _glad_result EQUAL 0)
    message(FATAL_ERROR "glad failed to generate the OpenGL loader: ${_glad_error}")
  endif()
  set(_glad_header ${_glad_dir}.tmp/include/glad/gl.h)
  file(READ ${_glad_header} _glad_text)
  string(REGEX MATCHALL "GLAD_API_CALL [^;(]*[ *]glad[A-Za-z0-9_]*\\(" _glad_functions "${_glad_text}")
  string(REGEX MATCHALL "typedef struct Glad[A-Za-z0-9_]*" _glad_structs "${_glad_text}")
  set(_glad_renames "/* Polder: glad's names with linkage are private to polder::render. */\n")
  foreach(_glad_declaration IN LISTS _glad_functions _glad_structs)
    string(REGEX MATCH "[Gg]lad[A-Za-z0-9_]*" _glad_name "${_glad_declaration}")
    string(APPEND _glad_renames "#define ${_glad_name} polder_${_glad_name}\n")
  endforeach()
  if(NOT _glad_functions OR NOT _glad_text MATCHES "\n#define GLAD_GL_H_\n")
    message(FATAL_ERROR "glad's gl.h (${_glad_header}) is not laid out as expected: cannot make its names private")
  endif()
  string(REPLACE "\n#define GLAD_GL_H_\n" "\n#define GLAD_GL_H_\n${_glad_renames}" _glad_text "${_glad_text}")
  file(WRITE ${_glad_header} "${_glad_text}")
  file(RENAME ${_glad_dir}.tmp ${_glad_dir})
endif()
set(POLDER_GLAD_SOURCE ${_glad_dir}/src/gl.c)
add_library(polder_glad INTERFACE)
target_include_directories(polder_glad INTERFACE ${_glad_dir}/include)
