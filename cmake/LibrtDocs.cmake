# The `docs` target: Doxygen HTML of the public headers' `///` comments, written to
# <build>/docs/html, with the warnings (undocumented public members first of all) in
# <build>/docs/doxygen-warnings.log and counted on the console. Defined only when
# Doxygen is found (Debian: doxygen). LIBRT_DOCS_STRICT=ON makes any warning an error.
# With the test suite on, the ctest docs.no_undocumented_api runs the same Doxygen step in
# strict mode, so an undocumented public member fails `ctest`.
find_package(Doxygen QUIET)
if(NOT DOXYGEN_FOUND)
  message(STATUS "librt: doxygen not found, no docs target")
  return()
endif()

option(LIBRT_DOCS_STRICT "Make the docs target fail on any Doxygen warning" OFF)
set(LIBRT_DOCS_OUTPUT_DIR "${PROJECT_BINARY_DIR}/docs")
set(LIBRT_DOCS_WARNINGS_LOG "${LIBRT_DOCS_OUTPUT_DIR}/doxygen-warnings.log")
configure_file("${PROJECT_SOURCE_DIR}/docs/Doxyfile.in" "${LIBRT_DOCS_OUTPUT_DIR}/Doxyfile" @ONLY)

add_custom_target(docs
  COMMAND "${CMAKE_COMMAND}"
    -D "DOXYGEN=$<TARGET_FILE:Doxygen::doxygen>"
    -D "DOXYFILE=${LIBRT_DOCS_OUTPUT_DIR}/Doxyfile"
    -D "LOG=${LIBRT_DOCS_WARNINGS_LOG}"
    -D "STRICT=${LIBRT_DOCS_STRICT}"
    -P "${PROJECT_SOURCE_DIR}/cmake/RunDoxygen.cmake"
  WORKING_DIRECTORY "${PROJECT_SOURCE_DIR}"
  COMMENT "Doxygen: API reference in ${LIBRT_DOCS_OUTPUT_DIR}/html"
  VERBATIM)

# docs.no_undocumented_api: Doxygen in strict mode over the same inputs, failing on any
# warning and printing the offenders. It has its own Doxyfile, output and log under
# <build>/docs-test, so it never races a `docs` build.
#   ctest --preset release -R docs
if(LIBRT_BUILD_TESTS)
  set(_librt_docs_dir "${LIBRT_DOCS_OUTPUT_DIR}")
  set(LIBRT_DOCS_OUTPUT_DIR "${PROJECT_BINARY_DIR}/docs-test")
  set(LIBRT_DOCS_WARNINGS_LOG "${LIBRT_DOCS_OUTPUT_DIR}/doxygen-warnings.log")
  configure_file("${PROJECT_SOURCE_DIR}/docs/Doxyfile.in" "${LIBRT_DOCS_OUTPUT_DIR}/Doxyfile"
                 @ONLY)
  add_test(NAME docs.no_undocumented_api
    COMMAND "${CMAKE_COMMAND}"
      -D "DOXYGEN=$<TARGET_FILE:Doxygen::doxygen>"
      -D "DOXYFILE=${LIBRT_DOCS_OUTPUT_DIR}/Doxyfile"
      -D "LOG=${LIBRT_DOCS_WARNINGS_LOG}"
      -D STRICT=ON
      -P "${PROJECT_SOURCE_DIR}/cmake/RunDoxygen.cmake"
    WORKING_DIRECTORY "${PROJECT_SOURCE_DIR}")
  set_tests_properties(docs.no_undocumented_api PROPERTIES LABELS docs TIMEOUT 60)
  set(LIBRT_DOCS_OUTPUT_DIR "${_librt_docs_dir}")
  set(LIBRT_DOCS_WARNINGS_LOG "${LIBRT_DOCS_OUTPUT_DIR}/doxygen-warnings.log")
endif()
