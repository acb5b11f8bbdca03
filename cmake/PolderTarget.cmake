# polder_add_library(NAME SOURCES...): the target of component NAME (declared in
# cmake/PolderDependencies.cmake) with the project's warnings, C++20, a polder:: alias and
# the module's include/ as its public headers, installed as install component polder_NAME.
function(polder_add_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES" ${ARGN})
  if(NOT POLDER_COMPONENT_${name})
    message(FATAL_ERROR "polder_add_library(${name}): not a component to build; declare it with "
                        "polder_component() in cmake/PolderDependencies.cmake")
  endif()
  add_library(${name} ${ARG_SOURCES})
  add_library(polder::${name} ALIAS ${name})
  set_target_properties(${name} PROPERTIES OUTPUT_NAME polder_${name} EXPORT_NAME ${name}
                        POSITION_INDEPENDENT_CODE ON)
  target_compile_features(${name} PUBLIC cxx_std_20)
  target_include_directories(${name} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  polder_target_defaults(${name})
  if(EXISTS ${CMAKE_CURRENT_SOURCE_DIR}/include)
    install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
            COMPONENT polder_${name})
  endif()
endfunction()

# polder_add_interface_library(NAME): a component without sources of its own (headers and
# the components it links), installed like polder_add_library's.
function(polder_add_interface_library name)
  if(NOT POLDER_COMPONENT_${name})
    message(FATAL_ERROR "polder_add_interface_library(${name}): not a component to build")
  endif()
  add_library(${name} INTERFACE)
  add_library(polder::${name} ALIAS ${name})
  set_target_properties(${name} PROPERTIES EXPORT_NAME ${name})
  target_compile_features(${name} INTERFACE cxx_std_20)
  target_include_directories(${name} INTERFACE
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
          COMPONENT polder_${name})
endfunction()

# Warnings and sanitizers for targets the project builds (never forced on a host).
function(polder_target_defaults name)
  if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
    target_compile_options(${name} PRIVATE -Wall -Wextra -Wpedantic -Wno-missing-field-initializers)
  endif()
  if(POLDER_FUZZ)
    # Coverage for libFuzzer in every library; only the fuzz programs link its main.
    target_compile_options(${name} PRIVATE -fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer)
    target_link_options(${name} PUBLIC -fsanitize=address,undefined)
  elseif(POLDER_SANITIZE)
    target_compile_options(${name} PRIVATE -fsanitize=address,undefined -fno-omit-frame-pointer)
    target_link_options(${name} PUBLIC -fsanitize=address,undefined)
  elseif(POLDER_SANITIZE_THREAD)
    target_compile_options(${name} PRIVATE -fsanitize=thread -fno-omit-frame-pointer)
    target_link_options(${name} PUBLIC -fsanitize=thread)
  endif()
endfunction()
