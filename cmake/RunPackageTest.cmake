# Script (cmake -P) behind the package tests of cmake/LibrtPackageTests.cmake.
#   MODE=install: BUILD_DIR, PREFIX, CONFIG. Installs the build into an emptied PREFIX.
#   MODE=pkgconfig: PREFIX, SOURCE (a .cpp), BINARY_DIR, CXX_COMPILER, CXX_FLAGS and
#                 EXE_LINKER_FLAGS (the build's, e.g. the sanitizers), APP (an installed
#                 app name, or empty). Compiles SOURCE with the flags
#                 `pkg-config --cflags --libs librt` gives from PREFIX's librt.pc alone, runs
#                 it, and runs PREFIX/bin/APP --version.
#   MODE=example: NAME, SOURCE_DIR, BINARY_DIR, PREFIX, CONFIG, GENERATOR, MAKE_PROGRAM,
#                 CXX_COMPILER, CXX_FLAGS, EXE_LINKER_FLAGS (CXX_FLAGS_CONFIG: the
#                 CONFIG build type's flags, when known). Configures SOURCE_DIR afresh
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

elseif(MODE STREQUAL "pkgconfig")
  file(GLOB_RECURSE pc_files "${PREFIX}/*/pkgconfig/librt.pc")
  if(NOT pc_files)
    message(FATAL_ERROR "no librt.pc under ${PREFIX}")
  endif()
  list(GET pc_files 0 pc_file)
  get_filename_component(pc_dir "${pc_file}" DIRECTORY)
  find_program(PKG_CONFIG pkg-config REQUIRED)
  set(ENV{PKG_CONFIG_PATH} "${pc_dir}")
  execute_process(COMMAND "${PKG_CONFIG}" --cflags --libs librt RESULT_VARIABLE rc
                  OUTPUT_VARIABLE flags OUTPUT_STRIP_TRAILING_WHITESPACE)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "pkg-config --cflags --libs librt failed (${rc})")
  endif()
  separate_arguments(flags UNIX_COMMAND "${flags}")
  # A shared librt in a prefix the loader does not search: run as a user of such a prefix
  # would, with the .pc file's libdir on LD_LIBRARY_PATH (a static librt ignores it).
  execute_process(COMMAND "${PKG_CONFIG}" --variable=libdir librt RESULT_VARIABLE rc
                  OUTPUT_VARIABLE pc_libdir OUTPUT_STRIP_TRAILING_WHITESPACE)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "pkg-config --variable=libdir librt failed (${rc})")
  endif()
  set(ENV{LD_LIBRARY_PATH} "${pc_libdir}")
  file(REMOVE_RECURSE "${BINARY_DIR}")
  file(MAKE_DIRECTORY "${BINARY_DIR}")
  # The build's own compile and link flags too: an instrumented (sanitizer) librt needs
  # its runtime in the program that links it.
  separate_arguments(build_flags UNIX_COMMAND "${CXX_FLAGS} ${EXE_LINKER_FLAGS}")
  run_step("compiling with pkg-config's flags" "${CXX_COMPILER}" ${build_flags} "${SOURCE}" -o
           "${BINARY_DIR}/pc_example" ${flags})
  set(_librt_step_options WORKING_DIRECTORY "${BINARY_DIR}")
  run_step("running the pkg-config example" "${BINARY_DIR}/pc_example")
  if(APP)
    run_step("running the installed ${APP}" "${PREFIX}/bin/${APP}" --version)
  endif()

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
    # The build type's own flags too (the sanitizer presets' -g1 instead of Debug's -g).
    if(DEFINED CXX_FLAGS_CONFIG)
      string(TOUPPER "${CONFIG}" config_upper)
      list(APPEND configure_args "-DCMAKE_CXX_FLAGS_${config_upper}=${CXX_FLAGS_CONFIG}")
    endif()
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
