# `format` rewrites, and `format-check` checks (clang-format --dry-run --Werror), every C++
# source under librt/ apps/ tests/ bench/ examples/ python/ against the root .clang-format. The
# file list is globbed when the target runs, so new files are always included. Defined
# only when clang-format is found (Debian 12: clang-format, version 14).
find_program(LIBRT_CLANG_FORMAT NAMES clang-format-14 clang-format
             DOC "clang-format used by the format and format-check targets")
if(NOT LIBRT_CLANG_FORMAT)
  message(STATUS "librt: clang-format not found, no format/format-check targets")
  return()
endif()

foreach(_mode IN ITEMS check fix)
  if(_mode STREQUAL "check")
    set(_target format-check)
  else()
    set(_target format)
  endif()
  add_custom_target(${_target}
    COMMAND "${CMAKE_COMMAND}"
      -D "CLANG_FORMAT=${LIBRT_CLANG_FORMAT}"
      -D "SOURCE_DIR=${PROJECT_SOURCE_DIR}"
      -D "MODE=${_mode}"
      -P "${PROJECT_SOURCE_DIR}/cmake/RunClangFormat.cmake"
    WORKING_DIRECTORY "${PROJECT_SOURCE_DIR}"
    VERBATIM)
endforeach()
