# ctest tests of the installed package: one fixture installs librt into a scratch prefix
# under the build directory, then each examples/<name>/ project is configured, built and
# run against that prefix alone, with the same generator, compiler, build type, compiler
# and linker flags (so sanitizer presets build the examples with sanitizers too). A
# broken install rule, export or config file fails here, not in a user's project.
#   ctest --preset release -R package
# Included from tests/CMakeLists.txt when librt is top level and LIBRT_INSTALL is on.

set(LIBRT_PACKAGE_TEST_DIR "${PROJECT_BINARY_DIR}/package-test")
set(LIBRT_PACKAGE_TEST_PREFIX "${LIBRT_PACKAGE_TEST_DIR}/prefix")
if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
  set(_librt_example_flags "-Wall -Wextra -Wpedantic -Werror")
else()
  set(_librt_example_flags "")
endif()
set(LIBRT_EXAMPLE_CXX_FLAGS "${_librt_example_flags}" CACHE STRING
    "Flags added to CMAKE_CXX_FLAGS for the examples built by the package tests")
mark_as_advanced(LIBRT_EXAMPLE_CXX_FLAGS)

set(_librt_package_script "${PROJECT_SOURCE_DIR}/cmake/RunPackageTest.cmake")

# A single-config build passes its build type's flags on (CMAKE_CXX_FLAGS_<CONFIG>), so
# the examples compile as the library did: the sanitizer presets' -g1, not Debug's -g,
# (package.example.caustics under ASan: 14.1 s with -g, 12.9 s with -g1).
set(_librt_config_flags "")
if(CMAKE_BUILD_TYPE AND NOT CMAKE_CONFIGURATION_TYPES)
  string(TOUPPER "${CMAKE_BUILD_TYPE}" _librt_config_upper)
  set(_librt_config_flags "-DCXX_FLAGS_CONFIG=${CMAKE_CXX_FLAGS_${_librt_config_upper}}")
endif()

add_test(NAME package.install
  COMMAND "${CMAKE_COMMAND}"
    -D MODE=install
    -D BUILD_DIR=${PROJECT_BINARY_DIR}
    -D PREFIX=${LIBRT_PACKAGE_TEST_PREFIX}
    -D CONFIG=$<CONFIG>
    -P "${_librt_package_script}")
set_tests_properties(package.install PROPERTIES FIXTURES_SETUP librt_package_install)

# Every examples/<name>/CMakeLists.txt is a test; its executable is called <name>.
file(GLOB _librt_example_lists CONFIGURE_DEPENDS "${PROJECT_SOURCE_DIR}/examples/*/CMakeLists.txt")
foreach(_list IN LISTS _librt_example_lists)
  get_filename_component(_dir "${_list}" DIRECTORY)
  get_filename_component(_name "${_dir}" NAME)
  # examples/mpi_* need librt::mpi, built only where MPI was found.
  if(_name MATCHES "^mpi_" AND NOT LIBRT_WITH_MPI)
    continue()
  endif()
  add_test(NAME package.example.${_name}
    COMMAND "${CMAKE_COMMAND}"
      -D MODE=example
      -D NAME=${_name}
      -D SOURCE_DIR=${_dir}
      -D BINARY_DIR=${LIBRT_PACKAGE_TEST_DIR}/${_name}
      -D PREFIX=${LIBRT_PACKAGE_TEST_PREFIX}
      -D CONFIG=$<CONFIG>
      -D GENERATOR=${CMAKE_GENERATOR}
      -D MAKE_PROGRAM=${CMAKE_MAKE_PROGRAM}
      -D CXX_COMPILER=${CMAKE_CXX_COMPILER}
      "-DCXX_FLAGS=${CMAKE_CXX_FLAGS} ${LIBRT_EXAMPLE_CXX_FLAGS}"
      "-DEXE_LINKER_FLAGS=${CMAKE_EXE_LINKER_FLAGS}"
      ${_librt_config_flags}
      -P "${_librt_package_script}")
  set_tests_properties(package.example.${_name} PROPERTIES
    FIXTURES_REQUIRED librt_package_install
    LABELS package
    TIMEOUT 900)
  if(_name MATCHES "^mpi_")  # Open MPI leaks at exit: see apps/CMakeLists.txt, mpi.*
    set_tests_properties(package.example.${_name} PROPERTIES
      ENVIRONMENT_MODIFICATION "ASAN_OPTIONS=string_append::detect_leaks=0")
  endif()
endforeach()

# The pkg-config file, used alone (no CMake), and the installed apps.
if(LIBRT_BUILD_APPS)
  set(_librt_installed_app rt_render)
else()
  set(_librt_installed_app "")
endif()
add_test(NAME package.pkgconfig
  COMMAND "${CMAKE_COMMAND}"
    -D MODE=pkgconfig
    -D PREFIX=${LIBRT_PACKAGE_TEST_PREFIX}
    -D SOURCE=${PROJECT_SOURCE_DIR}/examples/bvh_only/main.cpp
    -D BINARY_DIR=${LIBRT_PACKAGE_TEST_DIR}/pkgconfig
    -D CXX_COMPILER=${CMAKE_CXX_COMPILER}
    "-DCXX_FLAGS=${CMAKE_CXX_FLAGS} ${LIBRT_EXAMPLE_CXX_FLAGS}"
    "-DEXE_LINKER_FLAGS=${CMAKE_EXE_LINKER_FLAGS}"
    -D APP=${_librt_installed_app}
    -P "${_librt_package_script}")
set_tests_properties(package.pkgconfig PROPERTIES
  FIXTURES_REQUIRED librt_package_install LABELS package TIMEOUT 900)
set_tests_properties(package.install PROPERTIES LABELS package)
