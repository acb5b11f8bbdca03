# Polder's components: each is one library target polder::<name>, installed with its own
# targets file (PolderTargets-<name>.cmake) and deps file (PolderDeps-<name>.cmake), so that
# find_package(Polder CONFIG COMPONENTS ...) looks only for what the asked-for components need.
# cmake/PolderDependencies.cmake declares them; PolderInstall.cmake writes the package.
include(PolderFindPackage)

# polder_component(NAME [IF OPTION...]): declares component NAME, built when every OPTION is
# ON. Sets POLDER_COMPONENT_<NAME> (ON or OFF) for the add_subdirectory() that adds it.
function(polder_component name)
  cmake_parse_arguments(ARG "" "" "IF" ${ARGN})
  set(_off)
  foreach(_option IN LISTS ARG_IF)
    if(NOT ${_option})
      list(APPEND _off "${_option}=OFF")
    endif()
  endforeach()
  set_property(GLOBAL PROPERTY POLDER_COMPONENT_${name}_OPTIONS ${ARG_IF})
  if(_off)
    list(JOIN _off ", " _why)
    set_property(GLOBAL APPEND PROPERTY POLDER_SKIPPED_COMPONENTS ${name})
    set_property(GLOBAL PROPERTY POLDER_COMPONENT_${name}_WHY "${_why}")
    set(POLDER_COMPONENT_${name} OFF PARENT_SCOPE)
  else()
    set_property(GLOBAL APPEND PROPERTY POLDER_COMPONENTS ${name})
    set(POLDER_COMPONENT_${name} ON PARENT_SCOPE)
  endif()
endfunction()

# polder_dependency(COMPONENT PACKAGE [find_package arguments...]): a third-party package that
# COMPONENT needs (to compile, or to link, as static libraries pass their private libraries
# on). Found now when COMPONENT is built; written into PolderDeps-COMPONENT.cmake for hosts.
# A macro, so that the package's targets and variables belong to the caller's directory.
macro(polder_dependency component package)
  if(POLDER_COMPONENT_${component})
    set(_polder_args ${package} ${ARGN})
    list(JOIN _polder_args " " _polder_args)  # the arguments for find_package(), as one entry
    polder_find_package(${package} ${ARGN})
    if(NOT ${package}_FOUND)
      get_property(_polder_options GLOBAL PROPERTY POLDER_COMPONENT_${component}_OPTIONS)
      set(_polder_hint "")
      if(_polder_options)
        list(JOIN _polder_options "=OFF or -D" _polder_hint)
        set(_polder_hint ", or configure with -D${_polder_hint}=OFF to build Polder without it")
      endif()
      message(FATAL_ERROR "Polder component ${component} needs the package ${package} "
                          "(find_package(${_polder_args})), which was not found: install it${_polder_hint}.")
    endif()
    set_property(GLOBAL APPEND PROPERTY POLDER_COMPONENT_${component}_PACKAGES "${_polder_args}")
  endif()
endmacro()

# polder_missing_components(OUT NAME...): the components among NAME... that are not built,
# as text for a message ("polder::query, polder::render"); empty when all are.
function(polder_missing_components out)
  set(_missing)
  foreach(_name IN LISTS ARGN)
    if(NOT TARGET polder::${_name})
      list(APPEND _missing polder::${_name})
    endif()
  endforeach()
  list(JOIN _missing ", " _text)
  set(${out} "${_text}" PARENT_SCOPE)
endfunction()

# One line for the configure log: what is built and what is not, and why.
function(polder_report_components)
  get_property(_built GLOBAL PROPERTY POLDER_COMPONENTS)
  get_property(_skipped GLOBAL PROPERTY POLDER_SKIPPED_COMPONENTS)
  list(JOIN _built " " _text)
  message(STATUS "Polder components: ${_text}")
  foreach(_name IN LISTS _skipped)
    get_property(_why GLOBAL PROPERTY POLDER_COMPONENT_${_name}_WHY)
    message(STATUS "Polder component ${_name} not built (${_why})")
  endforeach()
endfunction()
