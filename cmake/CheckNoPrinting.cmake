# Script (cmake -P) behind the ctest style.library_prints_nothing: the library reports
# warnings through returned lists or callbacks and never writes to the console itself (the
# apps print). Fails, naming file:line, when a source or header under librt/src or
# librt/include writes to stdout or stderr: std::cout / cerr / clog, std::print, the C
# calls that print to a console implicitly (printf, vprintf, puts, putchar, perror), any
# mention of stderr / stdout / STDERR_FILENO / STDOUT_FILENO (fprintf, fputs, fwrite...
# to a FILE* the library opened are fine, as is snprintf into a buffer), or
# #include <iostream>.
# Comments (from // to the end of the line) are ignored.
#   ROOT: the repository root
# Before scanning the library it checks itself on a scratch file (one violation of each
# kind must be found, the harmless look-alikes must not), so a broken pattern cannot pass.
cmake_minimum_required(VERSION 3.22)
include("${CMAKE_CURRENT_LIST_DIR}/LibrtSourceScan.cmake")
librt_require_root()

# One printing construct at a word start (no identifier character before it, so snprintf,
# my_puts or fprintf_like are not matched). CMake regexes have no \b.
set(_word_start "(^|[^A-Za-z0-9_])")
set(_printing
  "${_word_start}std::(w?cout|w?cerr|w?clog|print|println)[^A-Za-z0-9_]"
  "${_word_start}(v?printf|puts|putchar|perror)[ \t]*\\("
  "${_word_start}(stdout|stderr|STDOUT_FILENO|STDERR_FILENO)([^A-Za-z0-9_]|$)"
  "#[ \t]*include[ \t]*<iostream>")

# Lines allowed to print, as "path relative to ROOT|substring of the line|why". Keep this
# list empty: an entry is a place where the library talks to the console (none today).
set(_exemptions)

# Sets out_var to one "\n  file:line: text" per printing line of `files` (paths relative
# to `root`) that no exemption covers (a string, not a list: code holds semicolons), and
# _used_<index> for each exemption that covered a line.
function(librt_find_printing root files out_var)
  set(found "")
  foreach(rel IN LISTS files)
    file(STRINGS "${root}/${rel}" lines)
    set(number 0)
    foreach(line IN LISTS lines)
      math(EXPR number "${number} + 1")
      librt_code_of_line("${line}" code)
      set(prints FALSE)
      foreach(pattern IN LISTS _printing)
        if(code MATCHES "${pattern}")
          set(prints TRUE)
        endif()
      endforeach()
      if(NOT prints)
        continue()
      endif()
      set(exempt FALSE)
      set(index 0)
      foreach(entry IN LISTS _exemptions)
        string(REPLACE "|" ";" parts "${entry}")
        list(GET parts 0 exempt_file)
        list(GET parts 1 exempt_text)
        string(FIND "${code}" "${exempt_text}" at)
        if(rel STREQUAL exempt_file AND at GREATER -1)
          set(exempt TRUE)
          set(_used_${index} TRUE PARENT_SCOPE)
        endif()
        math(EXPR index "${index} + 1")
      endforeach()
      if(NOT exempt)
        string(STRIP "${line}" shown)
        string(APPEND found "\n  ${rel}:${number}: ${shown}")
      endif()
    endforeach()
  endforeach()
  set(${out_var} "${found}" PARENT_SCOPE)
endfunction()

# Self-check: every construct above must be caught, and look-alikes must not be.
librt_scratch_folder(librt_no_printing_selftest _scratch)
# (No semicolons in these lines: they would split the CMake list.)
set(_bad
  "std::cerr << x" "std::cout << x" "std::clog << x" "std::printf(\"%d\", 1)"
  "printf(\"x\")" "std::fprintf(stderr, \"x\")" "fputs(\"x\", stdout)" "std::puts(\"x\")"
  "fputc('x', stderr)" "putchar('x')" "perror(\"x\")" "if (isatty(fileno(stderr)))"
  "std::print(\"{}\", 1)" "#include <iostream>" "write(STDERR_FILENO, p, n)")
set(_good
  "std::snprintf(buf, sizeof buf, \"%d\", 1)" "// std::cerr in a comment"
  "x = my_printf_like(1) // printf(" "std::ostringstream msg"
  "const char* stderr_name = nullptr" "#include <cstdio>"
  "std::fwrite(p, 1, n, file)" "std::fprintf(file, \"%d\", 1)" "fputc('x', out)")
list(LENGTH _bad _bad_count)
string(REPLACE ";" "\n" _text "${_bad}")
file(WRITE "${_scratch}/bad.cpp" "${_text}\n")
string(REPLACE ";" "\n" _text "${_good}")
file(WRITE "${_scratch}/good.cpp" "${_text}\n")
librt_find_printing("${_scratch}" "bad.cpp;good.cpp" _self)
file(REMOVE_RECURSE "${_scratch}")
string(REGEX MATCHALL "\n  bad.cpp:" _bad_hits "${_self}")
list(LENGTH _bad_hits _self_count)
if(_self MATCHES "good.cpp" OR NOT _self_count EQUAL _bad_count)
  message(FATAL_ERROR "self-check: expected the ${_bad_count} lines of bad.cpp and nothing "
                      "of good.cpp, found:${_self}")
endif()

# The library itself.
librt_library_files("${ROOT}" _files _file_count)
librt_find_printing("${ROOT}" "${_files}" _found)
set(_index 0)
foreach(entry IN LISTS _exemptions)
  if(NOT _used_${_index})
    message(STATUS "note: exemption '${entry}' matches no line any more: delete it")
  endif()
  math(EXPR _index "${_index} + 1")
endforeach()
if(_found)
  message(FATAL_ERROR "the library must not print (return warnings, the apps print them); "
                      "found in ${_file_count} files:${_found}")
endif()
message(STATUS "no printing in ${_file_count} library files")
