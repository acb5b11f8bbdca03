# FindOSMesa: Mesa's off-screen OpenGL library as the imported target OSMesa::OSMesa (found
# through pkg-config's osmesa.pc when there is one). Installed with Polder's package, for
# polder::platform_osmesa.
find_package(PkgConfig QUIET)
if(PKG_CONFIG_FOUND)
  pkg_check_modules(PC_OSMesa QUIET osmesa)
endif()
find_path(OSMesa_INCLUDE_DIR GL/osmesa.h HINTS ${PC_OSMesa_INCLUDE_DIRS})
find_library(OSMesa_LIBRARY NAMES OSMesa osmesa HINTS ${PC_OSMesa_LIBRARY_DIRS})
mark_as_advanced(OSMesa_INCLUDE_DIR OSMesa_LIBRARY)
set(OSMesa_VERSION "${PC_OSMesa_VERSION}")
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(OSMesa REQUIRED_VARS OSMesa_LIBRARY OSMesa_INCLUDE_DIR
                                  VERSION_VAR OSMesa_VERSION)
if(OSMesa_FOUND AND NOT TARGET OSMesa::OSMesa)
  add_library(OSMesa::OSMesa UNKNOWN IMPORTED)
  set_target_properties(OSMesa::OSMesa PROPERTIES IMPORTED_LOCATION "${OSMesa_LIBRARY}"
                        INTERFACE_INCLUDE_DIRECTORIES "${OSMesa_INCLUDE_DIR}")
endif()
