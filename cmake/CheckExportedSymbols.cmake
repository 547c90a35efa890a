# Script (cmake -P) behind the `visibility.exported_symbols` test of a shared librt: lists
# the dynamic symbols the library defines (nm -D --defined-only, demangled) and fails when
#   (a) a symbol of the public API is missing (a LIBRT_API lost on the way), or
#   (b) a symbol names something that must stay private: a nested namespace of librt
#       (librt::detail::, librt::teapot_data::, ... unless listed in `allowed` below), an
#       anonymous namespace, or a private dependency (tinyobj, tinygltf, nlohmann-json, stb).
# Registered by tests/CMakeLists.txt only when librt is a shared library.
#   LIBRARY: the shared library (e.g. $<TARGET_FILE:librt>)
#   NM:      the nm program (CMAKE_NM; plain "nm" if empty)
cmake_minimum_required(VERSION 3.22)

if(NOT LIBRARY OR NOT EXISTS "${LIBRARY}")
  message(FATAL_ERROR "LIBRARY='${LIBRARY}' does not exist")
endif()
if(NOT NM)
  set(NM nm)
endif()

# (a) One demangled symbol per line of the public API, matched as the start of a symbol:
# a class member, free functions from several headers, an exception's typeinfo (so that
# catch (const librt::Error&) works across the library boundary) and integrator vtables.
set(required
  "librt::Scene::add_sphere("
  "librt::Scene::commit()"
  "librt::TopLevel::intersect("
  "librt::TopLevel::occluded("
  "librt::render_progressive("
  "librt::render_block("
  "librt::write_exr("
  "librt::Camera::Camera("
  "librt::TriangleBvh::TriangleBvh("
  "librt::load_obj("
  "librt::load_gltf("
  "librt::save_obj("
  "librt::render("
  "librt::make_teapot("
  "librt::write_image("
  "librt::library_version_string()"
  "librt::GuardedIntegrator::guard("
  "typeinfo for librt::Error"
  "typeinfo for librt::Integrator"
  "vtable for librt::PathTracer")

# (b) Private names, as regular expressions matched anywhere in a symbol...
set(forbidden
  "librt::[a-z_][a-z0-9_]*::"   # a namespace nested in librt (classes are CamelCase)
  "\\(anonymous namespace\\)"
  "tinyobj::"
  "tinygltf::"
  "nlohmann::"
  "(^| |::)stbi")
# ...except these symbols (matched as the start of a symbol), exported on purpose: none
# since the large-page allocator became private (librt/src/core).
set(allowed)

execute_process(COMMAND "${NM}" -D --defined-only -C "${LIBRARY}"
  RESULT_VARIABLE rc OUTPUT_VARIABLE nm_output ERROR_VARIABLE nm_error)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${NM} -D --defined-only -C ${LIBRARY} failed (${rc}): ${nm_error}")
endif()

# Demangled names may hold ';', '[' and ']', which CMake lists treat specially: swap them
# for placeholders while the output is a list, and back when printing.
string(REPLACE ";" "<semicolon>" nm_output "${nm_output}")
string(REPLACE "[" "<lbracket>" nm_output "${nm_output}")
string(REPLACE "]" "<rbracket>" nm_output "${nm_output}")
string(REPLACE "\n" ";" lines "${nm_output}")
set(symbols)
foreach(line IN LISTS lines)
  # "<address> <type> <name>"; the name itself may contain spaces.
  if(line MATCHES "^[0-9a-fA-F]* *[A-Za-z] (.+)$")
    list(APPEND symbols "${CMAKE_MATCH_1}")
  endif()
endforeach()
list(LENGTH symbols count)
if(count EQUAL 0)
  message(FATAL_ERROR "${LIBRARY} exports no symbols: is it a shared library?")
endif()

function(restore out text)
  string(REPLACE "<semicolon>" ";" text "${text}")
  string(REPLACE "<lbracket>" "[" text "${text}")
  string(REPLACE "<rbracket>" "]" text "${text}")
  set(${out} "${text}" PARENT_SCOPE)
endfunction()

function(starts_with_any out symbol)
  foreach(prefix IN LISTS ARGN)
    string(FIND "${symbol}" "${prefix}" at)
    if(at EQUAL 0)
      set(${out} TRUE PARENT_SCOPE)
      return()
    endif()
  endforeach()
  set(${out} FALSE PARENT_SCOPE)
endfunction()

set(missing)
foreach(name IN LISTS required)
  set(found FALSE)
  foreach(symbol IN LISTS symbols)
    string(FIND "${symbol}" "${name}" at)
    if(at EQUAL 0)
      set(found TRUE)
      break()
    endif()
  endforeach()
  if(NOT found)
    list(APPEND missing "${name}")
  endif()
endforeach()

set(leaked)
foreach(symbol IN LISTS symbols)
  starts_with_any(is_allowed "${symbol}" ${allowed})
  if(is_allowed)
    continue()
  endif()
  foreach(pattern IN LISTS forbidden)
    if(symbol MATCHES "${pattern}")
      list(APPEND leaked "${symbol}")
      break()
    endif()
  endforeach()
endforeach()

set(report "")
if(missing)
  string(APPEND report "Public symbols missing from ${LIBRARY} (LIBRT_API lost?):\n")
  foreach(name IN LISTS missing)
    string(APPEND report "  ${name}...\n")
  endforeach()
endif()
if(leaked)
  string(APPEND report "Private symbols exported by ${LIBRARY} (hidden by default: drop "
                       "their LIBRT_API, or allow them in cmake/CheckExportedSymbols.cmake):\n")
  foreach(symbol IN LISTS leaked)
    restore(symbol "${symbol}")
    string(APPEND report "  ${symbol}\n")
  endforeach()
endif()
if(report)
  message(FATAL_ERROR "${report}")
endif()
message(STATUS "${LIBRARY}: ${count} exported symbols, public API present, nothing private")
