#pragma once

// librt's own MTL reader (tinyobjloader's is not used). It reads the statements librt
// maps to materials with the same strictness as the OBJ scan: every number of Ka, Kd, Ks,
// Ke, Tf, Ni, Ns, d, Tr and illum must parse completely and be finite in float, or the
// file is refused with "path:line: problem". Material names are the whole rest of the
// newmtl line (spaces included), as usemtl names are. map_Kd's options (-s, -o, -bm...)
// are skipped and its path, which may contain spaces, has Windows backslashes turned into
// slashes. Values that cannot be used as given are replaced, with a warning naming the
// line: d or Tr outside [0, 1] (clamped), a dielectric's Ni <= 0 (1.5).

#include <librt/geometry/mesh.h>

#include <string>
#include <string_view>
#include <vector>

namespace librt::detail {

/// Parses the MTL text of the file `name`, appending its materials (in file order, unnamed
/// ones dropped) to `materials`. map_Kd paths are returned as written (separators
/// normalised), not resolved. Warnings, "name:line: what", go to `warnings`.
void parse_mtl(std::string_view text, const std::string& name, std::vector<MeshMaterial>& materials,
               std::vector<std::string>& warnings);

/// A path as written in an OBJ or MTL file, with Windows backslashes as slashes (OBJ files
/// from Windows tools say `.\tex\wood.jpg`; a backslash is never part of a sane name).
[[nodiscard]] std::string normalise_separators(std::string_view path);

}  // namespace librt::detail
