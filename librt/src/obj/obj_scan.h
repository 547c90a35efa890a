#pragma once

// A strict first pass over an OBJ file's text, run before tinyobjloader parses it.
//
// tinyobjloader is lenient in ways that hide broken files: "v 1 abc 2" reads as (1, 0, 2),
// "v nan 0 0" as (0, 0, 0), "f 1 2 3.5" as (1, 2, 3), an index too large for an int wraps,
// a UTF-8 byte order mark swallows the first vertex, and its messages rarely name the line.
// This pass checks exactly the statements whose silent misreading would change the mesh
// (v, vt, vn, f) and reports the first problem as "path:line: what". Everything it cannot
// misread (groups, smoothing, materials, curves) is left to tinyobjloader.

#include <cstddef>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace librt::detail {

/// How a number token of an OBJ or MTL file reads as a float.
enum class NumberStatus {
    Ok,         ///< parsed completely and finite in float (a value below float's range is 0)
    Malformed,  ///< not a number, or trailing characters
    TooLarge,   ///< NaN, infinity, or beyond float's range
};

/// Parses one number token the way both the OBJ scan and the MTL reader accept them:
/// std::from_chars syntax plus a leading '+'; `1e-400` (below even double's range) reads
/// as 0, like `1e-50` (below float's): an underflow loses nothing a float could hold.
[[nodiscard]] NumberStatus parse_float(std::string_view token, float& value);

/// One `usemtl` switch: faces from `first_face` on (counted like load_obj's faces: from 0
/// in file order, faces of fewer than 3 corners not counted) use material `name`.
struct MaterialRun {
    std::size_t first_face;  ///< index of the first face using it
    std::size_t name;        ///< index into ObjScanResult::material_names
};

/// What the scan of an OBJ file found that is worth telling but not fatal.
struct ObjScanResult {
    /// Warnings, each "line N: ..." (load_obj prefixes the path).
    std::vector<std::string> warnings;
    /// Bytes to skip at the start of the text (a UTF-8 byte order mark), 0 or 3.
    std::size_t skip = 0;
    /// Offsets of trailing comments ("# ...") after v / vt / vn / f data: load_obj blanks
    /// them, so tinyobjloader (which fails on `f 1 2 3 # c`) sees what the scan accepted.
    std::vector<std::size_t> trailing_comments;
    /// mtllib statements: the rest of the line (trimmed) and its line number.
    std::vector<std::pair<std::string, std::size_t>> mtllibs;
    /// usemtl names (the whole rest of the line, trimmed: names may contain spaces), each
    /// once, with the line of its first use.
    std::vector<std::pair<std::string, std::size_t>> material_names;
    /// The usemtl switches in file order.
    std::vector<MaterialRun> material_runs;
    /// Faces of 3 or more corners.
    std::size_t face_count = 0;
};

/// Checks the first bytes of an OBJ file before the rest is read (a UTF-16 byte order mark,
/// a NUL byte), throwing librt::Error "name:line: problem" as scan_obj would: a binary or
/// huge sparse file is refused after 64 KiB, not after reading gigabytes.
void check_obj_head(std::string_view head, const std::string& name);

/// What the scan needs to know besides the text.
struct ObjScanOptions {
    bool check_uv_indices = true;      ///< range-check vt indices (off when uvs are not loaded)
    bool check_normal_indices = true;  ///< range-check vn indices (off when normals are not loaded)
};

/// Scans `text`, the whole OBJ file named `name`. Throws librt::Error
/// "name:line: problem" for the first of:
/// - a NUL byte (a binary file, or UTF-16 text: a UTF-16 byte order mark is named as such);
/// - a v / vt / vn statement with the wrong count of numbers (v: 3 to 7, vt: 1 to 3,
///   vn: 3), or a number that does not parse completely or is not finite in float;
/// - a face corner that is not v, v/vt, v//vn or v/vt/vn with integer fields, an index 0,
///   an index beyond the int range, a relative (negative) index reaching before the first
///   element, an absolute index beyond the file's element count, or a face of more than
///   255 corners (tinyobjloader counts corners in a byte).
/// Warns about faces of fewer than 3 corners, lines and points (l, p: ignored) and
/// statements it does not know (counted, the first named).
[[nodiscard]] ObjScanResult scan_obj(std::string_view text, const std::string& name,
                                     const ObjScanOptions& options = {});

}  // namespace librt::detail
