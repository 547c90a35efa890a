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

# pkg-config: librt.pc beside the CMake package, in <libdir>/pkgconfig, for projects that do
# not use CMake:  g++ -o app app.cpp $(pkg-config --cflags --libs librt)
file(RELATIVE_PATH LIBRT_PC_PREFIX_FROM_PCDIR "/prefix/${CMAKE_INSTALL_LIBDIR}/pkgconfig" "/prefix")
string(REGEX REPLACE "/$" "" LIBRT_PC_PREFIX_FROM_PCDIR "${LIBRT_PC_PREFIX_FROM_PCDIR}")
# A static librt needs its private dependencies on the link line; a shared one hides them.
set(_librt_pc_deps "-ltinyobjloader -lstb -ltinygltf -ltinyexr -lz -lpng16 -ldraco -lmeshoptimizer -lwebp")
if(LIBRT_CONFIG_STATIC)
  set(LIBRT_PC_CFLAGS " -DLIBRT_STATIC_DEFINE")
  set(LIBRT_PC_LIBS " ${_librt_pc_deps}")
  set(LIBRT_PC_LIBS_PRIVATE "")
else()
  set(LIBRT_PC_CFLAGS "")
  set(LIBRT_PC_LIBS "")
  set(LIBRT_PC_LIBS_PRIVATE "${_librt_pc_deps}")
endif()
configure_file("${PROJECT_SOURCE_DIR}/cmake/librt.pc.in" "${PROJECT_BINARY_DIR}/librt.pc" @ONLY)
install(FILES "${PROJECT_BINARY_DIR}/librt.pc"
  DESTINATION "${CMAKE_INSTALL_LIBDIR}/pkgconfig" COMPONENT librt_Development)
