#pragma once

#include <librt/export.h>
#include <librt/geometry/mesh.h>
#include <librt/io/file_digest.h>

#include <glm/mat4x4.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace librt {

/// How load_obj reads a file.
struct ObjLoadOptions {
    glm::mat4 transform{1.0f};  ///< applied on load, as librt::transform (e.g. make_transform)
    bool load_normals = true;   ///< read vn; if false the mesh has no normals
    bool load_uvs = true;       ///< read vt; if false the mesh has no uvs
    /// Where warnings go (a missing MTL, an unknown material, skipped faces, replaced MTL
    /// values), one line each, prefixed by the file name (and the line): appended when
    /// given; when null the caller does not want them and they are dropped. librt never
    /// prints: an application prints the list itself (the apps do).
    std::vector<std::string>* warnings = nullptr;
    /// Where the files read go, with the digest of their bytes (taken from memory, not read
    /// again): the OBJ (its path as given), then each MTL file found (the OBJ's directory /
    /// its name), appended when given. map_Kd images are read later, by add_mesh_with_mtl.
    std::vector<FileRead>* files_read = nullptr;
    /// Files larger than this are refused (librt::Error naming the size and this option)
    /// before a byte is read; 2 GiB by default. The mesh built from an OBJ takes about as
    /// much memory again as the file, so raise it only with memory to match.
    std::uint64_t max_file_bytes = std::uint64_t{1} << 31;
    /// Read MTL files and map_Kd textures outside the OBJ's directory tree (absolute
    /// paths, "..", symlinks that lead out). Off: such a name is a librt::Error, so an OBJ
    /// downloaded from anywhere reads only the files that came with it.
    bool allow_outside_files = false;
};

/// Reads a Wavefront OBJ (and its MTL, looked up in the OBJ's directory) into one mesh.
///
/// - All groups and objects are merged. OBJ's separate (v, vt, vn) indices are unified into
///   single vertices: vertex i is OBJ position i, with the first (vt, vn) pair a face uses it
///   with; each further distinct pair adds a vertex after the OBJ's positions (deduplicated
///   with a hash map). So a positions-only file keeps its vertices and their order, unused
///   ones included.
/// - Triangles keep their corners as written, degenerate ones too. Polygons are triangulated
///   by ear clipping in their plane; polygons of zero area (which triangulate to nothing) are
///   skipped with a warning. Points and lines are ignored.
/// - uvs are present when any face corner has a vt (others get (0, 0)); normals when any has
///   a vn (others get the area-weighted normal of their faces, or zero for unused vertices).
/// - material_ids is always filled. materials holds the MTL's materials in file order; if any
///   face has no (known) material, a default MeshMaterial named "default" is appended and those
///   faces use it. map_Kd is resolved against the OBJ's directory.
/// - Only regular files are read (the OBJ and its MTL files): a directory,
///   FIFO, device or socket is refused with librt::Error naming the path and what it is, as
///   is a missing or unreadable file or one above options.max_file_bytes (MTL: 256 MiB).
/// - Before tinyobjloader parses it (which would read "v 1 abc 2" as (1, 0, 2) and "nan" as
///   0), a strict pass checks every v / vt / vn / f statement and throws librt::Error
///   "path:line: problem" (face N counted from 1 in file order, not counting faces of under
///   3 corners) for: a NUL byte (binary or UTF-16 text), a UTF-16 byte order mark, a wrong
///   count of numbers, a number that is malformed or not finite in float, a malformed face
///   corner, an index 0, an index beyond the int range, a relative index before the first
///   element, an absolute index beyond the file's count, a face of more than 255 corners.
///   vt / vn indices are range-checked only when uvs / normals are loaded.
/// - Warnings, not errors (one each, with the first line): faces of fewer than 3 corners
///   (dropped), lines and points (ignored), unknown statements (ignored), no faces at all
///   (an empty mesh). A UTF-8 byte order mark is skipped. Lines may end in LF, CRLF or CR,
///   the last one with or without a newline, and be of any length.
/// - A missing MTL file is a warning, not an error: the faces get the default material.
///   MTL files are read by librt itself (obj/obj_mtl.h): numbers as strictly as the OBJ's
///   ("path:line: problem"); material names, in newmtl and usemtl alike, are the whole rest
///   of the line, spaces included; map_Kd options are skipped and backslashes in its path
///   become slashes; values replaced (d outside [0, 1], a transparent material's Ni <= 0)
///   are warned about. A usemtl naming no MTL material is warned about once, with its line.
/// - Trailing comments (`f 1 2 3 # note`) are allowed on every statement.
[[nodiscard]] LIBRT_API TriangleMesh load_obj(const std::filesystem::path& path,
                                              const ObjLoadOptions& options = {});

/// Writes a mesh as OBJ (v, vt, vn, f with 1-based v/vt/vn triplets, exact float round trip),
/// plus an MTL named after it (same stem, ".mtl") when the mesh has materials. Each file is
/// written to a temporary name beside it and renamed, so readers never see half a file.
/// Throws librt::Error naming the path when the mesh is invalid or a file cannot be written.
LIBRT_API void save_obj(const TriangleMesh& mesh, const std::filesystem::path& path);

}  // namespace librt
