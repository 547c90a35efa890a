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
#include <vector>

namespace librt::detail {

/// What the scan of an OBJ file found that is worth telling but not fatal.
struct ObjScanResult {
    /// Warnings, each "line N: ..." (load_obj prefixes the path).
    std::vector<std::string> warnings;
    /// Bytes to skip at the start of the text (a UTF-8 byte order mark), 0 or 3.
    std::size_t skip = 0;
};

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
