# Install rules: the seven libraries with their public headers, the CMake package
# (find_package(bouncecal CONFIG)), a pkg-config file and the bouncecal command. docs/install.md
# says how a project consumes them; tests/consumer/ checks that one can.
#
# The libraries are static, so their private dependencies (libsndfile, FFTW, NLopt, fmt, threads,
# libdl; FFmpeg is loaded at run time) are part of a consumer's link: bouncecalConfig.cmake finds
# them and bouncecal.pc lists them.
include(CMakePackageConfigHelpers)

set(BOUNCECAL_LIBRARIES
  bouncecal_core bouncecal_audio bouncecal_synth bouncecal_dem_model bouncecal_dem
  bouncecal_calibrate bouncecal_export)
# Exported as bouncecal::core, bouncecal::audio, ...: the names the build tree's aliases use.
foreach(library IN LISTS BOUNCECAL_LIBRARIES)
  string(REPLACE "bouncecal_" "" export_name "${library}")
  set_target_properties(${library} PROPERTIES EXPORT_NAME ${export_name})
endforeach()

set(BOUNCECAL_INSTALL_CMAKEDIR "${CMAKE_INSTALL_LIBDIR}/cmake/bouncecal"
  CACHE STRING "Where bouncecalConfig.cmake is installed, relative to the prefix")

install(TARGETS ${BOUNCECAL_LIBRARIES}
  EXPORT bouncecalTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(TARGETS bouncecal RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
# Each module's include/ holds only public headers (bouncecal/<module>/*.h); the internals stay
# in <module>/src/.
foreach(module core audio dem calibrate export)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${module}/include/
    DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
    FILES_MATCHING PATTERN "*.h")
endforeach()

install(EXPORT bouncecalTargets
  NAMESPACE bouncecal::
  DESTINATION ${BOUNCECAL_INSTALL_CMAKEDIR})
configure_package_config_file(cmake/bouncecalConfig.cmake.in
  ${PROJECT_BINARY_DIR}/bouncecalConfig.cmake
  INSTALL_DESTINATION ${BOUNCECAL_INSTALL_CMAKEDIR})
# 0.x: a minor release may change the API, so only the same 0.y satisfies a request.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/bouncecalConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES
  ${PROJECT_BINARY_DIR}/bouncecalConfig.cmake
  ${PROJECT_BINARY_DIR}/bouncecalConfigVersion.cmake
  DESTINATION ${BOUNCECAL_INSTALL_CMAKEDIR})

# pkg-config: the prefix is found from the .pc file's own location, so the file stays right when
# the tree is installed with `cmake --install --prefix` elsewhere than CMAKE_INSTALL_PREFIX, or
# moved. Requires (not Requires.private) because the libraries are static.
if(IS_ABSOLUTE "${CMAKE_INSTALL_LIBDIR}")
  message(FATAL_ERROR "CMAKE_INSTALL_LIBDIR must be relative to the prefix for bouncecal.pc, "
    "got ${CMAKE_INSTALL_LIBDIR}")
endif()
file(RELATIVE_PATH BOUNCECAL_PC_TO_PREFIX
  "/prefix/${CMAKE_INSTALL_LIBDIR}/pkgconfig" "/prefix")
string(REGEX REPLACE "/$" "" BOUNCECAL_PC_TO_PREFIX "${BOUNCECAL_PC_TO_PREFIX}")
configure_file(cmake/bouncecal.pc.in ${PROJECT_BINARY_DIR}/bouncecal.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/bouncecal.pc
  DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
