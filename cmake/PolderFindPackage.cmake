# polder_find_package(PACKAGE [find_package arguments...]): finds one of the third-party
# packages Polder's components use, then applies the fix-ups some of them need. Never
# REQUIRED: the caller says which component needs what is missing. Used by the build and by
# the installed PolderConfig.cmake alike. A macro, as find_package's results are the caller's.
macro(polder_find_package package)
  find_package(${package} ${ARGN})
  if("${package}" STREQUAL "OpenImageIO" AND OpenImageIO_FOUND)
    # Debian's OpenImageIO targets list /usr/include/opencv4, which exists only with
    # libopencv-dev installed; drop it so generation does not fail without OpenCV.
    foreach(_polder_oiio_target IN ITEMS OpenImageIO::OpenImageIO OpenImageIO::OpenImageIO_Util)
      if(TARGET ${_polder_oiio_target})
        get_target_property(_polder_oiio_includes ${_polder_oiio_target} INTERFACE_INCLUDE_DIRECTORIES)
        if(_polder_oiio_includes)
          list(FILTER _polder_oiio_includes EXCLUDE REGEX "opencv4")
          set_target_properties(${_polder_oiio_target} PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${_polder_oiio_includes}")
        endif()
      endif()
    endforeach()
  endif()
endmacro()
