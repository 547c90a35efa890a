# Script (cmake -P) behind the format and format-check targets.
#   CLANG_FORMAT, SOURCE_DIR, MODE = check (dry run, fails on any change) | fix (in place)
set(globs)
foreach(dir IN ITEMS librt apps tests bench examples python)
  foreach(ext IN ITEMS h hpp cpp cc)
    list(APPEND globs "${SOURCE_DIR}/${dir}/*.${ext}")
  endforeach()
endforeach()
# Paths relative to the sources, so that the filter below sees only what is inside them (a
# checkout at e.g. /work/build3 would otherwise lose every file to it).
file(GLOB_RECURSE files RELATIVE "${SOURCE_DIR}" ${globs})
# Skip build trees that may sit inside the sources (e.g. examples/<name>/build).
list(FILTER files EXCLUDE REGEX "(^|/)build[^/]*/")
list(SORT files)
list(LENGTH files count)
if(count EQUAL 0)
  # Never a silent pass: a check that saw no file checked nothing.
  message(FATAL_ERROR "clang-format: no sources found under ${SOURCE_DIR}")
endif()

if(MODE STREQUAL "check")
  execute_process(COMMAND "${CLANG_FORMAT}" --style=file --dry-run --Werror ${files}
                  WORKING_DIRECTORY "${SOURCE_DIR}" RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "clang-format: some of the ${count} files are not formatted; "
                        "run the format target (cmake --build <build> --target format)")
  endif()
  message(STATUS "clang-format: ${count} files formatted correctly")
elseif(MODE STREQUAL "fix")
  execute_process(COMMAND "${CLANG_FORMAT}" --style=file -i ${files}
                  WORKING_DIRECTORY "${SOURCE_DIR}" RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "clang-format failed (${rc})")
  endif()
  message(STATUS "clang-format: formatted ${count} files")
else()
  message(FATAL_ERROR "MODE must be check or fix, not '${MODE}'")
endif()
