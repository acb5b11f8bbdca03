# `cmake --install` produces a package that `find_package(Polder CONFIG)` consumes.
include(CMakePackageConfigHelpers)
get_property(_polder_targets GLOBAL PROPERTY POLDER_INSTALL_TARGETS)
install(TARGETS ${_polder_targets} EXPORT PolderTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
set(_config_dir ${CMAKE_INSTALL_LIBDIR}/cmake/Polder)
install(EXPORT PolderTargets NAMESPACE polder:: DESTINATION ${_config_dir})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/PolderConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/PolderConfig.cmake INSTALL_DESTINATION ${_config_dir})
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/PolderConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/PolderConfig.cmake
              ${CMAKE_CURRENT_BINARY_DIR}/PolderConfigVersion.cmake
        DESTINATION ${_config_dir})
