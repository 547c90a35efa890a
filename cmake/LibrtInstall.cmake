# Install rules and the CMake package: after
#   cmake --install <build> --prefix <prefix>
# a consumer needs only
#   find_package(librt 0.1 CONFIG REQUIRED)
#   target_link_libraries(app PRIVATE librt::librt)
# Included by the root CMakeLists.txt when LIBRT_INSTALL is on.
include(CMakePackageConfigHelpers)

set(LIBRT_INSTALL_CMAKEDIR "${CMAKE_INSTALL_LIBDIR}/cmake/librt" CACHE STRING
    "Where librtConfig.cmake is installed, relative to the prefix")
mark_as_advanced(LIBRT_INSTALL_CMAKEDIR)

install(TARGETS librt EXPORT librtTargets
  RUNTIME DESTINATION "${CMAKE_INSTALL_BINDIR}" COMPONENT librt_Runtime
  LIBRARY DESTINATION "${CMAKE_INSTALL_LIBDIR}" COMPONENT librt_Runtime
          NAMELINK_COMPONENT librt_Development
  ARCHIVE DESTINATION "${CMAKE_INSTALL_LIBDIR}" COMPONENT librt_Development)

# librt::mpi, when MPI was found (librt/CMakeLists.txt).
if(LIBRT_WITH_MPI)
  install(TARGETS librt_mpi EXPORT librtTargets
    RUNTIME DESTINATION "${CMAKE_INSTALL_BINDIR}" COMPONENT librt_Runtime
    LIBRARY DESTINATION "${CMAKE_INSTALL_LIBDIR}" COMPONENT librt_Runtime
            NAMELINK_COMPONENT librt_Development
    ARCHIVE DESTINATION "${CMAKE_INSTALL_LIBDIR}" COMPONENT librt_Development)
  set(_librt_mpi_headers "")
else()
  set(_librt_mpi_headers PATTERN "mpi" EXCLUDE)  # no header without its library
endif()

# Public headers only: librt/src is private and never installed.
install(DIRECTORY "${PROJECT_SOURCE_DIR}/librt/include/librt"
  DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}" COMPONENT librt_Development
  FILES_MATCHING PATTERN "*.h" ${_librt_mpi_headers})
install(FILES ${LIBRT_GENERATED_HEADERS}
  DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}/librt" COMPONENT librt_Development)

install(EXPORT librtTargets
  NAMESPACE librt::
  FILE librtTargets.cmake
  DESTINATION "${LIBRT_INSTALL_CMAKEDIR}" COMPONENT librt_Development)

# A static librt names its PRIVATE dependencies in its link interface, so its config file
# must find them too; a shared one hides them (they are linked into librt.so).
if(LIBRT_TARGET_TYPE STREQUAL "STATIC_LIBRARY")
  set(LIBRT_CONFIG_STATIC ON)
else()
  set(LIBRT_CONFIG_STATIC OFF)
endif()
configure_package_config_file(
  "${PROJECT_SOURCE_DIR}/cmake/librtConfig.cmake.in"
  "${PROJECT_BINARY_DIR}/librtConfig.cmake"
  INSTALL_DESTINATION "${LIBRT_INSTALL_CMAKEDIR}"
  NO_SET_AND_CHECK_MACRO)

# While librt is 0.x, a minor release may break the API, so find_package(librt 0.1)
# accepts 0.1.0, 0.1.1, ... but neither 0.2 nor 1.0. SameMinorVersion says exactly that;
# switch to SameMajorVersion at 1.0.
write_basic_package_version_file(
  "${PROJECT_BINARY_DIR}/librtConfigVersion.cmake"
  VERSION ${librt_VERSION}
  COMPATIBILITY SameMinorVersion)

install(FILES
  "${PROJECT_BINARY_DIR}/librtConfig.cmake"
  "${PROJECT_BINARY_DIR}/librtConfigVersion.cmake"
  DESTINATION "${LIBRT_INSTALL_CMAKEDIR}" COMPONENT librt_Development)
