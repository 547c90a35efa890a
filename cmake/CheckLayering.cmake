# Script (cmake -P) behind the ctest style.layering: the areas of librt depend on each
# other in one direction only (docs/architecture.md), and the renderer reads no files.
#   1. A file of area A (librt/include/librt/A/ or librt/src/A/) includes librt headers
#      (<librt/B/...> or the private "B/...") only of the areas A may use:
#        core       <- core
#        geometry   <- core, geometry
#        sampling   <- core .. sampling
#        accel      <- core .. accel
#        material   <- core .. accel, material (textures, BSDFs)
#        light      <- core .. material, light (a triangle light's emission is a texture)
#        film       <- core .. light, film (cameras, films)
#        scene      <- core .. film, scene (the scene, its shading points, shadow rays)
#        integrator <- core .. scene, integrator
#        render     <- core .. integrator, render (the drivers: passes, tiles, AOVs)
#        io         <- all of the above and io (files and images; a loader may build
#                      any type of the renderer)
#        obj        <- core .. io, obj (OBJ and MTL)
#        gltf       <- core .. obj, gltf (glTF 2.0)
#        loader     <- core .. gltf, loader (a scene file of any format)
#        mpi        <- core .. render, mpi (the optional librt::mpi reads no files)
#      plus <librt/export.h> and <librt/version.h> everywhere.
#   2. The renderer's areas (material .. render) do no file I/O: no <fstream>,
#      <filesystem>, stb, fopen, std::ifstream / ofstream / fstream, std::filesystem.
#      Files are read and written in io/.
# Fails naming file:line. Comments (from // to the end of the line) are ignored.
#   ROOT: the repository root
# It first checks itself on a scratch tree, so a broken rule cannot pass silently.
cmake_minimum_required(VERSION 3.22)
include("${CMAKE_CURRENT_LIST_DIR}/LibrtSourceScan.cmake")
librt_require_root()

set(_areas core geometry sampling accel material light film scene integrator render io obj gltf
           loader mpi)
# Each area uses itself and the areas before it; mpi uses the renderer, not the loaders.
set(_before "")
foreach(_area IN LISTS _areas)
  list(APPEND _before ${_area})
  set(_uses_${_area} ${_before})
endforeach()
list(REMOVE_ITEM _uses_mpi io obj gltf loader)
# The renderer's areas (everything between accel and io) read and write no files.
set(_no_file_io material light film scene integrator render)
set(_file_io_patterns
  "#[ \t]*include[ \t]*<(fstream|filesystem|stb/[^>]*)>"
  "(^|[^A-Za-z0-9_])fopen[ \t]*\\("
  "std::(i|o)?fstream([^A-Za-z0-9_]|$)"
  "std::filesystem::")

# Sets out_var to one "\n  file:line: problem" per violation among `files` (paths relative
# to `root`, each under librt/include/librt/<area>/ or librt/src/<area>/).
function(librt_check_layering root files out_var)
  set(found "")
  foreach(rel IN LISTS files)
    if(NOT rel MATCHES "^librt/(include/librt|src)/([a-z_]+)/")
      continue()
    endif()
    set(area "${CMAKE_MATCH_2}")
    if(NOT area IN_LIST _areas)
      string(APPEND found "\n  ${rel}: area '${area}' is not in cmake/CheckLayering.cmake")
      continue()
    endif()
    set(allowed ${_uses_${area}})
    file(STRINGS "${root}/${rel}" lines)
    set(number 0)
    foreach(line IN LISTS lines)
      math(EXPR number "${number} + 1")
      librt_code_of_line("${line}" code)
      set(used "")
      if(code MATCHES "#[ \t]*include[ \t]*<librt/([a-z_]+)/")
        set(used "${CMAKE_MATCH_1}")
      elseif(code MATCHES "#[ \t]*include[ \t]*\"([a-z_]+)/")
        set(used "${CMAKE_MATCH_1}")
      endif()
      if(used AND NOT used IN_LIST allowed)
        string(STRIP "${line}" shown)
        string(APPEND found "\n  ${rel}:${number}: ${area}/ may not include ${used}/: ${shown}")
      endif()
      if(area IN_LIST _no_file_io)
        foreach(pattern IN LISTS _file_io_patterns)
          if(code MATCHES "${pattern}")
            string(STRIP "${line}" shown)
            string(APPEND found "\n  ${rel}:${number}: file I/O belongs in io/: ${shown}")
            break()
          endif()
        endforeach()
      endif()
    endforeach()
  endforeach()
  set(${out_var} "${found}" PARENT_SCOPE)
endfunction()

# Self-check on a scratch tree: each bad line must be reported once, no good line.
librt_scratch_folder(librt_layering_selftest _scratch)
file(MAKE_DIRECTORY "${_scratch}/librt/src/render" "${_scratch}/librt/include/librt/accel"
     "${_scratch}/librt/src/io")
file(WRITE "${_scratch}/librt/src/render/bad.cpp"
  "#include <librt/obj/obj.h>\n#include <fstream>\n#include <filesystem>\n"
  "#include <stb/stb_image.h>\nFILE* f = std::fopen(name, \"rb\")\nstd::ifstream in(p)\n"
  "auto s = std::filesystem::status(p)\n")
file(WRITE "${_scratch}/librt/include/librt/accel/bad.h"
  "#include <librt/scene/scene.h>\n#include \"obj/obj_scan.h\"\n")
file(WRITE "${_scratch}/librt/src/render/good.cpp"
  "#include <librt/accel/bvh.h>\n#include <librt/export.h>\n#include <sstream>\n"
  "// std::ifstream in a comment\nstd::ostringstream msg\nint my_fopen_count = 0\n")
file(WRITE "${_scratch}/librt/src/io/good.cpp"
  "#include <librt/scene/scene.h>\n#include <fstream>\n#include \"io/file_io.h\"\n")
librt_check_layering("${_scratch}"
  "librt/src/render/bad.cpp;librt/include/librt/accel/bad.h;librt/src/render/good.cpp;librt/src/io/good.cpp"
  _self)
file(REMOVE_RECURSE "${_scratch}")
string(REGEX MATCHALL "/bad\\.(cpp|h):" _bad_hits "${_self}")
list(LENGTH _bad_hits _bad_count)
if(_self MATCHES "good\\.cpp" OR NOT _bad_count EQUAL 9)
  message(FATAL_ERROR "self-check: expected the 9 bad lines and no good one, found:${_self}")
endif()

# ---- Confinement rules (issue 43) ---------------------------------------------------------
# 3. The renderer asks a material what it does through the BSDF kinds' answers
#    (src/material/bsdf_dispatch.h: lobes_of, transmits, near_specular, casts_caustics,
#    is_lambertian, multiply_color), never by naming its kind, so a new kind cannot be
#    forgotten by a switch outside material/. `MaterialKind::` (or `using enum
#    MaterialKind`) may appear only in material/ (the kinds and their dispatch) and the
#    loaders (io/, obj/, gltf/, loader/: they build materials).
# 4. Only light/ looks inside a Light's variant (LightSource): std::get_if / get /
#    holds_alternative of a ...Light kind, or a light's `.source` (what std::visit takes).
#    Everywhere else asks the Light functions of light/light.h (light_type, is_infinite,
#    surface_normal, preprocess, sample_li ...), so adding a light kind touches light/ and
#    the LightSource registration only. io/ builds lights through Scene's add_*_light and
#    needs no exception.
set(_material_kind_areas material io obj gltf loader)
set(_material_kind_patterns
  "(^|[^A-Za-z0-9_])MaterialKind[ \t]*::"
  "using[ \t]+enum[ \t]+(librt[ \t]*::[ \t]*)?MaterialKind([^A-Za-z0-9_]|$)")
set(_material_kind_problem
    "only material/ and the loaders name a MaterialKind (ask the BSDF, material/bsdf_dispatch.h)")
set(_light_variant_areas light)
set(_light_variant_patterns
  "(get_if|holds_alternative|get)[ \t]*<[ \t]*(librt::)?[A-Za-z0-9_]*Light[ \t]*>"
  "[Ll]ight[A-Za-z0-9_]*(\\([^)]*\\))?\\.source([^A-Za-z0-9_]|$)")
set(_light_variant_problem "light-variant access belongs in light/")

# Sets out_var to one "\n  file:line: problem: line" per line of `files` (paths relative to
# `root`) outside the areas `allowed` whose code (comments dropped) matches one of
# `patterns`.
function(librt_check_confined root files allowed patterns problem out_var)
  set(found "")
  foreach(rel IN LISTS files)
    if(NOT rel MATCHES "^librt/(include/librt|src)/([a-z_]+)/")
      continue()
    endif()
    if("${CMAKE_MATCH_2}" IN_LIST allowed)
      continue()
    endif()
    # One list element per line: ; and [ ] would split or join CMake list elements.
    file(READ "${root}/${rel}" content)
    string(REPLACE ";" "," content "${content}")
    string(REPLACE "[" "(" content "${content}")
    string(REPLACE "]" ")" content "${content}")
    string(REPLACE "\n" ";" lines "${content}")
    set(number 0)
    foreach(line IN LISTS lines)
      math(EXPR number "${number} + 1")
      librt_code_of_line("${line}" code)
      foreach(pattern IN LISTS patterns)
        if(code MATCHES "${pattern}")
          string(STRIP "${line}" shown)
          string(APPEND found "\n  ${rel}:${number}: ${problem}: ${shown}")
          break()
        endif()
      endforeach()
    endforeach()
  endforeach()
  set(${out_var} "${found}" PARENT_SCOPE)
endfunction()

# Self-checks on scratch trees: each bad line reported once, at its line number; no good
# line. librt_expect_bad_lines fails unless `found` reports exactly the `expected`
# "/bad.ext:line:" list, in order, and no good.* file.
function(librt_expect_bad_lines rule found expected)
  string(REGEX MATCHALL "/bad\\.(cpp|h):[0-9]+:" hits "${found}")
  if(found MATCHES "good\\.(cpp|h)" OR NOT hits STREQUAL "${expected}")
    message(FATAL_ERROR "${rule} self-check: expected exactly ${expected} and no good line, "
                        "found:${found}")
  endif()
endfunction()
librt_scratch_folder(librt_confined_selftest _confined_scratch)
file(MAKE_DIRECTORY "${_confined_scratch}/librt/src/integrator"
     "${_confined_scratch}/librt/src/material" "${_confined_scratch}/librt/src/light"
     "${_confined_scratch}/librt/src/scene" "${_confined_scratch}/librt/include/librt/io"
     "${_confined_scratch}/librt/include/librt/scene")
file(WRITE "${_confined_scratch}/librt/src/integrator/bad.cpp"
  "if (m.kind == MaterialKind::Diffuse) {\ncase librt::MaterialKind ::Mirror:\n"
  "using enum MaterialKind;\n")
file(WRITE "${_confined_scratch}/librt/include/librt/scene/bad.h"
  "return m.kind != MaterialKind::Emissive;\n")
file(WRITE "${_confined_scratch}/librt/src/integrator/good.cpp"
  "// MaterialKind::Diffuse in a comment\nif (bsdfs::is_lambertian(m)) {\n"
  "MyMaterialKind::Value v;\nMaterialKind kind = m.kind;\n")
file(WRITE "${_confined_scratch}/librt/src/material/good.h"
  "case MaterialKind::Mirror:\nstatic constexpr MaterialKind kKind = MaterialKind::Mirror;\n")
file(WRITE "${_confined_scratch}/librt/include/librt/io/good.h"
  "m.kind = MaterialKind::MetallicRoughness;\n")
librt_check_confined("${_confined_scratch}"
  "librt/src/integrator/bad.cpp;librt/include/librt/scene/bad.h;librt/src/integrator/good.cpp;librt/src/material/good.h;librt/include/librt/io/good.h"
  "${_material_kind_areas}" "${_material_kind_patterns}" "MaterialKind" _kind_self)
file(WRITE "${_confined_scratch}/librt/src/scene/bad.cpp"
  "int a = 0;\n"
  "if (auto* e = std::get_if<EnvironmentLight>(&lights_[i].source)) e->r = 1;\n"
  "bool p = std::holds_alternative<PointLight>(l.light.source);\n"
  "const auto& s = std::get<librt::SphereLight>(light.source);\n"
  "    return std::visit([&](const auto& s) { return s.type(); },\n"
  "                      light.source);\n")
file(WRITE "${_confined_scratch}/librt/src/scene/good.cpp"
  "const std::uint32_t image = texture.source;  // std::get_if<PointLight>(&light.source)\n"
  "LightType t = light_type(light);\nauto v = std::get_if<int>(&x);\n")
file(WRITE "${_confined_scratch}/librt/src/light/good.cpp"
  "auto* s = std::get_if<SphereLight>(&light.source);\n")
librt_check_confined("${_confined_scratch}"
  "librt/src/scene/bad.cpp;librt/src/scene/good.cpp;librt/src/light/good.cpp"
  "${_light_variant_areas}" "${_light_variant_patterns}" "light variant" _light_self)
file(REMOVE_RECURSE "${_confined_scratch}")
# Judged after the scratch tree is gone, so a failing self-check leaves nothing behind.
librt_expect_bad_lines("MaterialKind" "${_kind_self}"
                       "/bad.cpp:1:;/bad.cpp:2:;/bad.cpp:3:;/bad.h:1:")
librt_expect_bad_lines("light-variant" "${_light_self}"
                       "/bad.cpp:2:;/bad.cpp:3:;/bad.cpp:4:;/bad.cpp:6:")

librt_library_files("${ROOT}" _files _file_count)
librt_check_layering("${ROOT}" "${_files}" _found)
librt_check_confined("${ROOT}" "${_files}" "${_material_kind_areas}" "${_material_kind_patterns}"
                     "${_material_kind_problem}" _kind_found)
librt_check_confined("${ROOT}" "${_files}" "${_light_variant_areas}" "${_light_variant_patterns}"
                     "${_light_variant_problem}" _light_found)
string(APPEND _found "${_kind_found}${_light_found}")
if(_found)
  message(FATAL_ERROR "layering broken (see docs/architecture.md):${_found}")
endif()
message(STATUS "layering holds in ${_file_count} library files")
