# Shared by the line-scanning style checks (CheckLayering.cmake, CheckNoPrinting.cmake),
# included by those cmake -P scripts: the check of ROOT, the library's source files, the
# code part of a line, and a scratch folder for each script's self-check.
include_guard(GLOBAL)

# Fails unless ROOT (set with -DROOT=...) is the repository root.
macro(librt_require_root)
  if(NOT ROOT OR NOT EXISTS "${ROOT}/librt")
    message(FATAL_ERROR "ROOT='${ROOT}' is not the repository root")
  endif()
endmacro()

# Sets out_var to the line's code: everything before "//" (comments are not checked).
function(librt_code_of_line line out_var)
  string(FIND "${line}" "//" comment)
  if(comment GREATER -1)
    string(SUBSTRING "${line}" 0 ${comment} line)
  endif()
  set(${out_var} "${line}" PARENT_SCOPE)
endfunction()

# Sets out_var to every source and header under librt/src and librt/include (paths
# relative to root, sorted) and count_var to their number; fails when fewer than ten are
# found, so a wrong root cannot pass by checking nothing.
function(librt_library_files root out_var count_var)
  file(GLOB_RECURSE files RELATIVE "${root}"
    "${root}/librt/src/*.h" "${root}/librt/src/*.hpp" "${root}/librt/src/*.cpp"
    "${root}/librt/src/*.inl" "${root}/librt/include/*.h" "${root}/librt/include/*.hpp")
  list(SORT files)
  list(LENGTH files count)
  if(count LESS 10)
    message(FATAL_ERROR "only ${count} library files found under ${root}/librt")
  endif()
  set(${out_var} "${files}" PARENT_SCOPE)
  set(${count_var} ${count} PARENT_SCOPE)
endfunction()

# Sets out_var to a new, empty scratch folder (a random name under the current binary
# folder) for a self-check; the caller removes it.
function(librt_scratch_folder name out_var)
  string(RANDOM LENGTH 12 tag)
  set(folder "${CMAKE_CURRENT_BINARY_DIR}/${name}_${tag}")
  file(MAKE_DIRECTORY "${folder}")
  set(${out_var} "${folder}" PARENT_SCOPE)
endfunction()
