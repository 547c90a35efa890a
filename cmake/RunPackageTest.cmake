# Script (cmake -P) behind the package tests of cmake/LibrtPackageTests.cmake.
#   MODE=install: BUILD_DIR, PREFIX, CONFIG. Installs the build into an emptied PREFIX.
#   MODE=example: NAME, SOURCE_DIR, BINARY_DIR, PREFIX, CONFIG, GENERATOR, MAKE_PROGRAM,
#                 CXX_COMPILER, CXX_FLAGS, EXE_LINKER_FLAGS. Configures SOURCE_DIR afresh
#                 against PREFIX only, builds it, checks that librt came from PREFIX, runs
#                 NAME.
cmake_minimum_required(VERSION 3.22)

function(run_step what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc ${_librt_step_options})
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what} failed (${rc}): ${ARGN}")
  endif()
endfunction()

if(MODE STREQUAL "install")
  file(REMOVE_RECURSE "${PREFIX}")
  set(config_args)
  if(CONFIG)
    set(config_args --config "${CONFIG}")
  endif()
  run_step("cmake --install" "${CMAKE_COMMAND}" --install "${BUILD_DIR}" --prefix "${PREFIX}"
           ${config_args})
  file(GLOB_RECURSE config_files "${PREFIX}/*/librtConfig.cmake")
  if(NOT config_files)
    message(FATAL_ERROR "no librtConfig.cmake under ${PREFIX}")
  endif()
  message(STATUS "installed librt into ${PREFIX}: ${config_files}")

elseif(MODE STREQUAL "example")
  if(NOT EXISTS "${PREFIX}")
    message(FATAL_ERROR "${PREFIX} does not exist: run the package.install test first")
  endif()
  file(REMOVE_RECURSE "${BINARY_DIR}")
  set(configure_args -S "${SOURCE_DIR}" -B "${BINARY_DIR}" -G "${GENERATOR}"
      "-DCMAKE_PREFIX_PATH=${PREFIX}"
      "-DCMAKE_CXX_COMPILER=${CXX_COMPILER}"
      "-DCMAKE_CXX_FLAGS=${CXX_FLAGS}"
      "-DCMAKE_EXE_LINKER_FLAGS=${EXE_LINKER_FLAGS}"
      # Only the scratch prefix: never a librt found through the package registries.
      -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF
      -DCMAKE_FIND_USE_SYSTEM_PACKAGE_REGISTRY=OFF)
  if(MAKE_PROGRAM)
    list(APPEND configure_args "-DCMAKE_MAKE_PROGRAM=${MAKE_PROGRAM}")
  endif()
  if(CONFIG)
    list(APPEND configure_args "-DCMAKE_BUILD_TYPE=${CONFIG}")
  endif()
  run_step("configuring ${NAME}" "${CMAKE_COMMAND}" ${configure_args})

  # The example must have found the librt just installed, not another one.
  file(STRINGS "${BINARY_DIR}/CMakeCache.txt" librt_dir_line REGEX "^librt_DIR:")
  string(REGEX REPLACE "^librt_DIR:[A-Z]+=" "" librt_dir "${librt_dir_line}")
  file(REAL_PATH "${PREFIX}" real_prefix)
  file(REAL_PATH "${librt_dir}" real_librt_dir)
  string(FIND "${real_librt_dir}/" "${real_prefix}/" at)
  if(NOT at EQUAL 0)
    message(FATAL_ERROR "${NAME} found librt in '${librt_dir}', not under ${PREFIX}")
  endif()

  set(build_args --build "${BINARY_DIR}")
  if(CONFIG)
    list(APPEND build_args --config "${CONFIG}")
  endif()
  run_step("building ${NAME}" "${CMAKE_COMMAND}" ${build_args})

  # Single-config generators put the program in BINARY_DIR, multi-config ones below it.
  set(program "")
  foreach(candidate "${BINARY_DIR}/${NAME}" "${BINARY_DIR}/${CONFIG}/${NAME}"
                    "${BINARY_DIR}/${NAME}.exe" "${BINARY_DIR}/${CONFIG}/${NAME}.exe")
    if(EXISTS "${candidate}" AND NOT IS_DIRECTORY "${candidate}")
      set(program "${candidate}")
      break()
    endif()
  endforeach()
  if(NOT program)
    message(FATAL_ERROR "${NAME} built no program called ${NAME} in ${BINARY_DIR}")
  endif()
  # Examples run without arguments and write any output into their working directory.
  set(_librt_step_options WORKING_DIRECTORY "${BINARY_DIR}")
  run_step("running ${NAME}" "${program}")

else()
  message(FATAL_ERROR "MODE must be install or example, not '${MODE}'")
endif()
